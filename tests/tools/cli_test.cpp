// The `oer` command line, run as a real process.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"

namespace fs = std::filesystem;

class Cli : public OerProcessTest {};

TEST_F(Cli, PreprocessDefaultPrintsTheRig) {
    const ProcessResult result = run("preprocess default");
    ASSERT_EQ(result.status, 0) << result.err;
    const nlohmann::json rig = nlohmann::json::parse(result.out);
    EXPECT_EQ(rig.at("id").get<std::string>().size(), 64u);
    EXPECT_EQ(rig.at("lighting_model"), "hdr");
    EXPECT_EQ(rig.at("lights").size(), oer::default_environment_lights().size());
    const int order = rig.at("sh").at("order");
    EXPECT_EQ(rig.at("sh").at("radiance").size(), std::size_t(order * order));
    EXPECT_EQ(rig.at("sh").at("per_light").size(), rig.at("lights").size());
    for (const auto& light : rig.at("lights")) {
        const auto d = light.at("direction");
        EXPECT_NEAR(
            double(d[0]) * double(d[0]) + double(d[1]) * double(d[1]) + double(d[2]) * double(d[2]),
            1.0, 1e-9);
        EXPECT_GT(double(light.at("solid_angle")), 0.0);
    }
    EXPECT_TRUE(rig.at("timings_ms").contains("total"));
    EXPECT_EQ(rig.at("source").at("repaired").at("nan"), 0);
    // The same input and options give the same id; other options another.
    EXPECT_EQ(nlohmann::json::parse(run("preprocess default").out).at("id"), rig.at("id"));
    EXPECT_NE(nlohmann::json::parse(run("preprocess default --sh-order 5").out).at("id"),
              rig.at("id"));
}

TEST_F(Cli, ExplicitOptionsAreHonoured) {
    const ProcessResult result =
        run("preprocess default --light-count 2 --sh-order 5 --window hanning");
    ASSERT_EQ(result.status, 0) << result.err;
    const nlohmann::json rig = nlohmann::json::parse(result.out);
    EXPECT_EQ(rig.at("lights").size(), 2u);
    EXPECT_EQ(rig.at("sh").at("order"), 5);
    EXPECT_EQ(rig.at("sh").at("window").at("kind"), "hanning");
    EXPECT_EQ(rig.at("options").at("light_count"), 2);
}

TEST_F(Cli, ErrorsNameTheProblemOnOneLine) {
    ProcessResult result = run("preprocess " + (dir_ / "missing.exr").string());
    EXPECT_EQ(result.status, 1);
    EXPECT_NE(result.err.find("missing.exr"), std::string::npos) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;

    std::ofstream(dir_ / "garbage.hdr") << "this is not an image";
    result = run("preprocess " + (dir_ / "garbage.hdr").string());
    EXPECT_EQ(result.status, 1);
    EXPECT_NE(result.err.find("garbage.hdr"), std::string::npos) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;

    result = run("preprocess default --light-count many");
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find("--light-count"), std::string::npos) << result.err;

    result = run("preprocess default --no-such-flag 1");
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find("--no-such-flag"), std::string::npos) << result.err;

    result = run("frobnicate");
    EXPECT_EQ(result.status, 2);
}

