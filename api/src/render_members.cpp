#include "render_members.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <glm/matrix.hpp>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/render_parameters.hpp"
#include "oer/core/one_line.hpp"

namespace oer::api::render_members {

using namespace request_values;

namespace {

constexpr Range kLightWeight{0.0, kMaxLightWeight};  // the renderer's limit
// The renderer rejects transforms whose |determinant| is under this (they flatten the mesh).
constexpr double kMinDeterminant = 1e-12;

void check_transform(const std::string& name, const glm::dmat4& transform) {
    if (std::abs(glm::determinant(transform)) < kMinDeterminant) {
        throw InvalidParameter(name, "must be invertible (its determinant is 0 or nearly)");
    }
}

void check_look_at(const std::string& name, const LookAtSpec& look_at, double fov_y) {
    try {
        validate_camera(to_camera(look_at, fov_y));
    } catch (const Error& error) {
        throw InvalidParameter(name, error.what());
    }
}

glm::dmat4 json_transform(const Json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 16) {
        reader().fail(path, "expected an array of 16 numbers (a column-major 4x4 matrix)");
    }
    glm::dmat4 transform{1.0};
    for (std::size_t i = 0; i < 16; ++i) {
        transform[int(i / 4)][int(i % 4)] = json_number(value[i], child(path, i), kCoordinate);
    }
    check_transform(path, transform);
    return transform;
}

// A variant's or a material's name as a request gives it: 1 to kMaxNameBytes bytes of UTF-8
// (the mesh then says whether it has it: variant_index, check_base_color_material).
constexpr std::size_t kMaxNameBytes = 256;
std::string checked_name(const std::string& parameter, const std::string& name) {
    if (name.empty() || name.size() > kMaxNameBytes) {
        throw InvalidParameter(parameter, "a name is 1 to " + std::to_string(kMaxNameBytes) +
                                              " bytes, got " + std::to_string(name.size()));
    }
    const bool control = std::any_of(name.begin(), name.end(), [](char c) {
        return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
    });
    if (control || detail::valid_utf8(name) != name) {
        throw InvalidParameter(parameter,
                               "a name is one line of UTF-8 text, without control characters");
    }
    return name;
}

ObjectSpec json_object_spec(const Json& value, const std::string& path) {
    require_object(value, path, render_member_names("objects/*"));
    ObjectSpec object;
    const Json& mesh = reader().member(value, path, "mesh");
    object.mesh = checked_id(child(path, "mesh"), json_string(mesh, child(path, "mesh")));
    if (const Json* transform = find(value, "transform")) {
        object.transform = json_transform(*transform, child(path, "transform"));
    }
    if (const Json* color = find(value, "base_color")) {
        object.base_color = json_vector3(*color, child(path, "base_color"), kColor);
    }
    if (const Json* variant = find(value, "variant")) {
        object.variant =
            checked_name(child(path, "variant"), json_string(*variant, child(path, "variant")));
    }
    if (const Json* material = find(value, "base_color_material")) {
        const std::string member = child(path, "base_color_material");
        if (!object.base_color) {
            reader().fail(member, "needs base_color: it names the material base_color recolours");
        }
        object.base_color_material = checked_name(member, json_string(*material, member));
    }
    return object;
}

OrbitSpec json_orbit(const Json& value, const std::string& path) {
    require_object(value, path, render_member_names("camera/orbit"));
    OrbitSpec orbit;
    if (const Json* yaw = find(value, "yaw")) {
        orbit.yaw = json_number(*yaw, child(path, "yaw"), kAngle);
    }
    if (const Json* pitch = find(value, "pitch")) {
        orbit.pitch = json_number(*pitch, child(path, "pitch"), kPitch);
    }
    if (const Json* distance = find(value, "distance")) {
        orbit.distance = json_number(*distance, child(path, "distance"), kDistance);
    }
    if (const Json* target = find(value, "target")) {
        orbit.target = json_vector3(*target, child(path, "target"), kCoordinate);
    }
    return orbit;
}

LookAtSpec json_look_at(const Json& value, const std::string& path, double fov_y) {
    const Json* eye = find(value, "eye");
    const Json* target = find(value, "target");
    if (!eye || !target) {
        reader().fail(child(path, eye ? "target" : "eye"),
                      "required: a camera has eye and target, or orbit");
    }
    LookAtSpec look_at;
    look_at.eye = json_vector3(*eye, child(path, "eye"), kCoordinate);
    look_at.target = json_vector3(*target, child(path, "target"), kCoordinate);
    if (const Json* up = find(value, "up")) {
        look_at.up = json_vector3(*up, child(path, "up"), kCoordinate);
    }
    check_look_at(path, look_at, fov_y);
    return look_at;
}

// The GET form's orbit: yaw, pitch, distance and target, any of them.
OrbitSpec query_orbit(const RenderQuery& query) {
    OrbitSpec orbit;
    if (const std::string* yaw = query_value(query, "yaw")) {
        orbit.yaw = parse_number("yaw", *yaw, kAngle.low, kAngle.high);
    }
    if (const std::string* pitch = query_value(query, "pitch")) {
        orbit.pitch = parse_number("pitch", *pitch, kPitch.low, kPitch.high);
    }
    if (const std::string* distance = query_value(query, "distance")) {
        orbit.distance = parse_number("distance", *distance, kDistance.low, kDistance.high);
    }
    if (const std::string* target = query_value(query, "target")) {
        orbit.target = parse_vector3("target", *target, kCoordinate.low, kCoordinate.high);
    }
    return orbit;
}

LookAtSpec query_look_at(const RenderQuery& query, double fov_y) {
    const std::string* eye = query_value(query, "eye");
    const std::string* target = query_value(query, "target");
    if (!eye || !target) {
        throw InvalidParameter(eye ? "target" : "eye",
                               "required: a camera has eye and target, or yaw, pitch and distance");
    }
    LookAtSpec look_at;
    look_at.eye = parse_vector3("eye", *eye, kCoordinate.low, kCoordinate.high);
    look_at.target = parse_vector3("target", *target, kCoordinate.low, kCoordinate.high);
    if (const std::string* up = query_value(query, "up")) {
        look_at.up = parse_vector3("up", *up, kCoordinate.low, kCoordinate.high);
    }
    check_look_at("eye", look_at, fov_y);
    return look_at;
}

// An asset camera's index (digits) or name, as the query's `camera=asset:...` and the body's
// `camera.asset` give it.
constexpr std::string_view kAssetPrefix = "asset:";
constexpr long long kMaxAssetCameraIndex = 1 << 20;  // far beyond any mesh's cameras

AssetCameraSpec json_asset_camera(const Json& value, const std::string& path) {
    if (value.is_number_integer()) {
        return {std::size_t(json_integer(value, path, 0, kMaxAssetCameraIndex))};
    }
    if (!value.is_string() || value.get<std::string>().empty()) {
        reader().fail(path, "expected an asset camera's index (an integer) or name (a string)");
    }
    return {value.get<std::string>()};
}

AssetCameraSpec query_asset_camera(const std::string& text) {
    if (!text.starts_with(kAssetPrefix) || text.size() == kAssetPrefix.size()) {
        throw InvalidParameter(
            "camera", "expected asset:N (an index) or asset:NAME, got '" + excerpt(text) + "'");
    }
    const std::string which = text.substr(kAssetPrefix.size());
    if (which.find_first_not_of("0123456789") != std::string::npos) {
        return {which};
    }
    return {std::size_t(parse_integer("camera", which, 0, kMaxAssetCameraIndex))};
}

// A light's weight (docs/design.md section 2, dimmable lights): true and false, the on/off
// form, are 1 and 0.
double json_light_weight(const Json& value, const std::string& path) {
    if (value.is_boolean()) {
        return value.get<bool>() ? 1.0 : 0.0;
    }
    return json_number(value, path, kLightWeight);
}

}  // namespace

