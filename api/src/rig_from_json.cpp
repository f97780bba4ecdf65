#include "oer/api/rig_from_json.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/error.hpp"

namespace oer::api {

namespace {

using nlohmann::json;

// A stored rig's wording: "rig document: <path>: <problem>", an InvalidInput error.
struct RigWording {
    [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
        throw Error(ErrorKind::InvalidInput,
                    "rig document: " + (path.empty() ? "document" : path) + ": " + problem);
    }
    std::string wrong_type(const std::string& expected, const json&) const {
        return "expected " + expected;
    }
    std::string missing() const { return "missing"; }
};

const checked_json::Reader<RigWording> read(RigWording{}, checked_json::PathStyle::Slash);

const json& member(const json& object, const std::string& path, const std::string& name) {
    return read.member(object, path, name);
}

double number(const json& value, const std::string& path, double low, double high) {
    const double x = read.number(value, path);
    if (!std::isfinite(x) || x < low || x > high) {
        read.fail(path, "out of range");
    }
    return x;
}

std::uint64_t count(const json& value, const std::string& path, std::uint64_t high) {
    // Written by rig_to_json as integers: a float here is a damaged document.
    read.expect(
        value,
        value.is_number_unsigned() || (value.is_number_integer() && value.get<long long>() >= 0),
        path, "a non-negative integer");
    const std::uint64_t n = value.get<std::uint64_t>();
    if (n > high) {
        read.fail(path, "out of range");
    }
    return n;
}

std::string text(const json& value, const std::string& path) {
    return read.string(value, path);
}

constexpr double kHuge = std::numeric_limits<double>::max();

glm::dvec3 vector3(const json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 3) {
        read.fail(path, "expected 3 numbers");
    }
    return {number(value[0], path + "/0", -kHuge, kHuge),
            number(value[1], path + "/1", -kHuge, kHuge),
            number(value[2], path + "/2", -kHuge, kHuge)};
}

ShRgb coefficients(const json& value, const std::string& path, int order) {
    if (!value.is_array() || value.size() != std::size_t(sh_count(order))) {
        read.fail(path, "expected " + std::to_string(sh_count(order)) + " RGB coefficients");
    }
    ShRgb sh(order);
    for (std::size_t i = 0; i < value.size(); ++i) {
        sh.coefficients[i] = vector3(value[i], path + "/" + std::to_string(i));
    }
    return sh;
}

template <typename FromString>
auto enum_value(const json& value, const std::string& path, FromString from_string) {
    try {
        return from_string(text(value, path));
    } catch (const Error& error) {
        read.fail(path, error.what());
    }
}

std::vector<std::uint32_t> mask(const json& runs, const std::string& path, std::uint64_t pixels,
                                std::uint64_t map_pixels) {
    if (!runs.is_array() || runs.size() % 2 != 0) {
        read.fail(path, "expected pairs of first index and length");
    }
    std::vector<std::uint32_t> indices;
    std::uint64_t next = 0;  // runs are sorted and disjoint
    for (std::size_t i = 0; i < runs.size(); i += 2) {
        const std::uint64_t first = count(runs[i], path + "/" + std::to_string(i), map_pixels);
        const std::uint64_t length =
            count(runs[i + 1], path + "/" + std::to_string(i + 1), map_pixels);
        if (first < next || length == 0 || first + length > map_pixels ||
            indices.size() + length > pixels) {
            read.fail(path + "/" + std::to_string(i), "runs out of order, empty or out of the map");
        }
        for (std::uint64_t k = first; k < first + length; ++k) {
            indices.push_back(std::uint32_t(k));
        }
        next = first + length;
    }
    if (indices.size() != pixels) {
        read.fail(path, "holds " + std::to_string(indices.size()) + " pixels, the light " +
                            std::to_string(pixels));
    }
    return indices;
}

}  // namespace

json light_masks_to_json(const Rig& rig) {
    json masks = json::array();
    for (const Light& light : rig.lights) {
        json runs = json::array();
        for (std::size_t i = 0; i < light.pixels.size();) {
            std::size_t end = i + 1;
            while (end < light.pixels.size() && light.pixels[end] == light.pixels[end - 1] + 1) {
                ++end;
            }
            runs.push_back(light.pixels[i]);
            runs.push_back(end - i);
            i = end;
        }
        masks.push_back(std::move(runs));
    }
    return masks;
}

checked_json::JsonBounds stored_rig_bounds(std::uint64_t max_map_pixels) {
    checked_json::JsonBounds bounds;
    bounds.max_elements = std::size_t((1u << 18) + 64 + 2 * max_map_pixels);
    bounds.max_depth = 16;
    return bounds;
}

