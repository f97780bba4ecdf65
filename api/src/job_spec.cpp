#include "oer/api/job_spec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <variant>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/error.hpp"

namespace oer::api {

namespace {

using Json = nlohmann::json;

// The render request's parser names members from the request's root; within a job they sit
// under `prefix`, so its failures are named again from the job's root.
RenderSpec parse_render_at(const Json& member, const std::string& prefix,
                           const RenderLimits& limits) {
    try {
        return parse_render_json(member.dump(), limits);
    } catch (const InvalidParameter& invalid) {
        throw invalid.nested_in(prefix);
    } catch (const MalformedRequest&) {
        throw;
    } catch (const Error& error) {
        // A render over its own limits (too many values): the job's member that holds it.
        throw InvalidParameter(prefix, error.what(), error.kind());
    }
}

const Json& required(const Json& object, const std::string& name, const std::string& path) {
    const auto member = object.find(name);
    if (member == object.end()) {
        throw InvalidParameter(path + name, "required");
    }
    return *member;
}

void check_members(const Json& object, const std::string& path,
                   std::initializer_list<std::string_view> known) {
    if (!object.is_object()) {
        throw InvalidParameter(path.empty() ? "body" : path.substr(0, path.size() - 1),
                               "expected an object");
    }
    for (const auto& [name, value] : object.items()) {
        if (std::find(known.begin(), known.end(), name) == known.end()) {
            throw InvalidParameter(path + excerpt(name), "unknown member");
        }
    }
}

std::size_t count_in(const Json& value, const std::string& path, std::size_t low,
                     std::size_t high) {
    if (!value.is_number_integer() || value.get<std::int64_t>() < std::int64_t(low) ||
        value.get<std::int64_t>() > std::int64_t(high)) {
        throw InvalidParameter(
            path, "expected an integer " + std::to_string(low) + ".." + std::to_string(high));
    }
    return std::size_t(value.get<std::int64_t>());
}

const Json& array_of_up_to(const Json& value, const std::string& path, std::size_t most) {
    if (!value.is_array() || value.empty() || value.size() > most) {
        throw InvalidParameter(path,
                               "expected an array of 1 to " + std::to_string(most) + " entries");
    }
    return value;
}

std::string string_at(const Json& value, const std::string& path) {
    if (!value.is_string() || value.get<std::string>().empty()) {
        throw InvalidParameter(path, "expected a non-empty string");
    }
    return value.get<std::string>();
}

// A name part made of frame-name characters only, so that a variant called "Deep Red" names
// the sequence "Deep_Red".
std::string name_part(const std::string& text) {
    std::string part = text.substr(0, 40);
    for (char& c : part) {
        if (!is_frame_name(std::string_view(&c, 1))) {
            c = '_';
        }
    }
    return part;
}

struct Size {
    int width = 0;
    int height = 0;
};

std::vector<Size> sizes_at(const Json& value, const std::string& path, const RenderLimits& limits,
                           std::size_t most) {
    std::vector<Size> sizes;
    for (std::size_t i = 0; i < array_of_up_to(value, path, most).size(); ++i) {
        const std::string at = path + "/" + std::to_string(i) + "/";
        check_members(value[i], at, {"width", "height"});
        sizes.push_back(
            {int(count_in(required(value[i], "width", at), at + "width", 1, limits.max_width)),
             int(count_in(required(value[i], "height", at), at + "height", 1, limits.max_height))});
    }
    return sizes;
}

void add_frame(JobSpec& job, std::set<std::string>& names, JobFrame frame, const std::string& path,
               const JobLimits& limits) {
    if (job.frames.size() >= limits.max_frames) {
        throw InvalidParameter(path,
                               "the job has more than " + std::to_string(limits.max_frames) +
                                   " frames, the most one job may have",
                               ErrorKind::LimitExceeded);
    }
    if (!names.insert(frame.name).second) {
        throw InvalidParameter(path, "two frames are named '" + frame.name + "'");
    }
    job.frames.push_back(std::move(frame));
}

JobSpec frames_job(const Json& frames, const RenderLimits& render_limits, const JobLimits& limits) {
    if (!frames.is_array() || frames.empty()) {
        throw InvalidParameter("frames", "expected a non-empty array of frames");
    }
    JobSpec job;
    std::set<std::string> names;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const std::string at = "frames/" + std::to_string(i) + "/";
        check_members(frames[i], at, {"name", "render"});
        JobFrame frame;
        frame.name = string_at(required(frames[i], "name", at), at + "name");
        if (!is_frame_name(frame.name)) {
            throw InvalidParameter(at + "name", "expected 1 to " +
                                                    std::to_string(kMaxFrameNameLength) +
                                                    " of the characters A-Z a-z 0-9 . _ -");
        }
        frame.spec =
            parse_render_at(required(frames[i], "render", at), at + "render", render_limits);
        add_frame(job, names, std::move(frame), at + "name", limits);
    }
    return job;
}

JobSpec turntable_job(const Json& turntable, const RenderLimits& render_limits,
                      const JobLimits& limits) {
    const std::string at = "turntable/";
    check_members(turntable, at, {"render", "views", "variants", "environments", "sizes"});
    const RenderSpec base =
        parse_render_at(required(turntable, "render", at), at + "render", render_limits);
    OrbitSpec orbit;
    if (base.camera) {
        const auto* given = std::get_if<OrbitSpec>(&base.camera->placement);
        if (!given) {
            throw InvalidParameter(at + "render/camera",
                                   "a turntable turns an orbit camera; give camera.orbit or none");
        }
        orbit = *given;
    }
    // Any count is read; one over the job's limit is refused as such (413) by add_frame.
    const std::size_t views =
        count_in(required(turntable, "views", at), at + "views", 1, std::size_t(1) << 30);

    // Each axis the job varies, with the part it adds to the sequence's name; an axis not given
    // is the base request's, and adds nothing.
    std::vector<std::optional<std::string>> variants{std::nullopt};
    if (const auto given = turntable.find("variants"); given != turntable.end()) {
        if (base.objects.empty()) {
            throw InvalidParameter(at + "variants", "the turntable's render has no objects");
        }
        variants.clear();
        for (std::size_t i = 0; i < array_of_up_to(*given, at + "variants", 64).size(); ++i) {
            variants.push_back(string_at((*given)[i], at + "variants/" + std::to_string(i)));
        }
    }
    std::vector<std::optional<std::string>> environments{std::nullopt};
    if (const auto given = turntable.find("environments"); given != turntable.end()) {
        environments.clear();
        for (std::size_t i = 0; i < array_of_up_to(*given, at + "environments", 64).size(); ++i) {
            environments.push_back(
                string_at((*given)[i], at + "environments/" + std::to_string(i)));
        }
    }
    std::vector<std::optional<Size>> sizes{std::nullopt};
    if (const auto given = turntable.find("sizes"); given != turntable.end()) {
        sizes.clear();
        for (const Size& size : sizes_at(*given, at + "sizes", render_limits, 16)) {
            sizes.push_back(size);
        }
    }

    JobSpec job;
    std::set<std::string> names;
    std::set<std::string> sequence_names;
    for (const auto& variant : variants) {
        for (const auto& environment : environments) {
            for (const auto& size : sizes) {
                JobSequence sequence;
                std::vector<std::string> parts;
                if (variant) {
                    parts.push_back(name_part(*variant));
                }
                if (environment) {
                    parts.push_back(name_part(environment->substr(0, 12)));
                }
                if (size) {
                    parts.push_back(std::to_string(size->width) + "x" +
                                    std::to_string(size->height));
                }
                for (const std::string& part : parts) {
                    sequence.name += (sequence.name.empty() ? "" : "-") + part;
                }
                if (sequence.name.empty()) {
                    sequence.name = "turntable";
                }
                if (!sequence_names.insert(sequence.name).second) {
                    throw InvalidParameter(
                        at + (variant ? "variants" : "environments"),
                        "two entries give the same sequence name '" + sequence.name + "'");
                }
                for (std::size_t view = 0; view < views; ++view) {
                    JobFrame frame;
                    char index[24];
                    std::snprintf(index, sizeof index, "%03zu", view);
                    frame.name = sequence.name + "-" + index;
                    frame.spec = base;
                    for (ObjectSpec& object : frame.spec.objects) {
                        if (variant) {
                            object.variant = *variant;
                        }
                    }
                    if (environment) {
                        frame.spec.environment = *environment;
                    }
                    if (size) {
                        frame.spec.width = size->width;
                        frame.spec.height = size->height;
                    }
                    // Evenly around the orbit from the base request's own yaw, within the
                    // parser's range (degrees, -360..360).
                    OrbitSpec turned = orbit;
                    turned.yaw = std::fmod(orbit.yaw + 360.0 * double(view) / double(views), 360.0);
                    frame.spec.camera =
                        CameraSpec{turned, base.camera ? base.camera->fov_y : CameraSpec{}.fov_y};
                    sequence.frames.push_back(frame.name);
                    add_frame(job, names, std::move(frame), at + "views", limits);
                }
                job.sequences.push_back(std::move(sequence));
            }
        }
    }
    return job;
}

void check_pixels(const JobSpec& job, const JobLimits& limits) {
    const std::uint64_t pixels = job_pixels(job);
    if (pixels > limits.max_pixels) {
        throw InvalidParameter("body",
                               "the job's frames hold " + std::to_string(pixels) +
                                   " pixels, over the " + std::to_string(limits.max_pixels) +
                                   " one job may have",
                               ErrorKind::LimitExceeded);
    }
}

}  // namespace

