#include "oer/api/render_request.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <type_traits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/render_parameters.hpp"
#include "oer/api/version.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/enum_names.hpp"
#include "oer/core/one_line.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "render_members.hpp"

namespace oer::api {

namespace {

using Json = nlohmann::json;

constexpr EnumNames<ImageFormat, 3> kFormatNames = {
    {{ImageFormat::Jpeg, "jpeg"}, {ImageFormat::Png, "png"}, {ImageFormat::Exr, "exr"}}};
constexpr EnumNames<ShadowFilter, 2> kFilterNames = {
    {{ShadowFilter::Pcf, "pcf"}, {ShadowFilter::Hard, "hard"}}};
constexpr EnumNames<Bounce, 2> kBounceNames = {{{Bounce::None, "none"}, {Bounce::One, "one"}}};
constexpr EnumNames<GroundChoice, 3> kGroundNames = {
    {{GroundChoice::Off, "off"}, {GroundChoice::Opaque, "on"}, {GroundChoice::Shadow, "shadow"}}};

// What a valid body can hold, checked while it is parsed, so that a body of many small values
// costs no more than a valid one. A valid body nests 4 levels deep (body, camera, orbit,
// target); its values are: 25 per object (the object, its mesh, its transform array and 16
// numbers, its base_color array and 3 numbers, its base_color_material and variant), one per
// light switch, and 44 others (the body, its 13 scalar members, the objects and lights arrays,
// the camera's 22 with its vectors and orbit, shadows' 6): under 64.
checked_json::JsonBounds request_bounds(const RenderLimits& limits, std::size_t extra_values) {
    checked_json::JsonBounds bounds;
    bounds.max_depth = 16;
    bounds.max_elements = 64 + 25 * limits.max_objects + limits.max_lights + extra_values;
    return bounds;
}

}  // namespace

Json render_members::read_render_body(std::string_view body, const RenderLimits& limits,
                                      std::size_t extra_values) {
    if (body.size() > limits.max_body_bytes) {
        throw Error(ErrorKind::LimitExceeded,
                    "render request: the body has " + std::to_string(body.size()) +
                        " bytes, over the limit of " + std::to_string(limits.max_body_bytes));
    }
    try {
        return checked_json::parse_bounded(body, request_bounds(limits, extra_values));
    } catch (const checked_json::JsonParseError& error) {
        if (error.cause() == checked_json::JsonParseError::Cause::TooMany) {
            throw Error(ErrorKind::LimitExceeded,
                        std::string("render request: ") + error.what() +
                            ", more than any request within the "
                            "limits (at most " +
                            std::to_string(limits.max_objects) + " objects and " +
                            std::to_string(limits.max_lights) + " light switches)");
        }
        throw MalformedRequest(error.what());
    }
}

namespace {

// The GET form's names: every parameter known, and given once but for a repeatable one (mesh).
void check_query_names(const std::multimap<std::string, std::string>& query) {
    const std::vector<RenderParameter>& rows = render_parameters();
    for (auto it = query.begin(); it != query.end(); it = query.upper_bound(it->first)) {
        const auto row = std::find_if(rows.begin(), rows.end(), [&it](const RenderParameter& r) {
            return !r.query.empty() && r.query == it->first;
        });
        if (row == rows.end()) {
            throw InvalidParameter(excerpt(it->first), "unknown parameter");
        }
        if (!row->repeatable && query.count(it->first) > 1) {
            throw InvalidParameter(it->first, "given more than once");
        }
    }
}

// The orbit's missing target or distance from the automatic framing of `scene` (the objects'
// enclosing bounds), as the renderer frames a request without a camera (frame_context.cpp): the
// same bounds, in float, at the frame's aspect ratio (width / height, never the size in pixels).
// With a floor (opaque or shadow-catching: the ground at the scene's lowest y, FrameRequest's
// rule), the pitch is raised to keep the eye above it (oer::pitch_above_floor): the floor's
// underside is never shown, nor a shadow caught from below.
Camera resolved_orbit(const OrbitSpec& orbit, float fov_y, const Bounds& scene, float aspect,
                      bool floor) {
    const std::optional<glm::vec3> target =
        orbit.target ? std::optional<glm::vec3>(glm::vec3(*orbit.target)) : std::nullopt;
    const std::optional<float> distance =
        orbit.distance ? std::optional<float>(float(*orbit.distance)) : std::nullopt;
    float pitch = float(orbit.pitch);
    if (floor) {
        try {
            pitch = pitch_above_floor(pitch, target, distance, scene, fov_y, aspect, scene.min.y);
        } catch (const Error&) {
            throw InvalidParameter("target",
                                   "no orbit pitch keeps the eye above the floor, which the ground "
                                   "puts at the scene's lowest y = " +
                                       std::to_string(scene.min.y) +
                                       ": the target is below it or too close to it for the "
                                       "distance; raise the target or ask for ground off");
        }
    }
    return frame_orbit(float(orbit.yaw), pitch, target, distance, scene, fov_y, aspect);
}

// "it has 2: 0 'Front' (perspective), 1 'Top' (orthographic)": what a mesh offers, for the
// error that names a camera it does not have (the first 16; the mesh JSON lists them all).
std::string listed_cameras(const std::vector<AssetCamera>& cameras) {
    if (cameras.empty()) {
        return "it has no cameras";
    }
    constexpr std::size_t kListed = 16;
    std::string list = "it has " + std::to_string(cameras.size()) + ": ";
    for (std::size_t i = 0; i < std::min(cameras.size(), kListed); ++i) {
        list += (i > 0 ? ", " : "") + std::to_string(i) + " '" + excerpt(cameras[i].name) + "' (" +
                (cameras[i].projection == CameraProjection::Perspective ? "perspective"
                                                                        : "orthographic") +
                ")";
    }
    return list + (cameras.size() > kListed ? ", ..." : "");
}

// The asset camera of the first object's mesh, placed by that object's transform.
Camera resolved_asset_camera(const AssetCameraSpec& asset, const RenderSpec& spec,
                             const std::vector<std::shared_ptr<const Mesh>>& meshes) {
    if (spec.objects.empty()) {
        throw InvalidParameter("camera",
                               "an asset camera is one of the first object's mesh's cameras, "
                               "and the request has no object");
    }
    const std::vector<AssetCamera>& cameras = meshes.front()->cameras;
    const auto chosen = std::visit(
        [&cameras](const auto& index_or_name) {
            if constexpr (std::is_same_v<std::decay_t<decltype(index_or_name)>, std::size_t>) {
                return index_or_name < cameras.size()
                           ? cameras.begin() + std::ptrdiff_t(index_or_name)
                           : cameras.end();
            } else {
                return std::find_if(cameras.begin(), cameras.end(),
                                    [&](const AssetCamera& c) { return c.name == index_or_name; });
            }
        },
        asset.index_or_name);
    if (chosen == cameras.end()) {
        const std::string wanted = std::visit(
            [](const auto& index_or_name) {
                if constexpr (std::is_same_v<std::decay_t<decltype(index_or_name)>, std::size_t>) {
                    return "no camera " + std::to_string(index_or_name);
                } else {
                    return "no camera named '" + excerpt(index_or_name) + "'";
                }
            },
            asset.index_or_name);
        throw InvalidParameter(
            "camera", "the first object's mesh has " + wanted + "; " + listed_cameras(cameras));
    }
    const std::string name =
        "camera " + std::to_string(chosen - cameras.begin()) + " '" + excerpt(chosen->name) + "'";
    if (chosen->projection != CameraProjection::Perspective) {
        throw InvalidParameter("camera", name +
                                             " is orthographic: oer renders perspective "
                                             "cameras only");
    }
    const glm::dmat4& transform = spec.objects.front().transform;
    const auto point = [&transform](const glm::vec3& p) {
        return glm::vec3(transform * glm::dvec4(glm::dvec3(p), 1.0));
    };
    Camera camera = chosen->camera;
    camera.eye = point(chosen->camera.eye);
    camera.target = point(chosen->camera.target);
    camera.up = glm::vec3(glm::normalize(glm::dmat3(transform) * glm::dvec3(chosen->camera.up)));
    // A transform barely invertible (within the parser's determinant) may still flatten the
    // view in float: eye and target one point, or up along the view.
    try {
        validate_camera(camera);
    } catch (const Error& error) {
        throw InvalidParameter("camera",
                               name + " placed by the first object's transform: " + error.what());
    }
    return camera;
}

}  // namespace

std::string to_string(ImageFormat format) {
    return name_of(format, kFormatNames);
}

ImageFormat image_format_from_string(const std::string& name) {
    return value_named(name, kFormatNames, "format");
}

std::string to_string(ShadowFilter filter) {
    return name_of(filter, kFilterNames);
}

ShadowFilter shadow_filter_from_string(const std::string& name) {
    return value_named(name, kFilterNames, "shadow filter");
}

std::string to_string(Bounce bounce) {
    return name_of(bounce, kBounceNames);
}

Bounce bounce_from_string(const std::string& name) {
    return value_named(name, kBounceNames, "bounce");
}

std::string to_string(GroundChoice ground) {
    return name_of(ground, kGroundNames);
}

GroundChoice ground_choice_from_string(const std::string& name) {
    return value_named(name, kGroundNames, "ground");
}

Background parse_background(const std::string& name, const std::string& text) {
    Background background;
    if (text == "env") {
        return background;
    }
    if (text == "transparent") {
        background.kind = BackgroundKind::Transparent;
        return background;
    }
    if (text.size() == 7 && text[0] == '#' &&
        text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        background.kind = BackgroundKind::Color;
        for (int i = 0; i < 3; ++i) {
            int channel = 0;
            std::from_chars(text.data() + 1 + 2 * i, text.data() + 3 + 2 * i, channel, 16);
            background.color[i] = float(channel) / 255.0f;
        }
        return background;
    }
    throw InvalidParameter(name,
                           "expected env, transparent or #rrggbb, got '" + excerpt(text) + "'");
}

std::string to_string(const Background& background) {
    switch (background.kind) {
        case BackgroundKind::Environment:
            return "env";
        case BackgroundKind::Transparent:
            return "transparent";
        case BackgroundKind::Color:
            break;
    }
    static constexpr char hex[] = "0123456789abcdef";
    std::string text = "#";
    for (int i = 0; i < 3; ++i) {
        const int channel = int(std::lround(std::clamp(background.color[i], 0.0f, 1.0f) * 255.0f));
        text += hex[channel >> 4];
        text += hex[channel & 15];
    }
    return text;
}

const std::vector<std::string>& render_json_members() {
    static const std::vector<std::string> members = [] {
        std::vector<std::string> list;
        for (const RenderParameter& row : render_parameters()) {
            list.emplace_back(row.json);
        }
        return list;
    }();
    return members;
}

const std::vector<std::string>& render_query_parameters() {
    static const std::vector<std::string> parameters = [] {
        std::vector<std::string> list;
        for (const RenderParameter& row : render_parameters()) {
            if (!row.query.empty() &&
                std::find(list.begin(), list.end(), row.query) == list.end()) {
                list.emplace_back(row.query);
            }
        }
        return list;
    }();
    return parameters;
}

RenderSpec parse_render_json(std::string_view body, const RenderLimits& limits) {
    RenderSpec spec;
    render_members::read_body_members(spec, render_members::read_render_body(body, limits), limits);
    return spec;
}

RenderSpec parse_render_query(const std::multimap<std::string, std::string>& query,
                              const RenderLimits& limits) {
    check_query_names(query);
    RenderSpec spec;
    for (const bool second_pass : {false, true}) {
        for (const RenderParameter& row : render_parameters()) {
            if (row.read_query && row.query_second_pass == second_pass) {
                row.read_query(spec, query, limits);
            }
        }
    }
    return spec;
}

nlohmann::json normalised_render_json(const RenderSpec& spec) {
    Json json = Json::object();
    for (const RenderParameter& row : render_parameters()) {
        if (row.write_canonical) {
            row.write_canonical(spec, json);
        }
    }
    return json;
}

std::string render_etag(const RenderSpec& spec) {
    const std::string canonical_text =
        "oer-render/" + std::string(kVersion) + "\n" + normalised_render_json(spec).dump();
    std::string etag = sha256_hex(canonical_text);
    etag.insert(etag.begin(), '"');
    etag.push_back('"');
    return etag;
}

Camera resolved_camera(const RenderSpec& spec,
                       const std::vector<std::shared_ptr<const Mesh>>& meshes) {
    if (meshes.size() != spec.objects.size() ||
        std::any_of(meshes.begin(), meshes.end(), [](const auto& mesh) { return !mesh; })) {
        throw Error(ErrorKind::Internal,
                    "resolved_camera: " + std::to_string(meshes.size()) + " mesh(es) for " +
                        std::to_string(spec.objects.size()) + " object(s), or a null one");
    }
    // The bounds the renderer frames a request without a camera by (oer::scene_bounds).
    std::vector<SceneObject> objects;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        objects.push_back({meshes[i], glm::mat4(spec.objects[i].transform), std::nullopt});
    }
    const Bounds scene = scene_bounds(objects).box;
    const float aspect = float(spec.width) / float(spec.height);
    if (!spec.camera) {
        return frame_bounds(scene, Camera{}.fov_y, aspect);
    }
    if (const auto* look_at = std::get_if<LookAtSpec>(&spec.camera->placement)) {
        // An eye under the floor would see its underside: the request says what it did not mean.
        if (spec.ground != GroundChoice::Off && look_at->eye.y <= double(scene.min.y)) {
            throw InvalidParameter(
                "eye", "y = " + std::to_string(look_at->eye.y) +
                           " is not above the floor, which the ground puts at the scene's lowest "
                           "y = " +
                           std::to_string(scene.min.y) + "; raise the eye or ask for ground off");
        }
        return render_members::to_camera(*look_at, spec.camera->fov_y);
    }
    if (const auto* asset = std::get_if<AssetCameraSpec>(&spec.camera->placement)) {
        return resolved_asset_camera(*asset, spec, meshes);
    }
    return resolved_orbit(std::get<OrbitSpec>(spec.camera->placement), float(spec.camera->fov_y),
                          scene, aspect, spec.ground != GroundChoice::Off);
}

