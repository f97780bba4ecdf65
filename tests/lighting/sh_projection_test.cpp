#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "sh_test_support.hpp"

using namespace oer;

namespace {

// n disjoint random pixel lists (each pixel in at most one), sorted, of about fraction of the map.
std::vector<std::vector<std::uint32_t>> random_masks(const HdrImage& image, int n, double fraction,
                                                     std::uint32_t seed) {
    std::vector<std::vector<std::uint32_t>> masks(n);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (std::uint32_t i = 0; i < image.pixel_count(); ++i) {
        const double u = uniform(rng);
        if (u < fraction) {
            masks[std::min(n - 1, int(u / fraction * n))].push_back(i);
        }
    }
    return masks;
}

// Disjoint rectangular blobs (rows y0..y0+h, columns x0..x0+w).
std::vector<std::uint32_t> blob(const HdrImage& image, int x0, int y0, int w, int h) {
    std::vector<std::uint32_t> pixels;
    for (int y = y0; y < y0 + h; ++y) {
        for (int x = x0; x < x0 + w; ++x) {
            pixels.push_back(std::uint32_t(y * image.width + x));
        }
    }
    return pixels;
}

void expect_close(const ShRgb& actual, const ShRgb& expected, double relative,
                  const std::string& what) {
    ASSERT_EQ(actual.order, expected.order) << what;
    ASSERT_EQ(actual.coefficients.size(), expected.coefficients.size()) << what;
    const double scale = std::max(test::max_abs(expected), 1e-300);
    EXPECT_LE(test::max_abs_difference(actual, expected), relative * scale) << what;
}

}  // namespace

TEST(ShProjection, SeparableEqualsNaivePerPixelProjection) {
    const std::array<std::pair<int, int>, 7> sizes = {
        std::pair{37, 19}, {1, 1}, {2, 1}, {1, 4096}, {64, 32}, {5, 300}, {400, 200}};
    std::uint32_t seed = 1;
    for (const auto& [w, h] : sizes) {
        const HdrImage image = test::random_map(w, h, seed++);
        const auto masks = random_masks(image, 3, 0.2, seed++);
        for (int order = 1; order <= 9; ++order) {
            // The largest size (two threads) at a few orders only, to stay fast.
            if (w * h > 100000 && order != 1 && order != 3 && order != 9) {
                continue;
            }
            const ShProjection fast = project_environment(image, masks, order);
            const std::string where =
                std::to_string(w) + "x" + std::to_string(h) + " order " + std::to_string(order);
            expect_close(fast.all, test::naive_projection(image, order), 1e-10, where);
            ASSERT_EQ(fast.per_light.size(), masks.size());
            for (std::size_t k = 0; k < masks.size(); ++k) {
                expect_close(fast.per_light[k], test::naive_projection(image, order, &masks[k]),
                             1e-10, where + " light " + std::to_string(k));
            }
        }
    }
}

TEST(ShProjection, HighestOrderEqualsNaive) {
    const HdrImage image = test::random_map(61, 33, 99);
    const auto masks = random_masks(image, 2, 0.1, 98);
    const ShProjection fast = project_environment(image, masks, kMaxShOrder);
    expect_close(fast.all, test::naive_projection(image, kMaxShOrder), 1e-10, "all");
    expect_close(fast.per_light[1], test::naive_projection(image, kMaxShOrder, &masks[1]), 1e-10,
                 "light 1");
}

TEST(ShProjection, UnsortedMaskGivesTheSameCoefficients) {
    const HdrImage image = test::random_map(300, 150, 5);
    auto masks = random_masks(image, 1, 0.05, 6);
    const ShProjection sorted = project_environment(image, masks, 4);
    std::mt19937 rng(4);
    std::shuffle(masks[0].begin(), masks[0].end(), rng);
    const ShProjection shuffled = project_environment(image, masks, 4);
    expect_close(shuffled.per_light[0], sorted.per_light[0], 1e-12, "shuffled");
}

TEST(ShProjection, DeterministicAcrossRuns) {
    const HdrImage image = test::random_map(512, 256, 11);
    const auto masks = random_masks(image, 2, 0.01, 12);
    const ShProjection a = project_environment(image, masks, 5);
    const ShProjection b = project_environment(image, masks, 5);
    EXPECT_EQ(a.all.coefficients, b.all.coefficients);
    EXPECT_EQ(a.per_light[0].coefficients, b.per_light[0].coefficients);
    EXPECT_EQ(a.per_light[1].coefficients, b.per_light[1].coefficients);
}

TEST(ShProjection, ConstantMapHasTheExactMean) {
    // L_00 = L * 4 pi * Y_00 exactly (the pixel solid angles sum to 4 pi), and the dipole band
    // vanishes by symmetry.
    const HdrImage image = test::constant_map(128, 64, {1.0f, 2.0f, 0.5f});
    const ShProjection p = project_environment(image, {}, 3);
    const double y00 = 0.5 / std::sqrt(std::numbers::pi);
    EXPECT_NEAR(p.all.coefficients[0].x, 4.0 * std::numbers::pi * y00, 1e-12);
    EXPECT_NEAR(p.all.coefficients[0].y, 8.0 * std::numbers::pi * y00, 1e-12);
    EXPECT_NEAR(p.all.coefficients[0].z, 2.0 * std::numbers::pi * y00, 1e-12);
    for (int i = 1; i < 4; ++i) {
        EXPECT_NEAR(glm::length(p.all.coefficients[i]), 0.0, 1e-12);
    }
}

