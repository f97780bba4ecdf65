// POST and GET /v1/jobs, GET and DELETE /v1/jobs/{id}, GET /v1/jobs/{id}/events
// (server-sent events), GET /v1/jobs/{id}/frames/{name}, GET /v1/jobs/{id}/zip,
// GET /v1/jobs/{id}/sequences/{name} (job_service.hpp, docs/jobs.md)
#include <charconv>
#include <cmath>
#include <memory>
#include <string>

#include "event_stream.hpp"
#include "http_exchange.hpp"
#include "oer/api/frame_encoding.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/image/image_encoding.hpp"
#include "service_context.hpp"
#include "spin_set.hpp"
#include "zip_archive.hpp"

namespace oer::server {

namespace {

// A job's answers change as it runs: never kept by a cache.
constexpr const char* kNoStore = "no-store";
// The most jobs a page of GET /v1/jobs lists: each entry is a status read from the store (its
// frames' and failures' folders listed, each failure read), not one file's size as an asset
// listing's entry is.
constexpr std::size_t kMaxJobsListed = 100;
// How often an event stream looks at its job when nothing here signals a change (another
// replica renders its frames).
constexpr std::chrono::milliseconds kEventPoll{500};

std::string job_path(const std::string& id) {
    return "/v1/jobs/" + id;
}

nlohmann::json job_status(ServiceContext& context, const std::string& id, bool with_frames) {
    auto status = context.jobs.status(id, with_frames);
    if (!status) {
        throw not_found(ProblemKind::UnknownId, "no job with id '" + api::excerpt(id) + "'");
    }
    return *status;
}

bool settled(const nlohmann::json& status) {
    return is_settled_state(status.at("state").get<std::string>());
}

// A finished job's whole results; 503 with Retry-After while frames are still to come.
void require_settled(const nlohmann::json& status) {
    if (!settled(status)) {
        throw unavailable("the job has " +
                              std::to_string(status.at("total").get<std::size_t>() -
                                             status.at("done").get<std::size_t>()) +
                              " frames still to render",
                          std::max(1, int(status.at("seconds_left").is_number()
                                              ? status.at("seconds_left").get<double>()
                                              : 1.0)));
    }
}

// The most pixels a sprite sheet (every view of a sequence) may hold: the decoders' own limit,
// so that any sheet served can be read back.
constexpr std::uint64_t kMaxSpinSetPixels = 64ull << 20;

int integer_parameter(const std::map<std::string, std::string>& query, const std::string& name,
                      int fallback, int low, int high) {
    const auto given = query.find(name);
    if (given == query.end()) {
        return fallback;
    }
    int value = 0;
    const std::string& text = given->second;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || value < low || value > high) {
        throw api::InvalidParameter(
            name, "expected an integer " + std::to_string(low) + ".." + std::to_string(high));
    }
    return value;
}

}  // namespace