TEST_F(Cli, IrradianceMapMatchesTheRigsShIrradiance) {
    const fs::path out = dir_ / "irradiance.exr";
    ProcessResult result =
        run("irradiance-map default --sh-order 3 --light-count 3 --size 64x32 -o " + out.string());
    ASSERT_EQ(result.status, 0) << result.err;
    const oer::HdrImage map = oer::load_image_file(out.string()).image;
    ASSERT_EQ(map.width, 64);
    ASSERT_EQ(map.height, 32);
    // Recompute from the rig JSON the CLI prints for the same options.
    const nlohmann::json rig =
        nlohmann::json::parse(run("preprocess default --sh-order 3 --light-count 3").out);
    oer::ShRgb radiance(3);
    for (int i = 0; i < 9; ++i) {
        const auto c = rig.at("sh").at("radiance")[i];
        radiance.coefficients[i] = {double(c[0]), double(c[1]), double(c[2])};
    }
    const oer::ShRgb irradiance = oer::irradiance_coefficients(radiance);
    for (int y = 0; y < 32; y += 5) {
        for (int x = 0; x < 64; x += 7) {
            // Unwindowed order-3 irradiance of the studio rings below zero in places; the file
            // keeps those values, and the loader repairs negative radiance to 0.
            const glm::dvec3 expected = glm::max(
                irradiance.evaluate(oer::equirect::pixel_direction(x, y, 64, 32)), glm::dvec3(0.0));
            const float* got = map.at(x, y);
            EXPECT_NEAR(got[0], expected.r, 1e-4 * std::abs(expected.r) + 1e-4);
            EXPECT_NEAR(got[1], expected.g, 1e-4 * std::abs(expected.g) + 1e-4);
        }
    }
    // Switching a light off lowers the irradiance facing it.
    const fs::path off = dir_ / "off.exr";
    result =
        run("irradiance-map default --sh-order 3 --light-count 3 --size 64x32 --lights 0,1,1 -o " +
            off.string());
    ASSERT_EQ(result.status, 0) << result.err;
    const oer::HdrImage dimmer = oer::load_image_file(off.string()).image;
    const auto d = rig.at("lights")[0].at("direction");
    const glm::dvec2 p =
        oer::equirect::position_of({double(d[0]), double(d[1]), double(d[2])}, 64, 32);
    EXPECT_LT(dimmer.at(int(p.x), int(p.y))[1], 0.9f * map.at(int(p.x), int(p.y))[1]);
}

TEST_F(Cli, MasksOutlinesEveryLight) {
    const fs::path out = dir_ / "masks.png";
    const ProcessResult result = run("masks default -o " + out.string());
    ASSERT_EQ(result.status, 0) << result.err;
    const oer::HdrImage picture = oer::load_image_file(out.string()).image;
    const oer::HdrImage studio = oer::make_default_environment();
    EXPECT_EQ(picture.width, studio.width);
    EXPECT_EQ(picture.height, studio.height);
    // The lights the rig reports for the same options, and the outline colors of lights 1..3
    // (pure-ish red, green, blue once the PNG's sRGB is decoded to linear).
    const nlohmann::json rig = nlohmann::json::parse(run("preprocess default").out);
    ASSERT_GE(rig.at("lights").size(), 3u);
    std::vector<glm::dvec3> directions;
    std::vector<double> radii;
    for (const auto& light : rig.at("lights")) {
        const auto d = light.at("direction");
        directions.emplace_back(double(d[0]), double(d[1]), double(d[2]));
        radii.push_back(double(light.at("angular_radius")));
    }
    const auto outline_of = [](const glm::vec3& c) {
        return c.r > 0.9f && c.g < 0.1f && c.b < 0.1f     ? 0
               : c.g > 0.9f && c.r < 0.1f && c.b < 0.1f   ? 1
               : c.b > 0.9f && c.r < 0.15f && c.g < 0.25f ? 2
                                                          : -1;
    };
    // Each light's outline and number lie within its mask's extent plus the label beside it
    // (draw_light_overlay: offset radius + 2 scale, digits 3 scale wide and 5 high, scale =
    // height / 128): a light's color near its direction, and no outline color far from every
    // light.
    const double pixel_angle = std::acos(-1.0) / picture.height;
    const double label_angle = (14.0 * std::max(1, picture.height / 128) + 4.0) * pixel_angle;
    std::vector<int> near_own(3, 0);
    int far = 0;
    for (int y = 0; y < picture.height; ++y) {
        for (int x = 0; x < picture.width; ++x) {
            const int outline = outline_of(picture.rgb(std::size_t(y) * picture.width + x));
            if (outline < 0) {
                continue;
            }
            const glm::dvec3 direction =
                oer::equirect::pixel_direction(x, y, picture.width, picture.height);
            const auto angle_to = [&](std::size_t k) {
                return std::acos(std::clamp(glm::dot(direction, directions[k]), -1.0, 1.0));
            };
            near_own[outline] += angle_to(outline) < 2.0 * radii[outline] + 3.0 * pixel_angle;
            bool near_any = false;
            for (std::size_t k = 0; k < directions.size(); ++k) {
                near_any = near_any || angle_to(k) < 2.0 * radii[k] + label_angle;
            }
            far += !near_any;
        }
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_GT(near_own[k], 20) << "light " << k + 1;
    }
    EXPECT_EQ(far, 0);
}
