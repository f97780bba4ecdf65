// Numerically hard and degenerate inputs through the whole preprocessing pipeline: each gives
// a finite rig or a clear error, within bounded memory.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"
#include "synthetic_maps.hpp"

using namespace oer;

namespace {

void expect_finite(const Rig& rig) {
    const auto finite = [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    for (const glm::dvec3& c : rig.sh.all.coefficients) {
        EXPECT_TRUE(finite(c));
    }
    for (const ShRgb& light : rig.sh.per_light) {
        for (const glm::dvec3& c : light.coefficients) {
            EXPECT_TRUE(finite(c));
        }
    }
    for (const Light& light : rig.lights) {
        EXPECT_TRUE(finite(light.direction) && finite(light.intensity));
        EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-9);
        EXPECT_TRUE(std::isfinite(light.solid_angle) && std::isfinite(light.angular_radius));
    }
}

long max_resident_kib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

}  // namespace

TEST(HardCases, OnePixelSunAMillionTimesBrighter) {
    HdrImage map = oer::testing::constant_map(1024, 512, glm::vec3(0.1f));
    const int sun_x = 700, sun_y = 100;
    map.at(sun_x, sun_y)[0] = map.at(sun_x, sun_y)[1] = map.at(sun_x, sun_y)[2] = 1e5f;
    RigOptions options;
    options.window = WindowChoice::Auto;
    const Rig rig = build_rig(map, {}, options);
    expect_finite(rig);
    ASSERT_GE(rig.lights.size(), 1u) << rig.light_count_reason;
    const std::uint32_t sun = sun_y * 1024 + sun_x;
    const auto& pixels = rig.lights[0].pixels;
    EXPECT_TRUE(std::binary_search(pixels.begin(), pixels.end(), sun));
    EXPECT_GE(min_relative_irradiance(rig.sh, rig.window), -1e-9) << rig.window_reason;
}

TEST(HardCases, TinyAndThinMaps) {
    for (const auto& [w, h] : {std::pair{1, 1}, {2, 1}, {1, 4096}, {4096, 1}, {3, 2}}) {
        HdrImage map(w, h);
        for (std::size_t i = 0; i < map.pixel_count(); ++i) {
            map.set(i, glm::vec3(float(i % 7) + 0.5f));
        }
        const Rig rig = build_rig(map, {}, RigOptions{});
        expect_finite(rig);
        EXPECT_EQ(rig.source_width, w);
    }
}

TEST(HardCases, BlackAndUniformMaps) {
    const Rig black = build_rig(HdrImage(256, 128), {}, RigOptions{});
    expect_finite(black);
    EXPECT_TRUE(black.lights.empty());
    EXPECT_EQ(black.sh.all.coefficients[0], glm::dvec3(0.0));

    const Rig uniform =
        build_rig(oer::testing::constant_map(256, 128, glm::vec3(5.0f)), {}, RigOptions{});
    expect_finite(uniform);
    EXPECT_TRUE(uniform.lights.empty());
    EXPECT_EQ(uniform.order, 1);
}

TEST(HardCases, NonFiniteAndNegativePixelsAreRepairedBeforeTheyPropagate) {
    HdrImage map = oer::testing::constant_map(64, 32, glm::vec3(1.0f));
    map.at(3, 3)[0] = std::numeric_limits<float>::quiet_NaN();
    map.at(4, 3)[1] = std::numeric_limits<float>::infinity();
    map.at(5, 3)[2] = -2.0f;
    map.at(6, 3)[0] = -std::numeric_limits<float>::infinity();
    const RepairCounts counts = repair_radiance(map);
    EXPECT_EQ(counts.nan, 1u);
    EXPECT_EQ(counts.inf, 1u);
    EXPECT_EQ(counts.negative, 2u);
    const Rig rig = build_rig(map, counts, RigOptions{});
    expect_finite(rig);
}

TEST(HardCases, HugeMapSlow) {
    const long before = max_resident_kib();
    const auto start = std::chrono::steady_clock::now();
    const HdrImage map = oer::testing::disc_map(
        8192, 4096, glm::vec3(0.2f), {{{0.5, 0.8, 0.3}, 0.05, {200.0f, 180.0f, 150.0f}}});
    const Rig rig = build_rig(map, {}, RigOptions{});
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    expect_finite(rig);
    EXPECT_EQ(rig.lights.size(), 1u) << rig.light_count_reason;
    // The map itself is 384 MiB of floats; the pipeline may add working sets of about its size
    // (blurred luminance, thresholds' copy), not multiples of it.
    const double grown_mib = (max_resident_kib() - before) / 1024.0;
    std::printf("8192x4096: %.1f s, resident memory grew by %.0f MiB\n", seconds, grown_mib);
    EXPECT_LT(grown_mib, 1200.0);
}
