#pragma once
// A render request (docs/design.md section 7) as the API receives it, ids not yet resolved: the
// JSON body of POST /v1/render and the query parameters of GET /v1/render both parse into one
// RenderSpec, so both forms accept the same requests and give the same canonical document and
// ETag. api/openapi.yaml publishes the same names, enums and ranges.
//
// Names: a query parameter has the JSON member's name wherever both exist.
//
//   JSON body                                  GET query
//   environment                                environment
//   objects[i].mesh                            mesh (repeatable: one object each)
//   objects[i].transform                       (JSON only; GET objects are untransformed)
//   objects[i].base_color                      base_color  (one color for every mesh)
//   objects[i].base_color_material             base_color_material  (the material recoloured)
//   objects[i].variant                         variant  (one variant for every mesh)
//   camera.eye, camera.target, camera.up       eye, target, up        (look-at camera)
//   camera.orbit.{yaw,pitch,distance,target}   yaw, pitch, distance, target  (orbit camera)
//   camera.fov_y                               fov_y
//   camera.asset: N | "NAME"                   camera=asset:N | camera=asset:NAME
//   lights: [1, 0.5, false]                    lights=1,0.5,0  (weights; true/false: 1/0)
//   ground: true | false | "shadow"            ground=on|off|shadow
//   occlusion: true | false                    occlusion=on|off
//   bounce: "none" | "one"                     bounce=none|one
//   shadows.enabled: true | false              shadows=on|off
//   shadows.resolution, shadows.filter         shadow_resolution, shadow_filter
//   shadows.softness, shadows.intensity        shadow_softness, shadow_intensity
//   environment_yaw                            environment_yaw
//   width, height, format, quality, exposure, tonemap, background, samples: the same
//
// `yaw` and `pitch` always belong to the orbit camera; the environment's rotation about +Y is
// `environment_yaw` in both forms. In the GET form, any of yaw, pitch, distance makes an orbit
// camera (target is then the orbit's), otherwise eye and target make a look-at camera; with
// neither, the scene is framed automatically. An orbit without target or distance takes them
// from that automatic framing. `camera=asset:N` (N digits: an index, anything else a name) is
// one of the asset's own cameras, and takes none of the other camera parameters.
//
// Errors: MalformedRequest when the body is not readable JSON or nests more than 16 levels
// (HTTP 400); oer::Error (LimitExceeded) for a body over RenderLimits::max_body_bytes, or
// holding more JSON values than a request within the limits can (checked while parsing, 413);
// InvalidParameter for
// anything else, naming the member by its path ("objects/1/transform", "camera/orbit/pitch",
// "body" for the document itself) or, in the GET form, the query parameter (422). Unknown
// members and parameters are errors, so that a typo is never silently ignored.
#include <array>
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "oer/mesh/camera.hpp"
#include "oer/scene/frame_request.hpp"