Rig rig_from_json(const json& document, const json& masks) {
    Rig rig;
    if (!is_content_id(text(member(document, "", "id"), "id"))) {
        read.fail("id", "not a content id");
    }
    const json& source = member(document, "", "source");
    rig.source_width = int(count(member(source, "source", "width"), "source/width", 1 << 20));
    rig.source_height = int(count(member(source, "source", "height"), "source/height", 1 << 20));
    if (rig.source_width < 1 || rig.source_height < 1) {
        read.fail("source", "empty map");
    }
    const std::uint64_t map_pixels = std::uint64_t(rig.source_width) * rig.source_height;
    const json& repaired = member(source, "source", "repaired");
    const auto repair_count = [&](const char* name) {
        return count(member(repaired, "source/repaired", name),
                     std::string("source/repaired/") + name,
                     std::numeric_limits<std::uint64_t>::max());
    };
    rig.repaired = {repair_count("nan"), repair_count("inf"), repair_count("negative")};
    rig.source_range = enum_value(member(source, "source", "dynamic_range"), "source/dynamic_range",
                                  dynamic_range_from_string);
    try {
        rig.options = rig_options_from_json(member(document, "", "options"));
    } catch (const InvalidParameter& error) {
        read.fail("options/" + error.parameter(), error.what());
    }
    rig.model = enum_value(member(document, "", "lighting_model"), "lighting_model",
                           lighting_model_from_string);

    const json& lights = member(document, "", "lights");
    if (!lights.is_array() || lights.size() > 64) {
        read.fail("lights", "expected an array of at most 64 lights");
    }
    if (!masks.is_array() || masks.size() != lights.size()) {
        read.fail("masks", "expected one mask per light");
    }
    for (std::size_t k = 0; k < lights.size(); ++k) {
        const std::string path = "lights/" + std::to_string(k);
        const json& entry = lights[k];
        Light light;
        light.direction = vector3(member(entry, path, "direction"), read.child(path, "direction"));
        light.intensity = vector3(member(entry, path, "intensity"), read.child(path, "intensity"));
        light.solid_angle = number(member(entry, path, "solid_angle"),
                                   read.child(path, "solid_angle"), 0.0, 4.0 * std::numbers::pi);
        light.angular_radius = number(member(entry, path, "angular_radius"),
                                      read.child(path, "angular_radius"), 0.0, std::numbers::pi);
        light.luminance_share = number(member(entry, path, "luminance_share"),
                                       read.child(path, "luminance_share"), 0.0, 1.0);
        const std::uint64_t pixels =
            count(member(entry, path, "pixels"), read.child(path, "pixels"), map_pixels);
        light.pixels = mask(masks[k], "masks/" + std::to_string(k), pixels, map_pixels);
        rig.lights.push_back(std::move(light));
    }
    const json& light_count = member(document, "", "light_count");
    if (count(member(light_count, "light_count", "chosen"), "light_count/chosen", 64) !=
        rig.lights.size()) {
        read.fail("light_count/chosen", "does not match the lights");
    }
    rig.light_count_reason =
        text(member(light_count, "light_count", "reason"), "light_count/reason");

    const json& sh = member(document, "", "sh");
    rig.order = int(count(member(sh, "sh", "order"), "sh/order", kMaxShOrder));
    if (rig.order < 1) {
        read.fail("sh/order", "out of range");
    }
    rig.order_reason = text(member(sh, "sh", "order_reason"), "sh/order_reason");
    const json& window = member(sh, "sh", "window");
    rig.window.kind =
        enum_value(member(window, "sh/window", "kind"), "sh/window/kind", window_kind_from_string);
    rig.window_reason = text(member(window, "sh/window", "reason"), "sh/window/reason");
    if (rig.window.kind != WindowKind::None) {
        rig.window.cutoff =
            number(member(window, "sh/window", "cutoff"), "sh/window/cutoff", 1e-300, kHuge);
    }
    rig.sh.all = coefficients(member(sh, "sh", "radiance"), "sh/radiance", rig.order);
    const json& per_light = member(sh, "sh", "per_light");
    if (!per_light.is_array() || per_light.size() != rig.lights.size()) {
        read.fail("sh/per_light", "expected one coefficient list per light");
    }
    for (std::size_t k = 0; k < per_light.size(); ++k) {
        rig.sh.per_light.push_back(
            coefficients(per_light[k], "sh/per_light/" + std::to_string(k), rig.order));
    }
    rig.sh.all_above_horizon = coefficients(member(sh, "sh", "radiance_above_horizon"),
                                            "sh/radiance_above_horizon", rig.order);
    const json& per_light_above = member(sh, "sh", "per_light_above_horizon");
    if (!per_light_above.is_array() || per_light_above.size() != rig.lights.size()) {
        read.fail("sh/per_light_above_horizon", "expected one coefficient list per light");
    }
    for (std::size_t k = 0; k < per_light_above.size(); ++k) {
        rig.sh.per_light_above_horizon.push_back(coefficients(
            per_light_above[k], "sh/per_light_above_horizon/" + std::to_string(k), rig.order));
    }
    if (const auto error = sh.find("irradiance_error"); error != sh.end()) {
        rig.reference_error = number(*error, "sh/irradiance_error", 0.0, kHuge);
    }
    const json& timings = read.object(member(document, "", "timings_ms"), "timings_ms");
    for (const auto& [step, ms] : timings.items()) {
        rig.timings_ms[step] = number(ms, "timings_ms/" + step, 0.0, kHuge);
    }
    return rig;
}

}  // namespace oer::api
