#include "oer/api/rig_options.hpp"

#include <functional>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/core/enum_names.hpp"

namespace oer::api {

namespace {

constexpr EnumNames<WindowChoice, 4> kWindowChoiceNames = {{{WindowChoice::None, "none"},
                                                            {WindowChoice::Hanning, "hanning"},
                                                            {WindowChoice::Lanczos, "lanczos"},
                                                            {WindowChoice::Auto, "auto"}}};

WindowChoice window_choice_from_string(const std::string& text) {
    return value_named(text, kWindowChoiceNames, "window");
}

std::string to_string(WindowChoice choice) {
    return name_of(choice, kWindowChoiceNames);
}

using Setter = std::function<void(RigOptions&, const std::string& name, const std::string& value)>;

const std::map<std::string, Setter>& setters() {
    static const std::map<std::string, Setter> table = {
        {"light_count",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.light_count =
                 v == "auto" ? std::nullopt : std::optional<int>(int(parse_integer(n, v, 0, 16)));
         }},
        {"max_lights",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.max_lights = int(parse_integer(n, v, 0, 16));
         }},
        {"shadow_threshold",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.shadow_visibility_threshold = parse_number(n, v, 0.0, 1.0);
         }},
        {"sh_order",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.sh_order = v == "auto"
                              ? std::nullopt
                              : std::optional<int>(int(parse_integer(n, v, 1, kMaxShOrder)));
         }},
        {"max_sh_order",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.max_sh_order = int(parse_integer(n, v, 1, kMaxShOrder));
         }},
        {"sh_tolerance",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.sh_tolerance = parse_number(n, v, 1e-6, 0.5);
         }},
        {"window",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.window = parse_enum(n, v, window_choice_from_string);
         }},
        {"window_cutoff",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.window_cutoff = parse_number(n, v, 0.0, 1000.0);
         }},
        {"model",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.model = parse_enum(n, v, lighting_model_from_string);
         }},
        {"clustering",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.location.clustering = parse_enum(n, v, clustering_from_string);
         }},
        {"blur_radius",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.location.blur_radius = parse_number(n, v, 0.0, 64.0);
         }},
        {"light_percentile",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.location.light_percentile = parse_number(n, v, 0.5, 0.99999);
         }},
        {"halo_percentile",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.location.halo_percentile = parse_number(n, v, 0.5, 0.99999);
         }},
        {"clusters",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.location.cluster_count = int(parse_integer(n, v, 1, 64));
         }},
        {"grow_connected",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             if (v != "true" && v != "false") {
                 throw InvalidParameter(n, "expected true or false, got '" + v + "'");
             }
             o.location.grow_connected = v == "true";
         }},
        {"seed",
         [](RigOptions& o, const std::string& n, const std::string& v) {
             o.location.seed = std::uint64_t(parse_integer(n, v, 0, (1ll << 53)));
         }},
    };
    return table;
}

}  // namespace

bool is_rig_option(const std::string& name) {
    return setters().contains(name);
}

std::vector<std::string> rig_option_names() {
    std::vector<std::string> names;
    for (const auto& [name, setter] : setters()) {
        names.push_back(name);
    }
    return names;
}

RigOptions parse_rig_options(const std::map<std::string, std::string>& parameters) {
    RigOptions options;
    for (const auto& [name, value] : parameters) {
        const auto setter = setters().find(name);
        if (setter == setters().end()) {
            throw InvalidParameter(name, "unknown preprocessing option");
        }
        setter->second(options, name, value);
    }
    if (options.location.halo_percentile > options.location.light_percentile) {
        throw InvalidParameter("halo_percentile", "must not exceed light_percentile");
    }
    return options;
}

nlohmann::json rig_options_to_json(const RigOptions& options) {
    nlohmann::json json;
    json["light_count"] = options.light_count ? nlohmann::json(*options.light_count) : "auto";
    json["max_lights"] = options.max_lights;
    json["shadow_threshold"] = options.shadow_visibility_threshold;
    json["sh_order"] = options.sh_order ? nlohmann::json(*options.sh_order) : "auto";
    json["max_sh_order"] = options.max_sh_order;
    json["sh_tolerance"] = options.sh_tolerance;
    json["window"] = to_string(options.window);
    json["window_cutoff"] = options.window_cutoff;
    json["model"] = to_string(options.model);
    json["clustering"] = to_string(options.location.clustering);
    json["blur_radius"] = options.location.blur_radius;
    json["light_percentile"] = options.location.light_percentile;
    json["halo_percentile"] = options.location.halo_percentile;
    json["clusters"] = options.location.cluster_count;
    json["seed"] = options.location.seed;
    json["grow_connected"] = options.location.grow_connected;
    return json;
}

RigOptions rig_options_from_json(const nlohmann::json& options) {
    if (!options.is_object()) {
        throw InvalidParameter("options", "expected an object");
    }
    // Each value back to the text a query would carry; number_text keeps every double exact.
    std::map<std::string, std::string> parameters;
    for (const auto& [name, value] : options.items()) {
        if (value.is_string()) {
            parameters[name] = value.get<std::string>();
        } else if (value.is_boolean()) {
            parameters[name] = value.get<bool>() ? "true" : "false";
        } else if (value.is_number_unsigned()) {
            parameters[name] = std::to_string(value.get<std::uint64_t>());
        } else if (value.is_number_integer()) {
            parameters[name] = std::to_string(value.get<std::int64_t>());
        } else if (value.is_number_float()) {
            parameters[name] = number_text(value.get<double>());
        } else {
            throw InvalidParameter(name, "expected a number, a boolean or a string");
        }
    }
    return parse_rig_options(parameters);
}

}  // namespace oer::api