void read_json_objects(RenderSpec& spec, const Json& value, const std::string& path,
                       const RenderLimits& limits) {
    require_array(value, path, limits.max_objects);
    for (std::size_t i = 0; i < value.size(); ++i) {
        spec.objects.push_back(json_object_spec(value[i], child(path, i)));
    }
}

void read_query_objects(RenderSpec& spec, const RenderQuery& query, const RenderLimits& limits) {
    if (query.count("mesh") > limits.max_objects) {
        throw InvalidParameter("mesh", "at most " + std::to_string(limits.max_objects) +
                                           " meshes, got " + std::to_string(query.count("mesh")));
    }
    // One base color for every mesh of the query: the GET form's meshes are one product, and a
    // colour variant recolours all of it (as objects[i].base_color does one object).
    std::optional<glm::dvec3> base_color;
    if (const std::string* color = query_value(query, "base_color")) {
        if (query.count("mesh") == 0) {
            throw InvalidParameter("base_color",
                                   "needs a mesh: it sets the base color of every mesh of the "
                                   "query, and there is none");
        }
        base_color = parse_vector3("base_color", *color, kColor.low, kColor.high);
    }
    // Likewise one variant: the product's colourway.
    std::optional<std::string> variant;
    if (const std::string* name = query_value(query, "variant")) {
        if (query.count("mesh") == 0) {
            throw InvalidParameter("variant",
                                   "needs a mesh: it chooses the variant of every mesh of the "
                                   "query, and there is none");
        }
        variant = checked_name("variant", *name);
    }
    std::optional<std::string> material;
    if (const std::string* name = query_value(query, "base_color_material")) {
        if (!base_color) {
            throw InvalidParameter("base_color_material",
                                   "needs base_color: it names the material base_color recolours");
        }
        material = checked_name("base_color_material", *name);
    }
    const auto [first_mesh, last_mesh] = query.equal_range("mesh");
    for (auto mesh = first_mesh; mesh != last_mesh; ++mesh) {
        spec.objects.push_back(
            {checked_id("mesh", mesh->second), glm::dmat4(1.0), base_color, material, variant});
    }
}