void add_job_routes(Router& router, ServiceContext& context) {
    router.post(
        "/v1/jobs",
        RoutePolicy{.needs_api_key = true, .max_body = context.jobs.bounds().job.max_body_bytes},
        [](const httplib::Request& request, httplib::Response&) {
            if (const std::string type = media_type(request); type != "application/json") {
                throw HttpError(
                    problem(ProblemKind::UnsupportedMediaType,
                            "a job is application/json, not '" + api::excerpt(type) + "'"));
            }
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            single_query(request, {});
            const api::JobSpec spec =
                api::parse_job_json(body, context.render_limits, context.jobs.bounds().job);
            const std::string id = context.jobs.submit(spec, request.remote_addr);
            response.set_header("Location", job_path(id));
            response.set_header("Cache-Control", kNoStore);
            send_json(response, 202, job_status(context, id, false));
        });

    // The requesting client's jobs only, as the per-client bounds count them (by address): a
    // job's id is what lets anyone read or follow it, so a listing of every client's jobs would
    // hand them out. With an API key, the key too, as for making and cancelling jobs.
    router.get(
        "/v1/jobs",
        [&context](const httplib::Request& request, httplib::Response& response) {
            const ListingQuery query = listing_query(
                request, {is_job_id, "32 lowercase hexadecimal digits", kMaxJobsListed});
            const auto page = context.jobs.list(request.remote_addr, query.after, query.limit);
            if (!page) {
                throw api::InvalidParameter("after",
                                            "no job of this client's has id '" + query.after +
                                                "' (removed since the previous page was read?)");
            }
            nlohmann::json entries = nlohmann::json::array();
            for (nlohmann::json entry : page->jobs) {
                entry["url"] = job_path(entry.at("id"));
                entry["created"] = rfc3339(std::chrono::system_clock::time_point(
                    std::chrono::duration_cast<std::chrono::system_clock::duration>(
                        std::chrono::duration<double>(entry.at("created").get<double>()))));
                entries.push_back(std::move(entry));
            }
            response.set_header("Cache-Control", kNoStore);
            send_listing(response, "/v1/jobs", "jobs", std::move(entries), page->next_after,
                         query.limit);
        },
        RoutePolicy{.needs_api_key = true});

    router.get("/v1/jobs/{id}",
               [&context](const httplib::Request& request, httplib::Response& response) {
                   single_query(request, {});
                   response.set_header("Cache-Control", kNoStore);
                   send_json(response, 200, job_status(context, request.matches[1], true));
               });

    router.del(
        "/v1/jobs/{id}",
        [&context](const httplib::Request& request, httplib::Response& response) {
            single_query(request, {});
            const std::string id = request.matches[1];
            if (!context.jobs.cancel(id)) {
                throw not_found(ProblemKind::UnknownId,
                                "no job with id '" + api::excerpt(id) + "'");
            }
            response.set_header("Cache-Control", kNoStore);
            send_json(response, 200, job_status(context, id, false));
        },
        RoutePolicy{.needs_api_key = true});

    router.get("/v1/jobs/{id}/events", [&context](const httplib::Request& request,
                                                  httplib::Response& response) {
        single_query(request, {});
        const std::string id = request.matches[1];
        job_status(context, id, false);  // 404 before the stream starts
        // Each change of the job's progress as one `progress` event, its data the job's
        // status (as GET /v1/jobs/{id} without frames); the stream ends after the event of
        // a settled job (done, failed, cancelled).
        send_progress_events(response,
                             {.status = [&context, id] { return context.jobs.status(id, false); },
                              .change = [](const nlohmann::json& status) { return status.dump(); },
                              .settled = settled,
                              .wait =
                                  [&context, changes = std::make_shared<std::uint64_t>(0)] {
                                      *changes = context.jobs.wait_for_change(*changes, kEventPoll);
                                  }});
    });

    router.get("/v1/jobs/{id}/frames/{name}", [&context](const httplib::Request& request,
                                                         httplib::Response& response) {
        single_query(request, {});
        const std::string id = request.matches[1];
        const std::string name = request.matches[2];
        job_status(context, id, false);
        bool known = false;
        const auto frame = context.jobs.frame(id, name, &known);
        if (!known) {
            throw not_found(ProblemKind::NotFound,
                            "job " + id + " has no frame named '" + api::excerpt(name) + "'");
        }
        if (!frame) {
            throw unavailable("the frame " + name + " is not rendered yet", kRetryAfterSeconds);
        }
        // A stored frame never changes: its job's id and its name name it for good.
        response.set_header("Cache-Control", "public, max-age=86400, immutable");
        response.set_content(frame->bytes, frame->content_type);
    });

    router.get("/v1/jobs/{id}/zip", [&context](const httplib::Request& request,
                                               httplib::Response& response) {
        single_query(request, {});
        const std::string id = request.matches[1];
        // One frame read at a time as the client takes the archive: its memory is one frame's.
        struct Archive {
            JobHold held;  // the job is not removed (retention) until the last byte is sent
            std::vector<std::string> names;
            std::size_t next = 0;
            ZipWriter zip;
        };
        auto archive = std::make_shared<Archive>();
        archive->held = context.jobs.hold(id);
        require_settled(job_status(context, id, false));
        const auto spec = context.jobs.spec(id);
        for (const api::JobFrame& frame : spec->frames) {
            if (context.jobs.store().has_frame(id, frame.name)) {
                archive->names.push_back(frame.name);
            }
        }
        response.set_header("Cache-Control", kNoStore);
        response.set_header("Content-Disposition", "attachment; filename=\"job-" + id + ".zip\"");
        response.set_chunked_content_provider(
            "application/zip", [&context, id, archive, spec](std::size_t, httplib::DataSink& sink) {
                if (archive->next == archive->names.size()) {
                    const std::string end = archive->zip.finish();
                    sink.write(end.data(), end.size());
                    sink.done();
                    return true;
                }
                const std::string& name = archive->names[archive->next++];
                const auto bytes = context.jobs.store().frame(id, name);
                if (!bytes) {
                    // Removed under the archive by another replica's retention: a cut-off
                    // download the client sees as one, never an archive of empty frames.
                    return false;
                }
                const auto* frame = &*std::find_if(
                    spec->frames.begin(), spec->frames.end(),
                    [&](const api::JobFrame& candidate) { return candidate.name == name; });
                const std::string entry =
                    archive->zip.entry(name + "." + api::to_string(frame->spec.format), *bytes);
                return sink.write(entry.data(), entry.size());
            });
    });

    router.get("/v1/jobs/{id}/sequences/{name}", [&context](const httplib::Request& request,
                                                            httplib::Response& response) {
        const auto query = single_query(request, {"format", "frame_ms", "columns", "quality"});
        const std::string id = request.matches[1];
        const std::string name = request.matches[2];
        const JobHold held = context.jobs.hold(id);  // its views stay until they are read
        const nlohmann::json status = job_status(context, id, false);
        const auto spec = context.jobs.spec(id);
        const auto sequence =
            std::find_if(spec->sequences.begin(), spec->sequences.end(),
                         [&](const api::JobSequence& candidate) { return candidate.name == name; });
        if (sequence == spec->sequences.end()) {
            throw not_found(ProblemKind::NotFound,
                            "job " + id + " has no sequence named '" + api::excerpt(name) + "'");
        }
        const std::string format = query.contains("format") ? query.at("format") : "webp";
        if (format != "webp" && format != "png" && format != "jpeg") {
            throw api::InvalidParameter("format", "expected webp, png or jpeg");
        }
        const int frame_ms = integer_parameter(query, "frame_ms", 100, 1, 65535);
        const int quality = integer_parameter(query, "quality", 85, 1, 100);
        std::vector<Rgba8Image> views;
        std::uint64_t pixels = 0;
        for (const std::string& frame_name : sequence->frames) {
            const auto frame = context.jobs.frame(id, frame_name);
            if (!frame) {
                if (!settled(status)) {
                    require_settled(status);
                }
                throw not_found(ProblemKind::NotFound,
                                "the view " + frame_name + " of the sequence was not rendered");
            }
            views.push_back(
                decode_8bit(std::vector<std::uint8_t>(frame->bytes.begin(), frame->bytes.end())));
            pixels += std::uint64_t(views.back().width) * std::uint64_t(views.back().height);
            if (pixels > kMaxSpinSetPixels) {
                throw api::InvalidParameter("name",
                                            "the sequence's views hold more than " +
                                                std::to_string(kMaxSpinSetPixels) +
                                                " pixels, more than one image of it may",
                                            ErrorKind::LimitExceeded);
            }
        }
        // A spin set is what its views are: the same whenever they are all rendered.
        response.set_header("Cache-Control", "public, max-age=86400, immutable");
        if (format == "webp") {
            response.set_content(animated_webp(views, frame_ms, quality), "image/webp");
            return;
        }
        const int columns =
            integer_parameter(query, "columns", int(std::ceil(std::sqrt(double(views.size())))), 1,
                              int(views.size()));
        Frame sheet;
        sheet.display = sprite_sheet(views, columns);
        sheet.width = sheet.display.width;
        sheet.height = sheet.display.height;
        const api::ImageFormat image_format =
            format == "png" ? api::ImageFormat::Png : api::ImageFormat::Jpeg;
        const std::vector<std::uint8_t> bytes = api::encode(sheet, image_format, quality);
        response.set_header("X-Oer-Sprite-Columns", std::to_string(columns));
        response.set_content(std::string(bytes.begin(), bytes.end()),
                             api::content_type_of(image_format));
    });
}

}  // namespace oer::server
