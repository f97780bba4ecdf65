#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "directions.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/lighting/equirect.hpp"
#include "process_memory.hpp"

using namespace oer;
using oer::testing::angle_between;
using std::numbers::pi;

namespace {

// The thesis's luminance weights over a pixel's radiance, without light_location's 179 lm/W.
double pixel_luminance(const float* p) {
    return 0.265 * p[0] + 0.670 * p[1] + 0.065 * p[2];
}

}  // namespace

TEST(DefaultEnvironment, IsFiniteNonNegativeAndDeterministic) {
    const HdrImage a = make_default_environment();
    ASSERT_EQ(a.width, 1024);
    ASSERT_EQ(a.height, 512);
    ASSERT_EQ(a.pixels.size(), a.pixel_count() * 3);
    for (float v : a.pixels) {
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << v;
    }
    EXPECT_EQ(a.pixels, make_default_environment().pixels);
    const HdrImage small = make_default_environment(64, 32);
    EXPECT_EQ(small.width, 64);
    EXPECT_EQ(small.height, 32);
    EXPECT_EQ(make_default_environment(1, 1).pixel_count(), 1u);
    EXPECT_THROW(make_default_environment(0, 10), Error);
    EXPECT_THROW(make_default_environment(10, -1), Error);
}

TEST(DefaultEnvironment, DocumentedLightsAreDistinct) {
    const std::vector<DefaultStudioLight> lights = default_environment_lights();
    ASSERT_EQ(lights.size(), 3u);
    EXPECT_EQ(lights[0].name, "key");
    EXPECT_EQ(lights[1].name, "fill");
    EXPECT_EQ(lights[2].name, "rim");
    for (const DefaultStudioLight& light : lights) {
        EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-12) << light.name;
    }
    // Key: large and warm; fill: smaller and cool; rim: smallest, neutral and brightest.
    EXPECT_GT(lights[0].angular_radius, lights[1].angular_radius);
    EXPECT_GT(lights[1].angular_radius, lights[2].angular_radius);
    EXPECT_GT(lights[0].radiance.r, lights[0].radiance.b);
    EXPECT_LT(lights[1].radiance.r, lights[1].radiance.b);
    EXPECT_EQ(lights[2].radiance.r, lights[2].radiance.b);
    EXPECT_GT(lights[2].radiance.g, lights[0].radiance.g);
    // Key up and front-left, fill on the other side and lower, rim behind and above.
    EXPECT_GT(lights[0].direction.y, 0.3);
    EXPECT_LT(lights[0].direction.x, 0.0);
    EXPECT_GT(lights[0].direction.z, 0.0);
    EXPECT_GT(lights[1].direction.x, 0.0);
    EXPECT_LT(lights[1].direction.y, lights[0].direction.y);
    EXPECT_LT(lights[2].direction.z, 0.0);
    EXPECT_GT(lights[2].direction.y, 0.3);
    // Their discs are far apart.
    for (std::size_t i = 0; i < lights.size(); ++i) {
        for (std::size_t j = i + 1; j < lights.size(); ++j) {
            EXPECT_GT(angle_between(lights[i].direction, lights[j].direction),
                      2.0 * (lights[i].angular_radius + lights[j].angular_radius));
        }
    }
}

TEST(DefaultEnvironment, LightCentresHaveTheDocumentedRadiance) {
    const HdrImage image = make_default_environment();
    for (const DefaultStudioLight& light : default_environment_lights()) {
        const glm::dvec2 at = equirect::position_of(light.direction, image.width, image.height);
        const float* p = image.at(int(at.x), int(at.y));
        for (int c = 0; c < 3; ++c) {
            // Plus the room, 0.30 at the horizon to 0.38 straight up (every light is above the
            // horizon).
            EXPECT_NEAR(p[c], light.radiance[c] + 0.34f, 0.01f * light.radiance[c] + 0.04f)
                << light.name << " channel " << c;
        }
    }
}

TEST(DefaultEnvironment, BrightPixelsLieInTheDocumentedDiscs) {
    const HdrImage image = make_default_environment();
    const equirect::Grid grid(image.width, image.height);
    const std::vector<DefaultStudioLight> lights = default_environment_lights();
    // Half a pixel's diagonal, in angle: the slack for a pixel centre near a disc's edge.
    const double slack = pi / image.height;
    std::vector<int> lit(lights.size(), 0);
    std::vector<std::pair<double, std::size_t>> by_luminance;
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        const double l = pixel_luminance(&image.pixels[i * 3]);
        by_luminance.emplace_back(l, i);
        if (l < 1.0) {  // 2.6x the brightest room (0.38): nothing but a light is here
            continue;
        }
        const glm::dvec3 d = grid.direction(i);
        bool inside = false;
        for (std::size_t k = 0; k < lights.size(); ++k) {
            if (angle_between(d, lights[k].direction) <= 1.15 * lights[k].angular_radius + slack) {
                inside = true;
                ++lit[k];
            }
        }
        EXPECT_TRUE(inside) << "bright pixel " << i % image.width << ", " << i / image.width
                            << " (luminance " << l << ") is in no documented light";
    }
    for (std::size_t k = 0; k < lights.size(); ++k) {
        EXPECT_GT(lit[k], 20) << lights[k].name << " has almost no bright pixels";
    }
    // The 100 brightest pixels all belong to the brightest light, the rim.
    std::partial_sort(by_luminance.begin(), by_luminance.begin() + 100, by_luminance.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    for (int n = 0; n < 100; ++n) {
        const glm::dvec3 d = grid.direction(by_luminance[n].second);
        EXPECT_LE(angle_between(d, lights[2].direction), lights[2].angular_radius + slack);
    }
}

TEST(DefaultEnvironment, HasNoSeam) {
    // Columns 0 and W-1 look along -X from either side; with the lights away from -X the two
    // must agree (a light or gradient computed in pixel space would break here).
    const HdrImage image = make_default_environment(512, 256);
    for (int y = 0; y < image.height; ++y) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(image.at(0, y)[c], image.at(image.width - 1, y)[c], 1e-6f) << y;
        }
    }
}

TEST(DefaultEnvironment, IsFast) {
    double best = 1e9;
    for (int i = 0; i < 5; ++i) {
        const auto start = std::chrono::steady_clock::now();
        const HdrImage image = make_default_environment(1024, 512);
        best = std::min(best, std::chrono::duration<double, std::milli>(
                                  std::chrono::steady_clock::now() - start)
                                  .count());
        ASSERT_EQ(image.width, 1024);
    }
    std::cout << "[          ] make_default_environment(1024, 512): best of 5 " << best << " ms\n";
#if defined(NDEBUG) && !defined(OER_ADDRESS_SANITIZER)
    EXPECT_LT(best, 50.0);
#endif
}
