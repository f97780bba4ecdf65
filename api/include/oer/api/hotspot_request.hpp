#pragma once
// Hotspots and picking (docs/hotspots.md): the requests of POST and GET /v1/hotspots (where a
// frame shows points of the product) and POST /v1/pick (which point of the product a pixel
// shows). Each carries a render request (render_request.hpp) for the scene, camera and size,
// with members of its own beside the render's:
//
//   JSON body                                            GET query (repeatable)
//   hotspots[i]: {"name", "object", "primitive",         hotspot=NAME:surface:OBJECT,PRIMITIVE,
//                 "triangle", "barycentric": [a, b, c]}          TRIANGLE,A,B,C
//   hotspots[i]: {"name", "position": [x, y, z],         hotspot=NAME:point:X,Y,Z,NX,NY,NZ
//                 "normal": [x, y, z]}
//   pixel: [x, y]                                        pixel=X,Y
//   (the pick's image position, in pixels from the top left corner, pixel centres at +0.5)
//
// A surface hotspot is a point of a triangle as Babylon's viewer stores it: the request's object
// (its index in `objects`), the primitive of that object's mesh, the triangle (its index in the
// primitive's triangle list) and the barycentric weights of its three corners, each in [0, 1]
// and summing to 1 (within 1e-3; they are scaled to sum to 1 exactly). Its normal is the
// triangle's, on the side its winding makes the front. A point hotspot is a world-space point
// and the normal of the surface there (any non-zero length; normalised). Names are 1 to 64
// letters, digits, '-' or '_' (they become the element's slot names, `hotspot-NAME`), unique
// within a request.
//
// Errors as the render request's: InvalidParameter naming the member ("hotspots/2/barycentric")
// or the query parameter ("hotspot"), 422; more than RenderLimits::max_hotspots is 413.
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "oer/api/render_parameters.hpp"
#include "oer/api/render_request.hpp"
#include "oer/scene/point_placement.hpp"

namespace oer::api {

struct SurfaceSpot {
    std::size_t object = 0;
    std::size_t primitive = 0;
    std::size_t triangle = 0;
    glm::dvec3 barycentric{1.0, 0.0, 0.0};  // weights of corners 0, 1, 2; sum 1
};

struct PointSpot {
    glm::dvec3 position{0.0};
    glm::dvec3 normal{0.0, 1.0, 0.0};  // unit
};

struct HotspotSpec {
    std::string name;
    std::variant<SurfaceSpot, PointSpot> place;
};

struct HotspotRequest {
    RenderSpec render;
    std::vector<HotspotSpec> hotspots;
};

struct PickRequest {
    RenderSpec render;
    glm::dvec2 pixel{0.0};  // inside [0, width) x [0, height)
};

HotspotRequest parse_hotspot_json(std::string_view body, const RenderLimits& limits = {});
HotspotRequest parse_hotspot_query(const RenderQuery& query, const RenderLimits& limits = {});
PickRequest parse_pick_json(std::string_view body, const RenderLimits& limits = {});
PickRequest parse_pick_query(const RenderQuery& query, const RenderLimits& limits = {});

// The point a triangle's barycentric weights name on `mesh` placed by `transform`, with the
// triangle's front normal (world space, unit; the corners' mean vertex normal for a degenerate
// triangle). The indices must be in range (surface_spot_error says whether they are).
ScenePoint surface_point(const Mesh& mesh, const glm::mat4& transform, const SurfaceSpot& spot);

// Each hotspot's point in world space, once the request's meshes are resolved (one per object,
// in order). Throws InvalidParameter naming the member ("hotspots/<i>/primitive",
// "hotspots/<i>/triangle"; "hotspot" in the query form) for an index the mesh does not have.
std::vector<ScenePoint> hotspot_points(const HotspotRequest& request,
                                       const std::vector<std::shared_ptr<const Mesh>>& meshes,
                                       bool query_form);

}  // namespace oer::api