// The above-horizon part is the projection of the map with its lower rows blackened, for the
// whole map and for each light, whether one thread projects or two (the split is the horizon);
// a light straddling the horizon keeps the share of its pixels above it.
TEST(ShProjection, AboveTheHorizonIsTheUpperHalfsProjection) {
    for (const auto& [width, height] : {std::pair{96, 48}, std::pair{512, 256}}) {
        HdrImage image = test::random_map(width, height, 5);
        const std::vector<std::vector<std::uint32_t>> masks = {
            blob(image, width / 4, height / 2 - 3, 6, 6), blob(image, width / 2, height / 8, 4, 3)};
        const ShProjection projection = project_environment(image, masks, 4);
        HdrImage upper = image;
        for (std::size_t i = std::size_t(width) * std::size_t(height / 2); i < upper.pixel_count();
             ++i) {
            upper.set(i, glm::vec3(0.0f));
        }
        const ShProjection expected = project_environment(upper, masks, 4);
        expect_close(projection.all_above_horizon, expected.all, 1e-9, "whole map");
        ASSERT_EQ(projection.per_light_above_horizon.size(), 2u);
        for (std::size_t k = 0; k < 2; ++k) {
            expect_close(projection.per_light_above_horizon[k], expected.per_light[k], 1e-9,
                         "light " + std::to_string(k));
        }
        // The light wholly above the horizon keeps all of itself; the straddling one about half.
        expect_close(projection.per_light_above_horizon[1], projection.per_light[1], 1e-12,
                     "light above");
        const double share = projection.per_light_above_horizon[0].coefficients[0].g /
                             projection.per_light[0].coefficients[0].g;
        EXPECT_GT(share, 0.3);
        EXPECT_LT(share, 0.7);
    }
}

TEST(ShProjection, SubsetsEqualProjectingTheBlackenedMap) {
    HdrImage image = test::random_map(96, 48, 21);
    const std::vector<std::vector<std::uint32_t>> masks = {
        blob(image, 10, 5, 6, 4), blob(image, 50, 20, 3, 9), blob(image, 80, 40, 12, 3)};
    for (const auto& mask : masks) {  // make the lights bright
        for (const std::uint32_t i : mask) {
            image.set(i, image.rgb(i) * 500.0f);
        }
    }
    for (const int order : {3, 6}) {
        const ShProjection projection = project_environment(image, masks, order);
        for (int subset = 0; subset < 8; ++subset) {
            const std::array<bool, 3> on = {(subset & 1) != 0, (subset & 2) != 0,
                                            (subset & 4) != 0};
            HdrImage blackened = image;
            for (int k = 0; k < 3; ++k) {
                if (!on[k]) {
                    for (const std::uint32_t i : masks[k]) {
                        blackened.set(i, glm::vec3(0.0f));
                    }
                }
            }
            const ShRgb direct = project_environment(blackened, {}, order).all;
            expect_close(subset_coefficients(projection, on), direct, 1e-9,
                         "subset " + std::to_string(subset) + " order " + std::to_string(order));
        }
    }
}

TEST(ShProjection, VisibilityInterpolatesBetweenSubsets) {
    const HdrImage image = test::random_map(64, 32, 31);
    const auto masks = random_masks(image, 3, 0.1, 32);
    const ShProjection projection = project_environment(image, masks, 3);
    const std::array<bool, 3> all_on = {true, true, true};
    const std::array<bool, 3> third_off = {true, true, false};
    for (const double t : {0.0, 0.25, 1.0}) {
        const std::array<double, 3> visibility = {1.0, 1.0, t};
        ShRgb expected = subset_coefficients(projection, all_on);
        expected *= t;
        ShRgb off = subset_coefficients(projection, third_off);
        off *= 1.0 - t;
        expected += off;
        expect_close(visibility_coefficients(projection, visibility), expected, 1e-12,
                     "t " + std::to_string(t));
    }
    const std::array<double, 3> none = {0.0, 0.0, 0.0};
    const std::array<bool, 3> all_off = {false, false, false};
    expect_close(visibility_coefficients(projection, none),
                 subset_coefficients(projection, all_off), 1e-12, "all off");
}

TEST(ShProjection, RejectsBadInput) {
    const HdrImage image = test::random_map(8, 4, 1);
    EXPECT_THROW(project_environment(image, {}, 0), Error);
    EXPECT_THROW(project_environment(image, {}, kMaxShOrder + 1), Error);
    const std::vector<std::vector<std::uint32_t>> outside = {{0, 32}};
    try {
        project_environment(image, outside, 3);
        FAIL() << "index 32 of an 8x4 map accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
    }
    HdrImage broken = image;
    broken.pixels.pop_back();
    EXPECT_THROW(project_environment(broken, {}, 3), Error);
    EXPECT_THROW(project_environment(HdrImage(), {}, 3), Error);

    const std::vector<std::vector<std::uint32_t>> masks = {{1, 2}, {5}};
    const ShProjection projection = project_environment(image, masks, 3);
    const std::array<bool, 1> one_flag = {true};
    try {
        subset_coefficients(projection, one_flag);
        FAIL() << "one flag for two lights accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
    }
    const std::array<double, 3> three = {1.0, 1.0, 1.0};
    EXPECT_THROW(visibility_coefficients(projection, three), Error);
    const std::array<double, 2> out_of_range = {1.5, 0.0};
    EXPECT_THROW(visibility_coefficients(projection, out_of_range), Error);
}
