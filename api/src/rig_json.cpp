#include "oer/api/rig_json.hpp"

#include "oer/api/rig_options.hpp"

namespace oer::api {

namespace {

nlohmann::json raw_vector_json(const glm::dvec3& v) {
    return nlohmann::json::array({v.x, v.y, v.z});
}

nlohmann::json coefficients_json(const ShRgb& sh) {
    nlohmann::json list = nlohmann::json::array();
    for (const glm::dvec3& c : sh.coefficients) {
        list.push_back(raw_vector_json(c));
    }
    return list;
}

}  // namespace

nlohmann::json rig_to_json(const Rig& rig, const std::string& id) {
    nlohmann::json json;
    json["id"] = id;
    json["source"] = {{"width", rig.source_width},
                      {"height", rig.source_height},
                      {"dynamic_range", to_string(rig.source_range)},
                      {"repaired",
                       {{"nan", rig.repaired.nan},
                        {"inf", rig.repaired.inf},
                        {"negative", rig.repaired.negative}}}};
    json["options"] = rig_options_to_json(rig.options);
    json["lighting_model"] = to_string(rig.model);

    nlohmann::json lights = nlohmann::json::array();
    for (const Light& light : rig.lights) {
        lights.push_back({{"direction", raw_vector_json(light.direction)},
                          {"intensity", raw_vector_json(light.intensity)},
                          {"solid_angle", light.solid_angle},
                          {"angular_radius", light.angular_radius},
                          {"luminance_share", light.luminance_share},
                          {"pixels", light.pixels.size()}});
    }
    json["lights"] = std::move(lights);
    json["light_count"] = {{"chosen", rig.lights.size()}, {"reason", rig.light_count_reason}};

    nlohmann::json per_light = nlohmann::json::array();
    for (const ShRgb& light : rig.sh.per_light) {
        per_light.push_back(coefficients_json(light));
    }
    nlohmann::json per_light_above_horizon = nlohmann::json::array();
    for (const ShRgb& light : rig.sh.per_light_above_horizon) {
        per_light_above_horizon.push_back(coefficients_json(light));
    }
    nlohmann::json window = {{"kind", to_string(rig.window.kind)}, {"reason", rig.window_reason}};
    if (rig.window.kind != WindowKind::None) {
        window["cutoff"] = rig.window.cutoff;
    }
    json["sh"] = {{"order", rig.order},
                  {"order_reason", rig.order_reason},
                  {"window", std::move(window)},
                  {"radiance", coefficients_json(rig.sh.all)},
                  {"per_light", std::move(per_light)},
                  {"radiance_above_horizon", coefficients_json(rig.sh.all_above_horizon)},
                  {"per_light_above_horizon", std::move(per_light_above_horizon)}};
    if (rig.reference_error >= 0.0) {
        json["sh"]["irradiance_error"] = rig.reference_error;
    }
    json["timings_ms"] = rig.timings_ms;
    return json;
}

}  // namespace oer::api
