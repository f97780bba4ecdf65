// bench/light_location_sweep --quick as a process: its JSON and CSV are well formed and agree,
// and the hard cases of light location are found where the painted discs are: with the default
// options, across the seam, at a pole, a tiny sun 10^6 times the sky and a large soft box each
// as one light within half a degree (1.5 pixels of the 1024x512 map) and 3 % of its intensity.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "sweep_process.hpp"

namespace {

class LightLocationSweepQuick : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        output_ = new SweepOutput(run_quick_sweep(LIGHT_LOCATION_SWEEP_PATH));
    }
    static void TearDownTestSuite() {
        delete output_;
        output_ = nullptr;
    }
    void SetUp() override {
        ASSERT_EQ(output_->status, 0) << output_->stderr_text;
        ASSERT_TRUE(output_->json.is_object());
        for (const auto& c : output_->json.at("cases")) {
            cases_[{c.at("case"), c.at("options")}] = c;
        }
    }

    static SweepOutput* output_;
    // (case, options) -> its JSON
    std::map<std::pair<std::string, std::string>, nlohmann::json> cases_;
};

SweepOutput* LightLocationSweepQuick::output_ = nullptr;

}  // namespace

TEST_F(LightLocationSweepQuick, CsvAndJsonHoldTheSameLights) {
    EXPECT_EQ(output_->json.at("benchmark"), "light_location_sweep");
    const auto& csv = output_->csv;
    ASSERT_FALSE(csv.empty());
    EXPECT_EQ(csv[0], (std::vector<std::string>{"case", "options", "width", "height", "light",
                                                "found", "merged_lights", "angular_error_degrees",
                                                "intensity_relative_error", "lights_found",
                                                "extra_lights", "rig_ms"}));
    std::size_t line = 1;
    for (const auto& c : output_->json.at("cases")) {
        EXPECT_EQ(c.at("width"), 1024);
        EXPECT_EQ(c.at("height"), 512);
        for (const auto& light : c.at("lights")) {
            ASSERT_LT(line, csv.size());
            const auto& fields = csv[line++];
            ASSERT_EQ(fields.size(), 12u) << "CSV line " << line;
            EXPECT_EQ(fields[0], c.at("case"));
            EXPECT_EQ(fields[1], c.at("options"));
            EXPECT_EQ(fields[5], light.at("found").get<bool>() ? "1" : "0");
            if (light.at("found").get<bool>()) {
                EXPECT_EQ(std::stoul(fields[6]), light.at("merged_lights").get<std::size_t>());
                EXPECT_NEAR(std::stod(fields[7]), light.at("angular_error_degrees").get<double>(),
                            1e-6);
                EXPECT_NEAR(std::stod(fields[8]),
                            light.at("intensity_relative_error").get<double>(), 1e-6);
            } else {
                EXPECT_EQ(fields[6], "");
                EXPECT_EQ(fields[7], "");
                EXPECT_EQ(fields[8], "");
            }
            EXPECT_EQ(std::stoul(fields[9]), c.at("lights_found").get<std::size_t>());
        }
    }
    EXPECT_EQ(line, csv.size());
    EXPECT_EQ(cases_.size(), 15u);  // 5 cases x (default, no_growth, thesis_pixels)
}

TEST_F(LightLocationSweepQuick, SingleHardLightsAreFoundWhereTheyAre) {
    for (const char* name : {"seam", "pole", "sun", "soft_box"}) {
        SCOPED_TRACE(name);
        const nlohmann::json& c = cases_.at({name, "default"});
        EXPECT_EQ(c.at("lights_found"), 1);
        EXPECT_EQ(c.at("extra_lights"), 0);
        const nlohmann::json& light = c.at("lights").at(0);
        ASSERT_TRUE(light.at("found").get<bool>());
        EXPECT_LT(light.at("angular_error_degrees").get<double>(), 0.5);
        EXPECT_LT(std::abs(light.at("intensity_relative_error").get<double>()), 0.03);
        for (const auto& value : light.at("found_intensity")) {
            EXPECT_TRUE(std::isfinite(value.get<double>()));
        }
    }
}

