#include "oer/api/render_parameters.hpp"

#include <algorithm>
#include <optional>
#include <utility>

#include "oer/api/light_switches.hpp"
#include "oer/api/parameter_text.hpp"
#include "render_members.hpp"
#include "request_values.hpp"

namespace oer::api {

namespace {

using namespace request_values;

// A row's names and what it means (the start of its --help text).
struct Names {
    std::string_view json;
    std::string_view query;
    std::string_view flag;
    std::string_view meaning;
};

using TextReader = std::function<void(RenderSpec&, const std::string& text, const std::string& name,
                                      const RenderLimits&)>;
using JsonReader = std::function<void(RenderSpec&, const Json& value, const std::string& path,
                                      const RenderLimits&)>;
using FrameSetter = std::function<void(const RenderSpec&, FrameRequest&)>;

// The frame request's field that takes the spec's value as it is. A scalar row's `field` (here
// and below) is an accessor usable on a const spec and a mutable one:
// [](auto& spec) -> auto& { return spec.width; }.
template <class Field, class Target>
FrameSetter lands_in(Field field, Target FrameRequest::*target) {
    return [field, target](const RenderSpec& spec, FrameRequest& request) {
        request.*target = field(spec);
    };
}

// A row's names, spelling and help; its readers and writers are set by the caller (a
// structured member's row) or left empty (the members a structured member's reader reads).
RenderParameter member_row(const Names& names, ParameterKind kind, Presence presence,
                           std::string value_name = {}) {
    RenderParameter row{};
    row.json = names.json;
    row.query = names.query;
    row.flag = names.flag;
    row.kind = kind;
    row.presence = presence;
    row.value_name = std::move(value_name);
    row.help = names.meaning;
    return row;
}

// "x,y,z", as the query and the CLI spell a vector.
std::string vector_text(const glm::dvec3& v) {
    return number_text(v.x) + "," + number_text(v.y) + "," + number_text(v.z);
}

// The spec's defaults, for --help.
const RenderSpec& defaults() {
    static const RenderSpec spec;
    return spec;
}

// A row whose value is one JSON scalar and one query text: read by `from_json` and `from_text`,
// written to the canonical document as `value` gives it.
RenderParameter scalar_row(const Names& names, ParameterKind kind, Presence presence,
                           std::string value_name, const std::string& range, JsonReader from_json,
                           TextReader from_text, std::function<Json(const RenderSpec&)> value,
                           FrameSetter to_frame) {
    RenderParameter row = member_row(names, kind, presence, std::move(value_name));
    row.help += range;
    row.read_json = std::move(from_json);
    row.read_query = [name = std::string(names.query), presence, from_text = std::move(from_text)](
                         RenderSpec& spec, const RenderQuery& query, const RenderLimits& limits) {
        if (const std::string* text = query_value(query, name)) {
            from_text(spec, *text, name, limits);
        } else if (presence == Presence::Required) {
            throw InvalidParameter(name, "required");
        }
    };
    row.write_canonical = [pointer = Json::json_pointer("/" + std::string(names.json)),
                           value = std::move(value)](const RenderSpec& spec, Json& document) {
        document[pointer] = value(spec);
    };
    row.to_frame = std::move(to_frame);
    return row;
}

// ", in [low, high], default D" for --help.
std::string range_help(Range range, std::optional<double> fallback) {
    return ", in [" + number_text(range.low) + ", " + number_text(range.high) + "]" +
           (fallback ? ", default " + number_text(*fallback) : "");
}

template <class Field>
RenderParameter number_row(const Names& names, Field field, Range range, FrameSetter to_frame) {
    const std::string help = range_help(range, field(defaults()));
    return scalar_row(
        names, ParameterKind::Number, Presence::Defaulted, "NUMBER", help,
        [field, range](RenderSpec& spec, const Json& value, const std::string& path,
                       const RenderLimits&) { field(spec) = json_number(value, path, range); },
        [field, range](RenderSpec& spec, const std::string& text, const std::string& name,
                       const RenderLimits&) {
            field(spec) = parse_number(name, text, range.low, range.high);
        },
        [field](const RenderSpec& spec) { return Json(canonical(field(spec))); },
        std::move(to_frame));
}

// An integer in [low, high(limits)], then held to `check` (a power of two, a frame limit).
using IntegerCheck = std::function<int(const std::string& name, long long, const RenderLimits&)>;
using IntegerBound = std::function<long long(const RenderLimits&)>;

template <class Field>
RenderParameter integer_row(const Names& names, Field field, long long low, IntegerBound high,
                            IntegerCheck check, FrameSetter to_frame) {
    return scalar_row(
        names, ParameterKind::Integer, Presence::Defaulted, "INTEGER",
        ", default " + std::to_string(field(defaults())),
        [field, low, high, check](RenderSpec& spec, const Json& value, const std::string& path,
                                  const RenderLimits& limits) {
            field(spec) = check(path, json_integer(value, path, low, high(limits)), limits);
        },
        [field, low, high, check](RenderSpec& spec, const std::string& text,
                                  const std::string& name, const RenderLimits& limits) {
            field(spec) = check(name, parse_integer(name, text, low, high(limits)), limits);
        },
        [field](const RenderSpec& spec) { return Json(field(spec)); }, std::move(to_frame));
}

IntegerBound fixed(long long high) {
    return [high](const RenderLimits&) { return high; };
}

int any_integer(const std::string&, long long value, const RenderLimits&) {
    return int(value);
}

template <class Field>
RenderParameter boolean_row(const Names& names, Field field, FrameSetter to_frame) {
    return scalar_row(
        names, ParameterKind::Boolean, Presence::Defaulted, "on|off",
        field(defaults()) ? ", default on" : ", default off",
        [field](RenderSpec& spec, const Json& value, const std::string& path, const RenderLimits&) {
            field(spec) = json_bool(value, path);
        },
        [field](RenderSpec& spec, const std::string& text, const std::string& name,
                const RenderLimits&) { field(spec) = parse_on_off(name, text); },
        [field](const RenderSpec& spec) { return Json(field(spec)); }, std::move(to_frame));
}

// A value spelled as one string in both forms (an enum's name, a background, an id): `parse`
// reads it, naming the member or parameter, `print` gives its canonical text.
template <class Field, class Parse, class Print>
RenderParameter text_row(const Names& names, Presence presence, std::string value_name, Field field,
                         Parse parse, Print print, FrameSetter to_frame) {
    const std::string help =
        presence == Presence::Defaulted ? ", default " + print(field(defaults())) : "";
    return scalar_row(
        names, ParameterKind::Name, presence, std::move(value_name), help,
        [field, parse](RenderSpec& spec, const Json& value, const std::string& path,
                       const RenderLimits&) {
            field(spec) = parse(path, json_string(value, path));
        },
        [field, parse](RenderSpec& spec, const std::string& text, const std::string& name,
                       const RenderLimits&) { field(spec) = parse(name, text); },
        [field, print](const RenderSpec& spec) { return Json(print(field(spec))); },
        std::move(to_frame));
}

// An enum by its names (the renderer's or the api's *_from_string and to_string).
template <class Enum>
auto enum_parser(Enum (*from_string)(const std::string&)) {
    return [from_string](const std::string& name, const std::string& text) {
        return parse_enum(name, text, from_string);
    };
}

template <class Enum>
auto enum_printer() {
    return [](Enum value) { return to_string(value); };
}

// The members of the object at `path` (a row's path, "" the body), each read by its row in the
// table's order: unknown members and missing required ones are errors.
void read_json_members(RenderSpec& spec, const Json& object, const std::string& path,
                       const RenderLimits& limits);

}  // namespace

namespace {

std::vector<RenderParameter> scene_rows() {
    std::vector<RenderParameter> rows;
    RenderParameter environment = text_row(
        {"environment", "environment", "", "the environment: a rig's content id or 'default'"},
        Presence::Required, "ID", [](auto& spec) -> auto& { return spec.environment; }, checked_id,
        [](const std::string& id) { return id; }, nullptr);
    environment.kind = ParameterKind::ContentId;
    rows.push_back(std::move(environment));
    RenderParameter objects =
        member_row({"objects", "", "", "the objects, each a mesh placed in the scene"},
                   ParameterKind::ObjectArray, Presence::Optional);
    objects.read_json = render_members::read_json_objects;
    objects.read_query = render_members::read_query_objects;
    objects.write_canonical = [](const RenderSpec& spec, Json& document) {
        document["objects"] = render_members::objects_json(spec.objects);
    };
    rows.push_back(std::move(objects));
    RenderParameter mesh =
        member_row({"objects/*/mesh", "mesh", "", "an object's mesh: a content id or 'default'"},
                   ParameterKind::ContentId, Presence::Required, "ID");
    mesh.repeatable = true;
    rows.push_back(std::move(mesh));
    rows.push_back(member_row({"objects/*/transform", "", "",
                               "world from mesh, a column-major 4x4 matrix, default identity"},
                              ParameterKind::Matrix, Presence::Defaulted));
    rows.push_back(
        member_row({"objects/*/base_color", "base_color", "base-color",
                    "linear RGB of every mesh, each in [" + number_text(kColor.low) + ", " +
                        number_text(kColor.high) + "]; default: the meshes' materials"},
                   ParameterKind::Vector3, Presence::Optional, "R,G,B"));
    rows.push_back(
        member_row({"objects/*/base_color_material", "base_color_material", "base-color-material",
                    "the name of the materials base_color recolours, in every mesh; "
                    "default: every material"},
                   ParameterKind::Text, Presence::Optional, "NAME"));
    rows.push_back(member_row({"objects/*/variant", "variant", "variant",
                               "the name of one of the mesh's KHR_materials_variants, for every "
                               "mesh; default: the file's default materials"},
                              ParameterKind::Text, Presence::Optional, "NAME"));
    return rows;
}

std::vector<RenderParameter> lighting_switch_rows() {
    std::vector<RenderParameter> rows;
    const auto ground = [](auto& spec) -> auto& {
        return spec.ground;
    };
    rows.push_back(scalar_row(
        {"ground", "ground", "ground",
         "the ground plane under the scene: on (an opaque floor), shadow (invisible but for the "
         "objects' shadows, over the background) or off"},
        ParameterKind::Switch, Presence::Defaulted, "on|off|shadow", ", default on",
        [ground](RenderSpec& spec, const Json& value, const std::string& path,
                 const RenderLimits&) {
            if (value.is_boolean()) {
                ground(spec) = value.get<bool>() ? GroundChoice::Opaque : GroundChoice::Off;
            } else if (value.is_string() && value.get<std::string>() == "shadow") {
                ground(spec) = GroundChoice::Shadow;
            } else {
                reader().fail(path, "expected true, false or \"shadow\"");
            }
        },
        [ground](RenderSpec& spec, const std::string& text, const std::string& name,
                 const RenderLimits&) {
            ground(spec) = parse_enum(name, text, ground_choice_from_string);
        },
        [ground](const RenderSpec& spec) {
            return ground(spec) == GroundChoice::Shadow
                       ? Json("shadow")
                       : Json(ground(spec) == GroundChoice::Opaque);
        },
        [ground](const RenderSpec& spec, FrameRequest& request) {
            request.ground = ground(spec) != GroundChoice::Off;
            request.ground_look = ground(spec) == GroundChoice::Shadow ? GroundLook::ShadowCatcher
                                                                       : GroundLook::Opaque;
        }));
    // Without objects nothing occludes the residual map: the unoccluded lighting is the same
    // frame, and there is no scene to bake a transfer for.
    rows.push_back(boolean_row(
        {"occlusion", "occlusion", "occlusion",
         "the residual lighting occluded by the objects (off: unoccluded)"},
        [](auto& spec) -> auto& { return spec.occlusion; },
        [](const RenderSpec& spec, FrameRequest& request) {
            request.occlusion = spec.occlusion && !spec.objects.empty();
        }));
    rows.push_back(text_row(
        {"bounce", "bounce", "bounce", "light reflected between ground and objects: none or one"},
        Presence::Defaulted, "none|one", [](auto& spec) -> auto& { return spec.bounce; },
        enum_parser(bounce_from_string), enum_printer<Bounce>(),
        lands_in(
            [](auto& spec) -> auto& { return spec.bounce; }, &FrameRequest::bounce)));
    return rows;
}

RenderParameter camera_row() {
    RenderParameter camera =
        member_row({"camera", "", "", "the camera; without one, the scene is framed automatically"},
                   ParameterKind::Object, Presence::Optional);
    camera.read_json = [](RenderSpec& spec, const Json& value, const std::string& path,
                          const RenderLimits&) {
        spec.camera = render_members::json_camera(value, path);
    };
    camera.read_query = [](RenderSpec& spec, const RenderQuery& query, const RenderLimits&) {
        spec.camera = render_members::query_camera(query);
    };
    camera.write_canonical = [](const RenderSpec& spec, Json& document) {
        if (spec.camera) {
            document["camera"] = render_members::camera_json(*spec.camera);
        }
    };
    return camera;
}

std::vector<RenderParameter> camera_rows() {
    std::vector<RenderParameter> rows;
    rows.push_back(camera_row());
    const auto vector = [](const Names& names, Presence presence) {
        return member_row(names, ParameterKind::Vector3, presence, "X,Y,Z");
    };
    // The orbit's defaults are oer::Orbit's; an absent distance is the automatic framing's.
    const auto number = [](const Names& names, Range range, std::optional<double> fallback) {
        RenderParameter row =
            member_row(names, ParameterKind::Number,
                       fallback ? Presence::Defaulted : Presence::Optional, "NUMBER");
        row.help += range_help(range, fallback);
        return row;
    };
    rows.push_back(
        vector({"camera/eye", "eye", "eye", "the look-at camera's position"}, Presence::Required));
    rows.push_back(vector({"camera/target", "target", "target", "the point the camera looks at"},
                          Presence::Required));
    rows.push_back(vector({"camera/up", "up", "up",
                           "the camera's up direction, default " + vector_text(LookAtSpec{}.up)},
                          Presence::Defaulted));
    rows.push_back(number({"camera/fov_y", "fov_y", "fov", "vertical field of view in degrees"},
                          kFovY, CameraSpec{}.fov_y));
    rows.push_back(member_row({"camera/orbit", "", "", "an orbit about a target"},
                              ParameterKind::Object, Presence::Optional));
    rows.push_back(number({"camera/orbit/yaw", "yaw", "", "the orbit's yaw in degrees"}, kAngle,
                          OrbitSpec{}.yaw));
    rows.push_back(number({"camera/orbit/pitch", "pitch", "", "the orbit's pitch in degrees"},
                          kPitch, OrbitSpec{}.pitch));
    rows.push_back(number({"camera/orbit/distance", "distance", "",
                           "the orbit's distance; default: the automatic framing's"},
                          kDistance, std::nullopt));
    rows.push_back(vector({"camera/orbit/target", "target", "",
                           "the orbit's centre; default: the automatic framing's"},
                          Presence::Optional));
    rows.push_back(member_row({"camera/asset", "camera", "camera",
                               "one of the asset's own cameras, of the first object's mesh: "
                               "asset:N (its index in the mesh's cameras) or asset:NAME"},
                              ParameterKind::AssetCamera, Presence::Optional,
                              "asset:N|asset:NAME"));
    return rows;
}

RenderParameter lights_row() {
    RenderParameter lights =
        member_row({"lights", "lights", "lights",
                    "one weight per light of the environment, each in [0, " +
                        number_text(kMaxLightWeight) + "] (0 off, 1 as captured); default: all 1"},
                   ParameterKind::Weights, Presence::Optional, "W,W,...");
    lights.read_json = render_members::read_json_lights;
    lights.read_query = [](RenderSpec& spec, const RenderQuery& query, const RenderLimits& limits) {
        if (const std::string* text = query_value(query, "lights")) {
            spec.lights = parse_light_list(*text, limits.max_lights);
        }
    };
    lights.write_canonical = [](const RenderSpec& spec, Json& document) {
        document["lights"] = render_members::lights_json(spec.lights);
    };
    lights.to_frame = [](const RenderSpec& spec, FrameRequest& request) {
        request.lights.assign(spec.lights.begin(), spec.lights.end());
    };
    return lights;
}

std::vector<RenderParameter> frame_size_rows() {
    std::vector<RenderParameter> rows;
    const auto side = [](const Names& names, auto field, int RenderLimits::*limit,
                         FrameSetter to_frame) {
        return integer_row(
            names, field, 1, fixed(kLargestSide),
            [limit](const std::string& name, long long value, const RenderLimits& limits) {
                return within_frame_limit(name, value, limits.*limit);
            },
            std::move(to_frame));
    };
    const auto width = [](auto& spec) -> auto& {
        return spec.width;
    };
    const auto height = [](auto& spec) -> auto& {
        return spec.height;
    };
    rows.push_back(side({"width", "width", "", "frame width in pixels"}, width,
                        &RenderLimits::max_width, lands_in(width, &FrameRequest::width)));
    rows.push_back(side({"height", "height", "", "frame height in pixels"}, height,
                        &RenderLimits::max_height, lands_in(height, &FrameRequest::height)));
    return rows;
}

// How the frame is exposed, tone mapped and encoded.
std::vector<RenderParameter> image_rows() {
    std::vector<RenderParameter> rows;
    rows.push_back(text_row(
        {"format", "format", "", "the image's encoding"}, Presence::Defaulted, "jpeg|png|exr",
        [](auto& spec) -> auto& { return spec.format; }, enum_parser(image_format_from_string),
        enum_printer<ImageFormat>(),
        [](const RenderSpec& spec, FrameRequest& request) {
            request.linear = spec.format == ImageFormat::Exr;
        }));
    rows.push_back(integer_row(
        {"quality", "quality", "quality", "JPEG quality"},
        [](auto& spec) -> auto& { return spec.quality; }, 1, fixed(kMaxQuality), any_integer,
        nullptr));
    const auto exposure = [](auto& spec) -> auto& {
        return spec.exposure;
    };
    rows.push_back(number_row({"exposure", "exposure", "exposure", "exposure in EV"}, exposure,
                              kExposure, lands_in(exposure, &FrameRequest::exposure)));
    const auto tonemap = [](auto& spec) -> auto& {
        return spec.tonemap;
    };
    rows.push_back(text_row({"tonemap", "tonemap", "tonemap", "the tone mapper"},
                            Presence::Defaulted, "NAME", tonemap,
                            enum_parser(tone_mapper_from_string), enum_printer<ToneMapper>(),
                            lands_in(tonemap, &FrameRequest::tonemap)));
    const auto background = [](auto& spec) -> auto& {
        return spec.background;
    };
    rows.push_back(text_row(
        {"background", "background", "background", "behind the scene: env, transparent or a color"},
        Presence::Defaulted, "env|transparent|#rrggbb", background, parse_background,
        [](const Background& value) { return to_string(value); },
        lands_in(background, &FrameRequest::background)));
    return rows;
}

std::vector<RenderParameter> shadow_rows() {
    std::vector<RenderParameter> rows;
    RenderParameter shadows = member_row({"shadows", "", "", "the lights' shadows"},
                                         ParameterKind::Object, Presence::Defaulted);
    shadows.read_json = read_json_members;
    shadows.to_frame = lands_in(
        [](auto& spec) -> auto& { return spec.shadows; }, &FrameRequest::shadows);
    rows.push_back(std::move(shadows));
    rows.push_back(boolean_row(
        {"shadows/enabled", "shadows", "shadows", "the lights' shadows"},
        [](auto& spec) -> auto& { return spec.shadows.enabled; }, nullptr));
    rows.push_back(integer_row(
        {"shadows/resolution", "shadow_resolution", "shadow-resolution",
         "the shadow map's side in texels, a power of two from " +
             std::to_string(kMinShadowResolution) + " to the service's limit"},
        [](auto& spec) -> auto& { return spec.shadows.resolution; }, kMinShadowResolution,
        [](const RenderLimits& limits) { return limits.max_shadow_resolution; },
        [](const std::string& name, long long value, const RenderLimits&) {
            return checked_resolution(name, value);
        },
        nullptr));
    rows.push_back(text_row(
        {"shadows/filter", "shadow_filter", "shadow-filter", "the shadow map's filter"},
        Presence::Defaulted, "pcf|hard", [](auto& spec) -> auto& { return spec.shadows.filter; },
        enum_parser(shadow_filter_from_string), enum_printer<ShadowFilter>(), nullptr));
    rows.push_back(number_row(
        {"shadows/softness", "shadow_softness", "shadow-softness",
         "each light's penumbra as a share of the light's own (as model-viewer's "
         "shadow-softness): 0 hard, 1 the light's size"},
        [](auto& spec) -> auto& { return spec.shadows.softness; }, kUnitInterval, nullptr));
    rows.push_back(number_row(
        {"shadows/intensity", "shadow_intensity", "shadow-intensity",
         "how dark the shadow-catching ground's shadows are (as model-viewer's "
         "shadow-intensity): 0 none, 1 all the light the objects take away"},
        [](auto& spec) -> auto& { return spec.shadows.intensity; }, kUnitInterval, nullptr));
    return rows;
}

std::vector<RenderParameter> sampling_rows() {
    std::vector<RenderParameter> rows;
    const auto samples = [](auto& spec) -> auto& {
        return spec.samples;
    };
    rows.push_back(integer_row(
        {"samples", "samples", "samples", "samples per pixel: 1, 2, 4 or 8"}, samples, 1,
        fixed(kSampleCounts.back()),
        [](const std::string& name, long long value, const RenderLimits&) {
            return checked_samples(name, value);
        },
        lands_in(samples, &FrameRequest::samples)));
    const auto yaw = [](auto& spec) -> auto& {
        return spec.environment_yaw;
    };
    rows.push_back(number_row({"environment_yaw", "environment_yaw", "yaw",
                               "the environment's rotation about +Y in degrees"},
                              yaw, kAngle, lands_in(yaw, &FrameRequest::environment_yaw)));
    return rows;
}

// "shadows" of "shadows/enabled", "" of "width".
std::string_view parent_of(std::string_view path) {
    const std::size_t slash = path.rfind('/');
    return slash == std::string_view::npos ? std::string_view() : path.substr(0, slash);
}

std::string_view member_name_of(std::string_view path) {
    return path.substr(path.rfind('/') + 1);
}

void read_json_members(RenderSpec& spec, const Json& object, const std::string& path,
                       const RenderLimits& limits) {
    require_object(object, path, render_member_names(path));
    for (const RenderParameter& row : render_parameters()) {
        if (parent_of(row.json) != path) {
            continue;
        }
        const std::string_view name = member_name_of(row.json);
        if (const Json* value = find(object, name)) {
            row.read_json(spec, *value, child(path, name), limits);
        } else if (row.presence == Presence::Required) {
            reader().fail(child(path, name), "required");
        }
    }
}

// The GET form reads these rows after all the others (RenderParameter::query_second_pass).
std::vector<RenderParameter> read_last_in_query(std::vector<RenderParameter> rows) {
    for (RenderParameter& row : rows) {
        row.query_second_pass = true;
    }
    return rows;
}

}  // namespace

const std::vector<RenderParameter>& render_parameters() {
    static const std::vector<RenderParameter> table = [] {
        std::vector<RenderParameter> rows;
        const auto append = [&rows](std::vector<RenderParameter> more) {
            std::move(more.begin(), more.end(), std::back_inserter(rows));
        };
        append(scene_rows());
        append(read_last_in_query(lighting_switch_rows()));
        append(camera_rows());
        rows.push_back(lights_row());
        append(frame_size_rows());
        append(image_rows());
        append(read_last_in_query(shadow_rows()));
        append(read_last_in_query(sampling_rows()));
        return rows;
    }();
    return table;
}

const std::vector<std::string_view>& render_member_names(std::string_view parent) {
    static const auto names = [] {
        std::map<std::string_view, std::vector<std::string_view>, std::less<>> levels;
        for (const RenderParameter& row : render_parameters()) {
            levels[parent_of(row.json)].push_back(member_name_of(row.json));
        }
        return levels;
    }();
    static const std::vector<std::string_view> none;
    const auto found = names.find(parent);
    return found == names.end() ? none : found->second;
}

void render_members::read_body_members(RenderSpec& spec, const Json& body,
                                       const RenderLimits& limits) {
    read_json_members(spec, body, "", limits);
}

}  // namespace oer::api
