#include <gtest/gtest.h>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/api/rig_options.hpp"

using namespace oer;
using oer::api::InvalidParameter;

namespace {

std::string parameter_of_failure(const std::map<std::string, std::string>& parameters) {
    try {
        api::parse_rig_options(parameters);
    } catch (const InvalidParameter& error) {
        return error.parameter();
    }
    return "";
}

}  // namespace

TEST(RigOptions, DefaultsAreAutoAndHdr) {
    const RigOptions options = api::parse_rig_options({});
    EXPECT_FALSE(options.light_count.has_value());
    EXPECT_FALSE(options.sh_order.has_value());
    EXPECT_EQ(options.model, LightingModel::Hdr);
    EXPECT_EQ(options.location.clustering, Clustering::Directions);
    EXPECT_EQ(options.max_lights, 4);
    EXPECT_DOUBLE_EQ(options.shadow_visibility_threshold, 0.05);
}

TEST(RigOptions, ParsesEveryOption) {
    const RigOptions options = api::parse_rig_options({
        {"light_count", "3"},
        {"max_lights", "6"},
        {"shadow_threshold", "0.1"},
        {"sh_order", "5"},
        {"max_sh_order", "7"},
        {"sh_tolerance", "0.02"},
        {"window", "lanczos"},
        {"window_cutoff", "4.5"},
        {"model", "thesis"},
        {"clustering", "pixels"},
        {"blur_radius", "2"},
        {"light_percentile", "0.98"},
        {"halo_percentile", "0.9"},
        {"clusters", "12"},
        {"seed", "42"},
        {"grow_connected", "false"},
    });
    EXPECT_EQ(options.light_count, 3);
    EXPECT_EQ(options.max_lights, 6);
    EXPECT_DOUBLE_EQ(options.shadow_visibility_threshold, 0.1);
    EXPECT_EQ(options.sh_order, 5);
    EXPECT_EQ(options.max_sh_order, 7);
    EXPECT_DOUBLE_EQ(options.sh_tolerance, 0.02);
    EXPECT_EQ(options.window, WindowChoice::Lanczos);
    EXPECT_DOUBLE_EQ(options.window_cutoff, 4.5);
    EXPECT_EQ(options.model, LightingModel::Thesis);
    EXPECT_EQ(options.location.clustering, Clustering::Pixels);
    EXPECT_DOUBLE_EQ(options.location.blur_radius, 2.0);
    EXPECT_DOUBLE_EQ(options.location.light_percentile, 0.98);
    EXPECT_DOUBLE_EQ(options.location.halo_percentile, 0.9);
    EXPECT_EQ(options.location.cluster_count, 12);
    EXPECT_EQ(options.location.seed, 42u);
    EXPECT_FALSE(options.location.grow_connected);
}

TEST(RigOptions, RejectsBadValuesNamingTheParameter) {
    EXPECT_EQ(parameter_of_failure({{"light_count", "many"}}), "light_count");
    EXPECT_EQ(parameter_of_failure({{"light_count", "17"}}), "light_count");
    EXPECT_EQ(parameter_of_failure({{"light_count", "-1"}}), "light_count");
    EXPECT_EQ(parameter_of_failure({{"sh_order", "0"}}), "sh_order");
    EXPECT_EQ(parameter_of_failure({{"sh_order", "3.5"}}), "sh_order");
    EXPECT_EQ(parameter_of_failure({{"window", "gauss"}}), "window");
    EXPECT_EQ(parameter_of_failure({{"model", "HDR"}}), "model");
    EXPECT_EQ(parameter_of_failure({{"clustering", ""}}), "clustering");
    EXPECT_EQ(parameter_of_failure({{"sh_tolerance", "nan"}}), "sh_tolerance");
    EXPECT_EQ(parameter_of_failure({{"blur_radius", "1e400"}}), "blur_radius");
    EXPECT_EQ(parameter_of_failure({{"light_percentile", "0.9"}, {"halo_percentile", "0.95"}}),
              "halo_percentile");
    EXPECT_EQ(parameter_of_failure({{"color", "red"}}), "color");
    EXPECT_EQ(parameter_of_failure({{"grow_connected", "yes"}}), "grow_connected");
}

TEST(RigOptions, CanonicalJsonFillsDefaults) {
    const nlohmann::json json =
        api::rig_options_to_json(api::parse_rig_options({{"sh_order", "5"}}));
    EXPECT_EQ(json.at("light_count"), "auto");
    EXPECT_EQ(json.at("sh_order"), 5);
    EXPECT_EQ(json.at("window"), "none");
    EXPECT_EQ(json.at("model"), "hdr");
    EXPECT_EQ(json.at("clustering"), "directions");
    EXPECT_EQ(json.at("grow_connected"), true);
    EXPECT_EQ(json.size(), 16u);
}