TEST_F(LightLocationSweepQuick, TwoLightsThreeDegreesApartAreToldApartWithoutGrowth) {
    // The connected-region growth of light_location.hpp takes the two discs, whose blurred
    // halos touch, as one lamp: with the defaults what must hold is that the light found stands
    // for both, at their power-weighted centre (measured 0.045 degrees) with their summed
    // energy (+0.9 %, the halo pixels it takes; against the brighter disc alone that is +66 %).
    // Without the growth, and with the thesis's clustering, both are found where they are.
    const nlohmann::json& merged = cases_.at({"pair_3deg", "default"});
    EXPECT_EQ(merged.at("lights_found").get<int>(), 1);
    for (const auto& light : merged.at("lights")) {
        ASSERT_TRUE(light.at("found").get<bool>());
        EXPECT_EQ(light.at("merged_lights"), 2);
        EXPECT_LT(light.at("angular_error_degrees").get<double>(), 0.2);
        EXPECT_LT(std::abs(light.at("intensity_relative_error").get<double>()), 0.03);
    }
    for (const char* options : {"no_growth", "thesis_pixels"}) {
        SCOPED_TRACE(options);
        const nlohmann::json& c = cases_.at({"pair_3deg", options});
        EXPECT_EQ(c.at("lights_found"), 2);
        for (const auto& light : c.at("lights")) {
            ASSERT_TRUE(light.at("found").get<bool>());
            EXPECT_LT(light.at("angular_error_degrees").get<double>(), 0.5);
        }
    }
}

// Why merging two lights 3 degrees apart is the right model: under a pole of height H the true
// lights' tip shadows lie cot(28.5) - cot(31.5) = 0.210 H apart, a band where one merged light
// gets the shadow wrong by at most the brighter light's share of the ground's irradiance (7.8 %);
// each 1-degree disc's own extent already spreads its tip over cot(27.5) - cot(29.5) = 0.153 H,
// a penumbra the renderer's point lights leave out too: the merge's error is of that kind and
// size, for one shadow map instead of two and half the on/off subsets.
TEST_F(LightLocationSweepQuick, MergingThePairMisplacesAShadowBandNoWiderThanAPenumbra) {
    const nlohmann::json& merges = cases_.at({"pair_3deg", "default"}).at("merged_shadows");
    ASSERT_EQ(merges.size(), 1u);
    const nlohmann::json& merge = merges.at(0);
    EXPECT_EQ(merge.at("lights"), nlohmann::json::array({0, 1}));
    EXPECT_NEAR(merge.at("true_tips_apart").get<double>(), 0.210, 0.002);
    EXPECT_NEAR(merge.at("own_penumbra").get<double>(), 0.153, 0.002);
    EXPECT_LT(merge.at("merged_tip_offset").get<double>(), 0.02);
    EXPECT_LT(merge.at("band_error_share").get<double>(), 0.1);
    EXPECT_LT(merge.at("true_tips_apart").get<double>(),
              1.5 * merge.at("own_penumbra").get<double>());
    for (const char* name : {"seam", "pole", "sun", "soft_box"}) {
        EXPECT_TRUE(cases_.at({name, "default"}).at("merged_shadows").empty()) << name;
    }
}

// What the two departures from the thesis buy: its pixel-space clustering splits a light across
// the seam or at a pole into several; the default finds each as one (checked above).
TEST_F(LightLocationSweepQuick, ThesisClusteringSplitsTheSeamAndPoleLights) {
    for (const char* name : {"seam", "pole"}) {
        SCOPED_TRACE(name);
        EXPECT_GT(cases_.at({name, "thesis_pixels"}).at("lights_found").get<int>(), 1);
        EXPECT_EQ(cases_.at({name, "default"}).at("lights_found").get<int>(), 1);
    }
}