FrameRequest to_frame_request(const RenderSpec& spec, std::shared_ptr<const Rig> rig,
                              std::shared_ptr<const HdrImage> environment_map,
                              const std::vector<std::shared_ptr<const Mesh>>& meshes) {
    return to_frame_request(spec, resolved_camera(spec, meshes), std::move(rig),
                            std::move(environment_map), meshes);
}

std::optional<std::uint32_t> variant_index(const ObjectSpec& object, const Mesh& mesh,
                                           const std::string& parameter) {
    if (!object.variant) {
        return std::nullopt;
    }
    const auto found = std::find(mesh.variants.begin(), mesh.variants.end(), *object.variant);
    if (found != mesh.variants.end()) {
        return std::uint32_t(found - mesh.variants.begin());
    }
    if (mesh.variants.empty()) {
        throw InvalidParameter(
            parameter, "mesh '" + object.mesh + "' has no variants (no KHR_materials_variants)");
    }
    std::string names;
    for (const std::string& name : mesh.variants) {
        names += (names.empty() ? "'" : ", '") + detail::one_line(name, 60) + "'";
    }
    throw InvalidParameter(parameter, "mesh '" + object.mesh + "' has no variant '" +
                                          detail::one_line(*object.variant, 60) +
                                          "' (its variants: " + names + ")");
}

