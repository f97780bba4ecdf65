#pragma once
// A batch job (POST /v1/jobs, docs/jobs.md) as the API receives it: a list of named frames, or a
// turntable (views around the orbit) crossed with variants, environments and sizes, expanded
// here into the same list. Every frame is a render request read by the render request's own
// parser (render_request.hpp), so a job accepts exactly what POST /v1/render does, and a
// turntable's views are that request's orbit camera turned about its target.
//
//   {"frames": [{"name": "front", "render": {...a render request...}}, ...]}
//   {"turntable": {"render": {...}, "views": 36, "variants": ["Red", "Blue"],
//                  "environments": ["default", "<id>"], "sizes": [{"width": 64, "height": 48}]}}
//
// A turntable's frames are named <sequence>-<view, 3 digits>, where the sequence names the
// variant, environment and size of its views (only those the job varies: "Red-64x48"; with
// none, "turntable"); each sequence is one spin set (its animated WebP, its sprite sheet).
//
// Errors as the render request's: MalformedRequest (400) for a body that is not JSON, and
// InvalidParameter naming the member by its path, "frames/3/render/width",
// "turntable/views" (422), or of kind LimitExceeded (413) for a job over JobLimits.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "oer/api/render_request.hpp"

namespace oer::api {

struct JobLimits {
    std::size_t max_frames = 1000;
    std::uint64_t max_pixels = 256ull << 20;  // the frames' width x height together
    std::size_t max_body_bytes = 1 << 20;
};

struct JobFrame {
    std::string name;  // [A-Za-z0-9._-], 1 to kMaxFrameNameLength characters, unique in its job
    RenderSpec spec;
};

// The frames of one turntable's views, in order around the orbit.
struct JobSequence {
    std::string name;
    std::vector<std::string> frames;
};

struct JobSpec {
    std::vector<JobFrame> frames;
    std::vector<JobSequence> sequences;  // empty for a list of frames
};

inline constexpr std::size_t kMaxFrameNameLength = 100;
bool is_frame_name(std::string_view name);

JobSpec parse_job_json(std::string_view body, const RenderLimits& render_limits,
                       const JobLimits& limits);

// The job as stored: every frame's canonical render request (normalised_render_json) under its
// name, and the sequences; read back by job_from_stored_json, which parses each frame again.
nlohmann::json stored_job_json(const JobSpec& job);
JobSpec job_from_stored_json(const nlohmann::json& stored, const RenderLimits& render_limits);

// The pixels of every frame together.
std::uint64_t job_pixels(const JobSpec& job);

}  // namespace oer::api