namespace oer::api {

// The values `samples` may take (the frame renderer supersamples a square grid of
// ceil(sqrt(samples))^2 per pixel).
inline constexpr std::array<int, 4> kSampleCounts = {1, 2, 4, 8};

struct RenderLimits {
    int max_width = 4096;
    int max_height = 4096;
    std::size_t max_objects = 64;
    std::size_t max_lights = 64;  // switches in one request, far above any rig's light count
    int max_shadow_resolution = 8192;
    std::size_t max_body_bytes = 256 << 10;  // 64 transformed objects: about 30 KiB compact
    // Hotspots placed by one request (POST and GET /v1/hotspots): 256 take about 30 KiB of
    // JSON and 256 reads of one depth sample each.
    std::size_t max_hotspots = 256;
};

// Positions (eye, target) and transform entries stay within +-kMaxCoordinate: far inside float.
inline constexpr double kMaxCoordinate = 1e6;

enum class ImageFormat { Jpeg, Png, Exr };
std::string to_string(ImageFormat format);                      // "jpeg", "png", "exr"
ImageFormat image_format_from_string(const std::string& name);  // throws oer::Error

std::string to_string(ShadowFilter filter);                       // "pcf", "hard"
ShadowFilter shadow_filter_from_string(const std::string& name);  // throws oer::Error

std::string to_string(Bounce bounce);                // "none", "one"
Bounce bounce_from_string(const std::string& name);  // throws oer::Error

// The ground plane (FrameRequest::ground and ::ground_look): none, an opaque floor, or a shadow
// catcher. JSON spells it false, true or "shadow"; the query off, on or shadow.
enum class GroundChoice { Off, Opaque, Shadow };
std::string to_string(GroundChoice ground);                       // "off", "on", "shadow"
GroundChoice ground_choice_from_string(const std::string& name);  // throws oer::Error

// "env", "transparent" or "#rrggbb" (either case); throws InvalidParameter naming `name`.
Background parse_background(const std::string& name, const std::string& text);
// The canonical text: "env", "transparent" or "#rrggbb" in lowercase.
std::string to_string(const Background& background);

struct ObjectSpec {
    std::string mesh;                      // a content id or kDefaultPresetId
    glm::dmat4 transform{1.0};             // world from mesh
    std::optional<glm::dvec3> base_color;  // linear RGB in [0, 1]; empty: the mesh's materials
    // The name of the materials base_color recolours (needs base_color); empty: every one.
    std::optional<std::string> base_color_material;
    // A variant's name among the mesh's KHR_materials_variants (Mesh::variants); empty: the
    // file's default materials.
    std::optional<std::string> variant;
};

// The index in mesh.variants of object.variant (nullopt when the object names none). Throws
// InvalidParameter naming `parameter` when the mesh has no variant of that name, listing the
// ones it has.
std::optional<std::uint32_t> variant_index(const ObjectSpec& object, const Mesh& mesh,
                                           const std::string& parameter);
// The index in mesh.materials of the first material named object.base_color_material (nullopt
// when the object names none). Throws InvalidParameter naming `parameter` when no material of
// the mesh has that name, listing their names.
std::optional<std::uint32_t> base_color_material_index(const ObjectSpec& object, const Mesh& mesh,
                                                       const std::string& parameter);

struct LookAtSpec {
    glm::dvec3 eye{0.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
};

// Angles in degrees, as oer::Orbit (whose defaults these are). An absent target or distance is
// the automatic framing's (oer::frame_orbit: the scene's bounds at the frame's aspect ratio),
// resolved by to_frame_request once the meshes are known; it stays absent in the canonical
// document, so that the request keeps one ETag whatever the meshes.
struct OrbitSpec {
    double yaw = Orbit{}.yaw;
    double pitch = Orbit{}.pitch;
    std::optional<double> distance;
    std::optional<glm::dvec3> target;
};

// One of the asset's own cameras (Mesh::cameras, the mesh JSON's `cameras`): of the first
// object's mesh, placed by that object's transform, by its index in that list or by its name
// (the first camera of that name). It has its own field of view.
struct AssetCameraSpec {
    std::variant<std::size_t, std::string> index_or_name;
};

struct CameraSpec {
    std::variant<LookAtSpec, OrbitSpec, AssetCameraSpec> placement;
    double fov_y = Camera{}.fov_y;  // look-at and orbit only
};

struct RenderSpec {
    std::string environment;  // a rig id or kDefaultPresetId
    std::vector<ObjectSpec> objects;
    GroundChoice ground = GroundChoice::Opaque;
    // The occlusion switches, FrameRequest::occlusion and ::bounce: false, the previous OER
    // lighting (the residual map unoccluded); none, the ground lights nothing and nothing
    // reflects (to compare with a direct-only reference).
    bool occlusion = true;
    Bounce bounce = Bounce::One;
    std::optional<CameraSpec> camera;  // empty: frame the scene automatically
    // One weight per rig light in [0, kMaxLightWeight] (0 off, 1 as captured; the body's true
    // and false are 1 and 0, so both spellings share the canonical document); empty: all 1.
    std::vector<double> lights;
    int width = 512;
    int height = 512;
    ImageFormat format = ImageFormat::Jpeg;
    int quality = 85;       // JPEG quality, 1..100
    double exposure = 0.0;  // EV
    ToneMapper tonemap = ToneMapper::Neutral;
    Background background;
    ShadowOptions shadows;         // resolution: a power of two from 64 to the limit
    int samples = 4;               // 1, 2, 4 or 8
    double environment_yaw = 0.0;  // degrees about +Y, in [-360, 360]
};

RenderSpec parse_render_json(std::string_view body, const RenderLimits& limits = {});
RenderSpec parse_render_query(const std::multimap<std::string, std::string>& query,
                              const RenderLimits& limits = {});

// Every JSON member the parser accepts, as a path ("objects/*/transform", "camera/orbit/yaw";
// "*" stands for any array index), and every query parameter: the names of the table of
// parameters (render_parameters.hpp) that the parsers read by, for the API description's test.
const std::vector<std::string>& render_json_members();
const std::vector<std::string>& render_query_parameters();

// The request with every default filled in (objects' identity transforms included; the camera
// and base colors only when given) and numbers as doubles (-0 as 0): equal requests, JSON or
// GET, give equal documents. It is itself a valid request body.
nlohmann::json normalised_render_json(const RenderSpec& spec);

// A strong ETag, "\"<64 hex digits>\"": SHA-256 of the canonical document and the service's
// version (a new version may draw the same request differently).
std::string render_etag(const RenderSpec& spec);

// The camera the frame is seen from, once the spec's meshes are resolved (one per object, in
// order): its look-at camera, its orbit with a missing target or distance from the automatic
// framing, its asset camera placed by the first object's transform, or without a camera the
// automatic framing itself (oer::frame_bounds of the objects' transformed bounds, as the
// renderer frames a FrameRequest without one). Throws InvalidParameter("camera") for an asset
// camera the first object's mesh does not have (listing those it has), an orthographic one (oer
// draws perspective only) or one without an object; oer::Error (Internal) when the meshes do
// not match the objects.
Camera resolved_camera(const RenderSpec& spec,
                       const std::vector<std::shared_ptr<const Mesh>>& meshes);

// The frame the spec asks for, once its ids are resolved (its camera always set, by
// resolved_camera): `meshes` holds one mesh per object, in
// order (their transformed bounds frame an orbit without target or distance); `environment_map`
// (the image the rig was made from) may be null unless the background is the environment. Throws
// InvalidParameter("lights") when the weights do not match the rig's lights, and oer::Error
// (Internal) when the resolved assets do not match the spec (a caller's bug).
// An object's variant or base_color_material that its mesh does not have: InvalidParameter
// ("objects/<i>/variant", "objects/<i>/base_color_material").
// FrameRequest::occlusion is the spec's for a scene with objects (without, nothing occludes);
// FrameRequest::transfer stays empty: with occlusion on, the caller bakes it
// (oer::bake_transfer) or finds it cached (the service's transfer registry).
FrameRequest to_frame_request(const RenderSpec& spec, std::shared_ptr<const Rig> rig,
                              std::shared_ptr<const HdrImage> environment_map,
                              const std::vector<std::shared_ptr<const Mesh>>& meshes);
// The same from the camera resolved_camera gave for this spec and these meshes, for a caller
// that needs the camera beside the frame (the service's X-Oer-Camera) and resolves it once.
FrameRequest to_frame_request(const RenderSpec& spec, const Camera& camera,
                              std::shared_ptr<const Rig> rig,
                              std::shared_ptr<const HdrImage> environment_map,
                              const std::vector<std::shared_ptr<const Mesh>>& meshes);

}  // namespace oer::api
