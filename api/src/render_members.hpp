#pragma once
// The dedicated readers and writers of the render request's structured members (the rows
// `objects`, `camera` and `lights` of render_parameters.cpp): the objects with their mesh,
// transform and base color, the camera's look-at or orbit (and the GET form's rules for telling
// them apart, render_request.hpp), the lights' weights.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "request_values.hpp"

namespace oer::api::render_members {

using request_values::Json;

void read_json_objects(RenderSpec& spec, const Json& value, const std::string& path,
                       const RenderLimits& limits);
void read_query_objects(RenderSpec& spec, const RenderQuery& query, const RenderLimits& limits);
Json objects_json(const std::vector<ObjectSpec>& objects);

CameraSpec json_camera(const Json& value, const std::string& path);
std::optional<CameraSpec> query_camera(const RenderQuery& query);
Json camera_json(const CameraSpec& camera);
Camera to_camera(const LookAtSpec& look_at, double fov_y);

void read_json_lights(RenderSpec& spec, const Json& value, const std::string& path,
                      const RenderLimits& limits);
Json lights_json(const std::vector<double>& lights);

// A render request's body parsed, bounded by what a request within `limits` can hold plus
// `extra_values` JSON values (the members of their own that the hotspots' and the pick's bodies
// carry beside the render's). Throws as parse_render_json does.
Json read_render_body(std::string_view body, const RenderLimits& limits,
                      std::size_t extra_values = 0);

// The body's members, each read by its row of the table (render_parameters.cpp, which defines
// this): unknown members and a missing required one are errors.
void read_body_members(RenderSpec& spec, const Json& body, const RenderLimits& limits);

}  // namespace oer::api::render_members