std::optional<std::uint32_t> base_color_material_index(const ObjectSpec& object, const Mesh& mesh,
                                                       const std::string& parameter) {
    if (!object.base_color_material) {
        return std::nullopt;
    }
    std::string names;
    for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
        const Material& material = mesh.materials[m];
        if (material.name == *object.base_color_material) {
            return std::uint32_t(m);
        }
        names += (names.empty() ? "'" : ", '") + detail::one_line(material.name, 60) + "'";
    }
    throw InvalidParameter(parameter, "mesh '" + object.mesh + "' has no material named '" +
                                          detail::one_line(*object.base_color_material, 60) +
                                          "' (its materials: " + names + ")");
}

FrameRequest to_frame_request(const RenderSpec& spec, const Camera& camera,
                              std::shared_ptr<const Rig> rig,
                              std::shared_ptr<const HdrImage> environment_map,
                              const std::vector<std::shared_ptr<const Mesh>>& meshes) {
    if (!rig) {
        throw Error(ErrorKind::Internal,
                    "to_frame_request: no rig for environment '" + spec.environment + "'");
    }
    if (meshes.size() != spec.objects.size() ||
        std::any_of(meshes.begin(), meshes.end(), [](const auto& mesh) { return !mesh; })) {
        throw Error(ErrorKind::Internal, "to_frame_request: " + std::to_string(meshes.size()) +
                                             " mesh(es) resolved for " +
                                             std::to_string(spec.objects.size()) +
                                             " object(s), or a null one");
    }
    if (!spec.lights.empty() && spec.lights.size() != rig->lights.size()) {
        throw InvalidParameter(
            "lights", "the environment has " + std::to_string(rig->lights.size()) +
                          " light(s), got " + std::to_string(spec.lights.size()) + " weights");
    }
    FrameRequest request;
    request.rig = std::move(rig);
    request.environment_map = std::move(environment_map);
    for (std::size_t i = 0; i < spec.objects.size(); ++i) {
        const ObjectSpec& object = spec.objects[i];
        SceneObject drawn;
        drawn.mesh = meshes[i];
        drawn.transform = glm::mat4(object.transform);
        if (object.base_color) {
            drawn.base_color = glm::vec3(*object.base_color);
        }
        drawn.variant =
            variant_index(object, *meshes[i], "objects/" + std::to_string(i) + "/variant");
        drawn.base_color_material = base_color_material_index(
            object, *meshes[i], "objects/" + std::to_string(i) + "/base_color_material");
        request.objects.push_back(std::move(drawn));
    }
    request.camera = camera;
    for (const RenderParameter& row : render_parameters()) {
        if (row.to_frame) {
            row.to_frame(spec, request);
        }
    }
    return request;
}

}  // namespace oer::api