bool is_frame_name(std::string_view name) {
    return !name.empty() && name.size() <= kMaxFrameNameLength &&
           std::all_of(name.begin(), name.end(),
                       [](char c) {
                           return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                  (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
                       }) &&
           name.front() != '.';
}

std::uint64_t job_pixels(const JobSpec& job) {
    std::uint64_t pixels = 0;
    for (const JobFrame& frame : job.frames) {
        pixels += std::uint64_t(frame.spec.width) * std::uint64_t(frame.spec.height);
    }
    return pixels;
}

JobSpec parse_job_json(std::string_view body, const RenderLimits& render_limits,
                       const JobLimits& limits) {
    if (body.size() > limits.max_body_bytes) {
        throw Error(ErrorKind::LimitExceeded, "job: the body has " + std::to_string(body.size()) +
                                                  " bytes, over the limit of " +
                                                  std::to_string(limits.max_body_bytes));
    }
    Json document;
    try {
        // Every value takes at least two bytes of text (itself and a separator), so a body
        // within the byte limit holds at most half as many values.
        document = checked_json::parse_bounded(body, {limits.max_body_bytes / 2, 24});
    } catch (const checked_json::JsonParseError& error) {
        throw MalformedRequest(error.what());
    }
    check_members(document, "", {"frames", "turntable"});
    const bool listed = document.contains("frames");
    if (listed == document.contains("turntable")) {
        throw InvalidParameter("body", "give either frames or turntable");
    }
    JobSpec job = listed ? frames_job(document["frames"], render_limits, limits)
                         : turntable_job(document["turntable"], render_limits, limits);
    check_pixels(job, limits);
    return job;
}

nlohmann::json stored_job_json(const JobSpec& job) {
    Json frames = Json::array();
    for (const JobFrame& frame : job.frames) {
        frames.push_back({{"name", frame.name}, {"render", normalised_render_json(frame.spec)}});
    }
    Json sequences = Json::array();
    for (const JobSequence& sequence : job.sequences) {
        sequences.push_back({{"name", sequence.name}, {"frames", sequence.frames}});
    }
    return {{"frames", frames}, {"sequences", sequences}};
}

JobSpec job_from_stored_json(const nlohmann::json& stored, const RenderLimits& render_limits) {
    JobSpec job;
    for (const Json& frame : stored.at("frames")) {
        job.frames.push_back({frame.at("name").get<std::string>(),
                              parse_render_json(frame.at("render").dump(), render_limits)});
    }
    for (const Json& sequence : stored.at("sequences")) {
        job.sequences.push_back({sequence.at("name").get<std::string>(),
                                 sequence.at("frames").get<std::vector<std::string>>()});
    }
    return job;
}

}  // namespace oer::api
