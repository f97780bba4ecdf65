#include "oer/api/render_request.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <span>

#include <glm/matrix.hpp>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/version.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/enum_names.hpp"

namespace oer::api {

namespace {

using Json = nlohmann::json;

constexpr EnumNames<ImageFormat, 3> kFormatNames = {
    {{ImageFormat::Jpeg, "jpeg"}, {ImageFormat::Png, "png"}, {ImageFormat::Exr, "exr"}}};
constexpr EnumNames<ShadowFilter, 2> kFilterNames = {
    {{ShadowFilter::Pcf, "pcf"}, {ShadowFilter::Hard, "hard"}}};
constexpr EnumNames<Bounce, 2> kBounceNames = {{{Bounce::None, "none"}, {Bounce::One, "one"}}};

// The ranges both forms check, and api/openapi.yaml states.
struct Range {
    double low;
    double high;
};
constexpr Range kCoordinate{-kMaxCoordinate, kMaxCoordinate};
constexpr Range kFovY{1.0, 179.0};
constexpr Range kAngle{-360.0, 360.0};  // orbit yaw, environment_yaw
constexpr Range kPitch{-90.0, 90.0};
constexpr Range kDistance{1e-4, 1e6};
constexpr Range kExposure{-64.0, 64.0};  // the renderer's limit
constexpr Range kColor{0.0, 1.0};
constexpr Range kLightWeight{0.0, kMaxLightWeight};  // the renderer's limit
constexpr int kMaxQuality = 100;
constexpr int kMinShadowResolution = 64;
// The renderer rejects transforms whose |determinant| is under this (they flatten the mesh).
constexpr double kMinDeterminant = 1e-12;

using Names = std::span<const std::string_view>;
constexpr std::array<std::string_view, 17> kBodyMembers = {
    "environment", "objects",    "ground",  "occlusion", "bounce",         "camera",
    "lights",      "width",      "height",  "format",    "quality",        "exposure",
    "tonemap",     "background", "shadows", "samples",   "environment_yaw"};
constexpr std::array<std::string_view, 3> kObjectMembers = {"mesh", "transform", "base_color"};
constexpr std::array<std::string_view, 5> kCameraMembers = {"eye", "target", "up", "fov_y",
                                                            "orbit"};
constexpr std::array<std::string_view, 4> kOrbitMembers = {"yaw", "pitch", "distance", "target"};
constexpr std::array<std::string_view, 3> kShadowMembers = {"enabled", "resolution", "filter"};
constexpr std::array<std::string_view, 26> kQueryParameters = {"environment",
                                                               "mesh",
                                                               "eye",
                                                               "target",
                                                               "up",
                                                               "fov_y",
                                                               "yaw",
                                                               "pitch",
                                                               "distance",
                                                               "lights",
                                                               "width",
                                                               "height",
                                                               "format",
                                                               "quality",
                                                               "exposure",
                                                               "tonemap",
                                                               "background",
                                                               "ground",
                                                               "occlusion",
                                                               "bounce",
                                                               "shadows",
                                                               "shadow_resolution",
                                                               "shadow_filter",
                                                               "samples",
                                                               "environment_yaw",
                                                               "base_color"};

bool contains(Names names, std::string_view name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

// The request's wording: an InvalidParameter naming the member's path ("objects/0/mesh"),
// "expected <kind>, got <JSON type>".
struct RequestWording {
    [[noreturn]] void fail(const std::string& path, const std::string& message) const {
        throw InvalidParameter(path, message);
    }
    std::string wrong_type(const std::string& expected, const Json& value) const {
        return "expected " + expected + ", got " + (value.is_null() ? "null" : value.type_name());
    }
    std::string missing() const { return "required"; }
};

const checked_json::Reader<RequestWording> read(RequestWording{}, checked_json::PathStyle::Slash);

std::string child(const std::string& path, std::string_view name) {
    return read.child(path, name);
}

std::string child(const std::string& path, std::size_t index) {
    return read.child(path, index);
}

// Checks shared by both forms, each naming the member or parameter it is given.

std::string checked_id(const std::string& name, const std::string& text) {
    if (text != kDefaultPresetId && !is_content_id(text)) {
        throw InvalidParameter(name, "expected a content id (64 lowercase hex digits) or '" +
                                         std::string(kDefaultPresetId) + "', got '" +
                                         excerpt(text) + "'");
    }
    return text;
}

int checked_resolution(const std::string& name, long long resolution) {
    if ((resolution & (resolution - 1)) != 0) {
        throw InvalidParameter(name, "must be a power of two, got " + std::to_string(resolution));
    }
    return int(resolution);
}

int checked_samples(const std::string& name, long long samples) {
    if (std::find(kSampleCounts.begin(), kSampleCounts.end(), samples) == kSampleCounts.end()) {
        throw InvalidParameter(name, "must be 1, 2, 4 or 8, got " + std::to_string(samples));
    }
    return int(samples);
}

void check_transform(const std::string& name, const glm::dmat4& transform) {
    if (std::abs(glm::determinant(transform)) < kMinDeterminant) {
        throw InvalidParameter(name, "must be invertible (its determinant is 0 or nearly)");
    }
}

Camera to_camera(const LookAtSpec& look_at, double fov_y) {
    return {glm::vec3(look_at.eye), glm::vec3(look_at.target), glm::vec3(look_at.up), float(fov_y)};
}

void check_look_at(const std::string& name, const LookAtSpec& look_at, double fov_y) {
    try {
        validate_camera(to_camera(look_at, fov_y));
    } catch (const Error& error) {
        throw InvalidParameter(name, error.what());
    }
}

// The JSON form: each reader checks the type first, then the value, naming the member's path.

double json_number(const Json& value, const std::string& path, Range range) {
    const double number = read.number(value, path);
    if (!(number >= range.low && number <= range.high)) {
        read.fail(path, "must be in [" + number_text(range.low) + ", " + number_text(range.high) +
                            "], got " + excerpt(value.dump()));
    }
    return number;
}

// Frame sides beyond this are nonsense rather than over a configured limit.
constexpr long long kLargestSide = 1 << 20;

// A frame side over the configured limit is a size limit (HTTP 413), not a malformed value.
int within_frame_limit(const std::string& name, long long value, int limit) {
    if (value > limit) {
        throw InvalidParameter(
            name, std::to_string(value) + " is over the limit of " + std::to_string(limit),
            ErrorKind::LimitExceeded);
    }
    return int(value);
}

long long json_integer(const Json& value, const std::string& path, long long low, long long high) {
    const double number = read.expect(value, value.is_number(), path, "an integer").get<double>();
    if (number != std::floor(number)) {
        read.fail(path, "expected an integer, got " + excerpt(value.dump()));
    }
    if (!(number >= double(low) && number <= double(high))) {
        read.fail(path, "must be in " + std::to_string(low) + ".." + std::to_string(high) +
                            ", got " + excerpt(value.dump()));
    }
    return static_cast<long long>(number);
}

bool json_bool(const Json& value, const std::string& path) {
    return read.boolean(value, path, "true or false");
}

// A light's weight (docs/design.md section 2, dimmable lights): true and false, the on/off form,
// are 1 and 0.
double json_light_weight(const Json& value, const std::string& path) {
    if (value.is_boolean()) {
        return value.get<bool>() ? 1.0 : 0.0;
    }
    return json_number(value, path, kLightWeight);
}

const std::string& json_string(const Json& value, const std::string& path) {
    return read.string(value, path);
}

void require_array(const Json& value, const std::string& path, std::size_t max_size) {
    read.array(value, path);
    if (value.size() > max_size) {
        read.fail(path, "at most " + std::to_string(max_size) + " entries, got " +
                            std::to_string(value.size()));
    }
}

glm::dvec3 json_vector3(const Json& value, const std::string& path, Range range) {
    if (!value.is_array() || value.size() != 3) {
        read.fail(path, "expected an array of 3 numbers");
    }
    glm::dvec3 v{0.0};
    for (std::size_t i = 0; i < 3; ++i) {
        v[int(i)] = json_number(value[i], child(path, i), range);
    }
    return v;
}

// An object whose members are all among `names`; path "" is the body itself.
void require_object(const Json& value, const std::string& path, Names names) {
    read.object(value, path.empty() ? "body" : path);
    if (const std::string* unknown = read.unknown_member(value, names)) {
        std::string known;
        for (const std::string_view name : names) {
            known += (known.empty() ? "" : ", ") + std::string(name);
        }
        read.fail(child(path, excerpt(*unknown)), "unknown member; expected one of " + known);
    }
}

const Json* find(const Json& object, std::string_view name) {
    return checked_json::find(object, name);
}

// What a valid body can hold, checked while it is parsed, so that a body of many small values
// costs no more than a valid one. A valid body nests 4 levels deep (body, camera, orbit,
// target); its values are: 23 per object (the object, its mesh, its transform array and 16
// numbers, its base_color array and 3 numbers), one per light switch, and 42 others (the body,
// its 13 scalar members, the objects and lights arrays, the camera's 22 with its vectors and
// orbit, shadows' 4): under 64.
checked_json::JsonBounds request_bounds(const RenderLimits& limits) {
    checked_json::JsonBounds bounds;
    bounds.max_depth = 16;
    bounds.max_elements = 64 + 23 * limits.max_objects + limits.max_lights;
    return bounds;
}

Json read_body(std::string_view body, const RenderLimits& limits) {
    if (body.size() > limits.max_body_bytes) {
        throw Error(ErrorKind::LimitExceeded,
                    "render request: the body has " + std::to_string(body.size()) +
                        " bytes, over the limit of " + std::to_string(limits.max_body_bytes));
    }
    try {
        return checked_json::parse_bounded(body, request_bounds(limits));
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

ObjectSpec json_object_spec(const Json& value, const std::string& path) {
    require_object(value, path, kObjectMembers);
    ObjectSpec object;
    const Json& mesh = read.member(value, path, "mesh");
    object.mesh = checked_id(child(path, "mesh"), json_string(mesh, child(path, "mesh")));
    if (const Json* transform = find(value, "transform")) {
        const std::string transform_path = child(path, "transform");
        if (!transform->is_array() || transform->size() != 16) {
            read.fail(transform_path,
                      "expected an array of 16 numbers (a column-major 4x4 matrix)");
        }
        for (std::size_t i = 0; i < 16; ++i) {
            object.transform[int(i / 4)][int(i % 4)] =
                json_number((*transform)[i], child(transform_path, i), kCoordinate);
        }
        check_transform(transform_path, object.transform);
    }
    if (const Json* color = find(value, "base_color")) {
        object.base_color = json_vector3(*color, child(path, "base_color"), kColor);
    }
    return object;
}

CameraSpec json_camera(const Json& value, const std::string& path) {
    require_object(value, path, kCameraMembers);
    CameraSpec camera;
    if (const Json* fov_y = find(value, "fov_y")) {
        camera.fov_y = json_number(*fov_y, child(path, "fov_y"), kFovY);
    }
    if (const Json* orbit_json = find(value, "orbit")) {
        for (const std::string_view name : {"eye", "target", "up"}) {
            if (find(value, name)) {
                read.fail(child(path, name), "a camera has eye and target, or orbit, not both");
            }
        }
        const std::string orbit_path = child(path, "orbit");
        require_object(*orbit_json, orbit_path, kOrbitMembers);
        OrbitSpec orbit;
        if (const Json* yaw = find(*orbit_json, "yaw")) {
            orbit.yaw = json_number(*yaw, child(orbit_path, "yaw"), kAngle);
        }
        if (const Json* pitch = find(*orbit_json, "pitch")) {
            orbit.pitch = json_number(*pitch, child(orbit_path, "pitch"), kPitch);
        }
        if (const Json* distance = find(*orbit_json, "distance")) {
            orbit.distance = json_number(*distance, child(orbit_path, "distance"), kDistance);
        }
        if (const Json* target = find(*orbit_json, "target")) {
            orbit.target = json_vector3(*target, child(orbit_path, "target"), kCoordinate);
        }
        camera.placement = orbit;
        return camera;
    }
    const Json* eye = find(value, "eye");
    const Json* target = find(value, "target");
    if (!eye || !target) {
        read.fail(child(path, eye ? "target" : "eye"),
                  "required: a camera has eye and target, or orbit");
    }
    LookAtSpec look_at;
    look_at.eye = json_vector3(*eye, child(path, "eye"), kCoordinate);
    look_at.target = json_vector3(*target, child(path, "target"), kCoordinate);
    if (const Json* up = find(value, "up")) {
        look_at.up = json_vector3(*up, child(path, "up"), kCoordinate);
    }
    check_look_at(path, look_at, camera.fov_y);
    camera.placement = look_at;
    return camera;
}

ShadowOptions json_shadows(const Json& value, const std::string& path, const RenderLimits& limits) {
    require_object(value, path, kShadowMembers);
    ShadowOptions shadows;
    if (const Json* enabled = find(value, "enabled")) {
        shadows.enabled = json_bool(*enabled, child(path, "enabled"));
    }
    if (const Json* resolution = find(value, "resolution")) {
        const std::string name = child(path, "resolution");
        shadows.resolution = checked_resolution(
            name,
            json_integer(*resolution, name, kMinShadowResolution, limits.max_shadow_resolution));
    }
    if (const Json* filter = find(value, "filter")) {
        const std::string name = child(path, "filter");
        shadows.filter = parse_enum(name, json_string(*filter, name), shadow_filter_from_string);
    }
    return shadows;
}

// The GET form: camera parameters.
using Lookup = std::function<const std::string*(std::string_view)>;

std::optional<CameraSpec> query_camera(const Lookup& get) {
    const bool orbit = get("yaw") || get("pitch") || get("distance");
    if (orbit && (get("eye") || get("up"))) {
        throw InvalidParameter(get("eye") ? "eye" : "up",
                               "a camera has eye and target, or an orbit (yaw, pitch, distance), "
                               "not both");
    }
    if (!orbit && !get("eye") && !get("target") && !get("up")) {
        if (get("fov_y")) {
            throw InvalidParameter("fov_y",
                                   "needs a camera: eye and target, or yaw, pitch and distance");
        }
        return std::nullopt;
    }
    CameraSpec camera;
    if (const std::string* fov_y = get("fov_y")) {
        camera.fov_y = parse_number("fov_y", *fov_y, kFovY.low, kFovY.high);
    }
    if (orbit) {
        OrbitSpec spec;
        if (const std::string* yaw = get("yaw")) {
            spec.yaw = parse_number("yaw", *yaw, kAngle.low, kAngle.high);
        }
        if (const std::string* pitch = get("pitch")) {
            spec.pitch = parse_number("pitch", *pitch, kPitch.low, kPitch.high);
        }
        if (const std::string* distance = get("distance")) {
            spec.distance = parse_number("distance", *distance, kDistance.low, kDistance.high);
        }
        if (const std::string* target = get("target")) {
            spec.target = parse_vector3("target", *target, kCoordinate.low, kCoordinate.high);
        }
        camera.placement = spec;
        return camera;
    }
    if (!get("eye") || !get("target")) {
        throw InvalidParameter(get("eye") ? "target" : "eye",
                               "required: a camera has eye and target, or yaw, pitch and distance");
    }
    LookAtSpec look_at;
    look_at.eye = parse_vector3("eye", *get("eye"), kCoordinate.low, kCoordinate.high);
    look_at.target = parse_vector3("target", *get("target"), kCoordinate.low, kCoordinate.high);
    if (const std::string* up = get("up")) {
        look_at.up = parse_vector3("up", *up, kCoordinate.low, kCoordinate.high);
    }
    check_look_at("eye", look_at, camera.fov_y);
    camera.placement = look_at;
    return camera;
}

// Canonical numbers: -0 and 0 are one value.
double canonical(double value) {
    return value + 0.0;
}

Json vector_json(const glm::dvec3& v) {
    return Json::array({canonical(v.x), canonical(v.y), canonical(v.z)});
}

Json camera_json(const CameraSpec& camera) {
    Json json;
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

// The orbit's missing target or distance from the automatic framing of `scene` (the objects'
// enclosing bounds), as the renderer frames a request without a camera (frame_context.cpp): the
// same bounds, in float, at the frame's aspect ratio (width / height, never the size in pixels).
Camera resolved_orbit(const OrbitSpec& orbit, float fov_y, const Bounds& scene, float aspect) {
    const std::optional<glm::vec3> target =
        orbit.target ? std::optional<glm::vec3>(glm::vec3(*orbit.target)) : std::nullopt;
    const std::optional<float> distance =
        orbit.distance ? std::optional<float>(float(*orbit.distance)) : std::nullopt;
    return frame_orbit(float(orbit.yaw), float(orbit.pitch), target, distance, scene, fov_y,
                       aspect);
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
        const auto add = [&list](const std::string& parent, Names names) {
            for (const std::string_view name : names) {
                list.push_back(child(parent, name));
            }
        };
        add("", kBodyMembers);
        add("objects/*", kObjectMembers);
        add("camera", kCameraMembers);
        add("camera/orbit", kOrbitMembers);
        add("shadows", kShadowMembers);
        return list;
    }();
    return members;
}

const std::vector<std::string>& render_query_parameters() {
    static const std::vector<std::string> parameters(kQueryParameters.begin(),
                                                     kQueryParameters.end());
    return parameters;
}

RenderSpec parse_render_json(std::string_view body, const RenderLimits& limits) {
    const Json json = read_body(body, limits);
    require_object(json, "", kBodyMembers);
    RenderSpec spec;
    spec.environment =
        checked_id("environment", json_string(read.member(json, "", "environment"), "environment"));
    if (const Json* objects = find(json, "objects")) {
        require_array(*objects, "objects", limits.max_objects);
        for (std::size_t i = 0; i < objects->size(); ++i) {
            spec.objects.push_back(json_object_spec((*objects)[i], child("objects", i)));
        }
    }
    if (const Json* ground = find(json, "ground")) {
        spec.ground = json_bool(*ground, "ground");
    }
    if (const Json* occlusion = find(json, "occlusion")) {
        spec.occlusion = json_bool(*occlusion, "occlusion");
    }
    if (const Json* bounce = find(json, "bounce")) {
        spec.bounce = parse_enum("bounce", json_string(*bounce, "bounce"), bounce_from_string);
    }
    if (const Json* camera = find(json, "camera")) {
        spec.camera = json_camera(*camera, "camera");
    }
    if (const Json* lights = find(json, "lights")) {
        require_array(*lights, "lights", limits.max_lights);
        for (std::size_t i = 0; i < lights->size(); ++i) {
            spec.lights.push_back(json_light_weight((*lights)[i], child("lights", i)));
        }
    }
    if (const Json* width = find(json, "width")) {
        spec.width = within_frame_limit("width", json_integer(*width, "width", 1, kLargestSide),
                                        limits.max_width);
    }
    if (const Json* height = find(json, "height")) {
        spec.height = within_frame_limit("height", json_integer(*height, "height", 1, kLargestSide),
                                         limits.max_height);
    }
    if (const Json* format = find(json, "format")) {
        spec.format =
            parse_enum("format", json_string(*format, "format"), image_format_from_string);
    }
    if (const Json* quality = find(json, "quality")) {
        spec.quality = int(json_integer(*quality, "quality", 1, kMaxQuality));
    }
    if (const Json* exposure = find(json, "exposure")) {
        spec.exposure = json_number(*exposure, "exposure", kExposure);
    }
    if (const Json* tonemap = find(json, "tonemap")) {
        spec.tonemap =
            parse_enum("tonemap", json_string(*tonemap, "tonemap"), tone_mapper_from_string);
    }
    if (const Json* background = find(json, "background")) {
        spec.background = parse_background("background", json_string(*background, "background"));
    }
    if (const Json* shadows = find(json, "shadows")) {
        spec.shadows = json_shadows(*shadows, "shadows", limits);
    }
    if (const Json* samples = find(json, "samples")) {
        spec.samples =
            checked_samples("samples", json_integer(*samples, "samples", 1, kSampleCounts.back()));
    }
    if (const Json* yaw = find(json, "environment_yaw")) {
        spec.environment_yaw = json_number(*yaw, "environment_yaw", kAngle);
    }
    return spec;
}

RenderSpec parse_render_query(const std::multimap<std::string, std::string>& query,
                              const RenderLimits& limits) {
    for (auto it = query.begin(); it != query.end(); it = query.upper_bound(it->first)) {
        if (!contains(kQueryParameters, it->first)) {
            throw InvalidParameter(excerpt(it->first), "unknown parameter");
        }
        if (it->first != "mesh" && query.count(it->first) > 1) {
            throw InvalidParameter(it->first, "given more than once");
        }
    }
    const Lookup get = [&query](std::string_view name) -> const std::string* {
        const auto found = query.find(std::string(name));
        return found == query.end() ? nullptr : &found->second;
    };
    RenderSpec spec;
    const std::string* environment = get("environment");
    if (!environment) {
        throw InvalidParameter("environment", "required");
    }
    spec.environment = checked_id("environment", *environment);
    if (query.count("mesh") > limits.max_objects) {
        throw InvalidParameter("mesh", "at most " + std::to_string(limits.max_objects) +
                                           " meshes, got " + std::to_string(query.count("mesh")));
    }
    // One base color for every mesh of the query: the GET form's meshes are one product, and a
    // colour variant recolours all of it (as objects[i].base_color does one object).
    std::optional<glm::dvec3> base_color;
    if (const std::string* color = get("base_color")) {
        if (query.count("mesh") == 0) {
            throw InvalidParameter("base_color",
                                   "needs a mesh: it sets the base color of every mesh of the "
                                   "query, and there is none");
        }
        base_color = parse_vector3("base_color", *color, kColor.low, kColor.high);
    }
    const auto [first_mesh, last_mesh] = query.equal_range("mesh");
    for (auto mesh = first_mesh; mesh != last_mesh; ++mesh) {
        spec.objects.push_back({checked_id("mesh", mesh->second), glm::dmat4(1.0), base_color});
    }
    spec.camera = query_camera(get);
    if (const std::string* lights = get("lights")) {
        spec.lights = parse_light_list(*lights, limits.max_lights);
    }
    if (const std::string* width = get("width")) {
        spec.width = within_frame_limit("width", parse_integer("width", *width, 1, kLargestSide),
                                        limits.max_width);
    }
    if (const std::string* height = get("height")) {
        spec.height = within_frame_limit(
            "height", parse_integer("height", *height, 1, kLargestSide), limits.max_height);
    }
    if (const std::string* format = get("format")) {
        spec.format = parse_enum("format", *format, image_format_from_string);
    }
    if (const std::string* quality = get("quality")) {
        spec.quality = int(parse_integer("quality", *quality, 1, kMaxQuality));
    }
    if (const std::string* exposure = get("exposure")) {
        spec.exposure = parse_number("exposure", *exposure, kExposure.low, kExposure.high);
    }
    if (const std::string* tonemap = get("tonemap")) {
        spec.tonemap = parse_enum("tonemap", *tonemap, tone_mapper_from_string);
    }
    if (const std::string* background = get("background")) {
        spec.background = parse_background("background", *background);
    }
    if (const std::string* ground = get("ground")) {
        spec.ground = parse_on_off("ground", *ground);
    }
    if (const std::string* occlusion = get("occlusion")) {
        spec.occlusion = parse_on_off("occlusion", *occlusion);
    }
    if (const std::string* bounce = get("bounce")) {
        spec.bounce = parse_enum("bounce", *bounce, bounce_from_string);
    }
    if (const std::string* shadows = get("shadows")) {
        spec.shadows.enabled = parse_on_off("shadows", *shadows);
    }
    if (const std::string* resolution = get("shadow_resolution")) {
        spec.shadows.resolution = checked_resolution(
            "shadow_resolution", parse_integer("shadow_resolution", *resolution,
                                               kMinShadowResolution, limits.max_shadow_resolution));
    }
    if (const std::string* filter = get("shadow_filter")) {
        spec.shadows.filter = parse_enum("shadow_filter", *filter, shadow_filter_from_string);
    }
    if (const std::string* samples = get("samples")) {
        spec.samples =
            checked_samples("samples", parse_integer("samples", *samples, 1, kSampleCounts.back()));
    }
    if (const std::string* yaw = get("environment_yaw")) {
        spec.environment_yaw = parse_number("environment_yaw", *yaw, kAngle.low, kAngle.high);
    }
    return spec;
}

nlohmann::json normalised_render_json(const RenderSpec& spec) {
    Json objects = Json::array();
    for (const ObjectSpec& object : spec.objects) {
        Json transform = Json::array();
        for (int i = 0; i < 16; ++i) {
            transform.push_back(canonical(object.transform[i / 4][i % 4]));
        }
        Json json = {{"mesh", object.mesh}, {"transform", std::move(transform)}};
        if (object.base_color) {
            json["base_color"] = vector_json(*object.base_color);
        }
        objects.push_back(std::move(json));
    }
    // Weights as numbers, so that [true, false] and [1, 0] are one request.
    Json lights = Json::array();
    for (const double weight : spec.lights) {
        lights.push_back(canonical(weight));
    }
    Json json = {{"environment", spec.environment},
                 {"objects", std::move(objects)},
                 {"ground", spec.ground},
                 {"occlusion", spec.occlusion},
                 {"bounce", to_string(spec.bounce)},
                 {"lights", std::move(lights)},
                 {"width", spec.width},
                 {"height", spec.height},
                 {"format", to_string(spec.format)},
                 {"quality", spec.quality},
                 {"exposure", canonical(spec.exposure)},
                 {"tonemap", to_string(spec.tonemap)},
                 {"background", to_string(spec.background)},
                 {"shadows",
                  {{"enabled", spec.shadows.enabled},
                   {"resolution", spec.shadows.resolution},
                   {"filter", to_string(spec.shadows.filter)}}},
                 {"samples", spec.samples},
                 {"environment_yaw", canonical(spec.environment_yaw)}};
    if (spec.camera) {
        json["camera"] = camera_json(*spec.camera);
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
    std::vector<Bounds> boxes;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        boxes.push_back(
            transformed_bounds(meshes[i]->bounds, glm::mat4(spec.objects[i].transform)));
    }
    const Bounds scene = enclosing_bounds(boxes);
    const float aspect = float(spec.width) / float(spec.height);
    if (!spec.camera) {
        return frame_bounds(scene, Camera{}.fov_y, aspect);
    }
    if (const auto* look_at = std::get_if<LookAtSpec>(&spec.camera->placement)) {
        return to_camera(*look_at, spec.camera->fov_y);
    }
    return resolved_orbit(std::get<OrbitSpec>(spec.camera->placement), float(spec.camera->fov_y),
                          scene, aspect);
}

FrameRequest to_frame_request(const RenderSpec& spec, std::shared_ptr<const Rig> rig,
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
        request.objects.push_back({meshes[i], glm::mat4(object.transform),
                                   object.base_color
                                       ? std::optional<glm::vec3>(glm::vec3(*object.base_color))
                                       : std::nullopt});
    }
    request.camera = resolved_camera(spec, meshes);
    request.lights.assign(spec.lights.begin(), spec.lights.end());
    request.width = spec.width;
    request.height = spec.height;
    request.ground = spec.ground;
    // Without objects nothing occludes the residual map: the unoccluded lighting is the same
    // frame, and there is no scene to bake a transfer for.
    request.occlusion = spec.occlusion && !spec.objects.empty();
    request.bounce = spec.bounce;
    request.background = spec.background;
    request.exposure = spec.exposure;
    request.tonemap = spec.tonemap;
    request.shadows = spec.shadows;
    request.samples = spec.samples;
    request.environment_yaw = spec.environment_yaw;
    request.linear = spec.format == ImageFormat::Exr;
    return request;
}

}  // namespace oer::api