Json objects_json(const std::vector<ObjectSpec>& objects) {
    Json list = Json::array();
    for (const ObjectSpec& object : objects) {
        Json transform = Json::array();
        for (int i = 0; i < 16; ++i) {
            transform.push_back(canonical(object.transform[i / 4][i % 4]));
        }
        Json json = {{"mesh", object.mesh}, {"transform", std::move(transform)}};
        if (object.base_color) {
            json["base_color"] = vector_json(*object.base_color);
        }
        if (object.base_color_material) {
            json["base_color_material"] = *object.base_color_material;
        }
        if (object.variant) {
            json["variant"] = *object.variant;
        }
        list.push_back(std::move(json));
    }
    return list;
}

CameraSpec json_camera(const Json& value, const std::string& path) {
    require_object(value, path, render_member_names("camera"));
    CameraSpec camera;
    if (const Json* asset = find(value, "asset")) {
        for (const std::string_view name : {"eye", "target", "up", "orbit", "fov_y"}) {
            if (find(value, name)) {
                reader().fail(child(path, name),
                              "an asset camera has its own placement and field of view: not "
                              "with asset");
            }
        }
        camera.placement = json_asset_camera(*asset, child(path, "asset"));
        return camera;
    }
    if (const Json* fov_y = find(value, "fov_y")) {
        camera.fov_y = json_number(*fov_y, child(path, "fov_y"), kFovY);
    }
    if (const Json* orbit = find(value, "orbit")) {
        for (const std::string_view name : {"eye", "target", "up"}) {
            if (find(value, name)) {
                reader().fail(child(path, name), "a camera has eye and target, or orbit, not both");
            }
        }
        camera.placement = json_orbit(*orbit, child(path, "orbit"));
        return camera;
    }
    camera.placement = json_look_at(value, path, camera.fov_y);
    return camera;
}

std::optional<CameraSpec> query_camera(const RenderQuery& query) {
    const auto given = [&query](std::string_view name) { return query_value(query, name); };
    if (const std::string* asset = given("camera")) {
        for (const std::string_view name :
             {"eye", "target", "up", "yaw", "pitch", "distance", "fov_y"}) {
            if (given(name)) {
                throw InvalidParameter(std::string(name),
                                       "camera=asset:... places the camera and gives its field "
                                       "of view: not with " +
                                           std::string(name));
            }
        }
        return CameraSpec{query_asset_camera(*asset)};
    }
    const bool orbit = given("yaw") || given("pitch") || given("distance");
    if (orbit && (given("eye") || given("up"))) {
        throw InvalidParameter(given("eye") ? "eye" : "up",
                               "a camera has eye and target, or an orbit (yaw, pitch, distance), "
                               "not both");
    }
    if (!orbit && !given("eye") && !given("target") && !given("up")) {
        if (given("fov_y")) {
            throw InvalidParameter("fov_y",
                                   "needs a camera: eye and target, or yaw, pitch and distance");
        }
        return std::nullopt;
    }
    CameraSpec camera;
    if (const std::string* fov_y = given("fov_y")) {
        camera.fov_y = parse_number("fov_y", *fov_y, kFovY.low, kFovY.high);
    }
    if (orbit) {
        camera.placement = query_orbit(query);
    } else {
        camera.placement = query_look_at(query, camera.fov_y);
    }
    return camera;
}

Json camera_json(const CameraSpec& camera) {
    Json json;
    if (const auto* asset = std::get_if<AssetCameraSpec>(&camera.placement)) {
        // Its own field of view, from the mesh the document names by id: none written.
        std::visit([&json](const auto& index_or_name) { json["asset"] = index_or_name; },
                   asset->index_or_name);
        return json;
    }
    if (const auto* look_at = std::get_if<LookAtSpec>(&camera.placement)) {
        json = {{"eye", vector_json(look_at->eye)},
                {"target", vector_json(look_at->target)},
                {"up", vector_json(look_at->up)}};
    } else {
        const OrbitSpec& orbit = std::get<OrbitSpec>(camera.placement);
        json["orbit"] = {{"yaw", canonical(orbit.yaw)}, {"pitch", canonical(orbit.pitch)}};
        // Absent stays absent: the automatic framing's target and distance depend on the
        // meshes, which the canonical document names by id.
        if (orbit.distance) {
            json["orbit"]["distance"] = canonical(*orbit.distance);
        }
        if (orbit.target) {
            json["orbit"]["target"] = vector_json(*orbit.target);
        }
    }
    json["fov_y"] = canonical(camera.fov_y);
    return json;
}

Camera to_camera(const LookAtSpec& look_at, double fov_y) {
    return {glm::vec3(look_at.eye), glm::vec3(look_at.target), glm::vec3(look_at.up), float(fov_y)};
}

void read_json_lights(RenderSpec& spec, const Json& value, const std::string& path,
                      const RenderLimits& limits) {
    require_array(value, path, limits.max_lights);
    for (std::size_t i = 0; i < value.size(); ++i) {
        spec.lights.push_back(json_light_weight(value[i], child(path, i)));
    }
}

// Weights as numbers, so that [true, false] and [1, 0] are one request.
Json lights_json(const std::vector<double>& lights) {
    Json list = Json::array();
    for (const double weight : lights) {
        list.push_back(canonical(weight));
    }
    return list;
}

}  // namespace oer::api::render_members
