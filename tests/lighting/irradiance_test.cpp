#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/reference_irradiance.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "sh_test_support.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

ShRgb random_sh(int order, std::uint32_t seed) {
    ShRgb sh(order);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (glm::dvec3& c : sh.coefficients) {
        c = {uniform(rng), uniform(rng), uniform(rng)};
    }
    return sh;
}

std::vector<glm::dvec3> irradiance_at(const ShRgb& radiance, const std::vector<glm::dvec3>& normals,
                                      const ShWindow& window = {}) {
    const ShRgb e = irradiance_coefficients(radiance, window);
    std::vector<glm::dvec3> result;
    for (const glm::dvec3& n : normals) {
        result.push_back(e.evaluate(n));
    }
    return result;
}

// A dim sky with one small, very bright light (a "sun" of a few pixels): rings at order >= 3.
HdrImage sun_map(int width, int height, int sun_x, int sun_y, int sun_size, float sun_radiance,
                 std::vector<std::uint32_t>* sun_pixels) {
    HdrImage image = test::constant_map(width, height, {0.2f, 0.25f, 0.3f});
    for (int y = sun_y; y < sun_y + sun_size; ++y) {
        for (int x = sun_x; x < sun_x + sun_size; ++x) {
            image.set(std::size_t(y) * width + x,
                      {sun_radiance, sun_radiance, 0.8f * sun_radiance});
            if (sun_pixels != nullptr) {
                sun_pixels->push_back(std::uint32_t(y * width + x));
            }
        }
    }
    return image;
}

}  // namespace

TEST(Irradiance, BandFactorsAreTheClampedCosineExpansion) {
    // A_l = 2 pi integral_0^1 t P_l(t) dt, by a Gauss rule exact for the degree l + 1 integrand.
    const test::GaussLegendre rule(12);
    for (int l = 0; l < kMaxShOrder; ++l) {
        double integral = 0.0;
        for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
            const double t = 0.5 * (rule.nodes[i] + 1.0);
            integral += 0.5 * rule.weights[i] * t * test::legendre_p(l, t);
        }
        EXPECT_NEAR(lambertian_band_factor(l), 2.0 * pi * integral, 1e-13) << "band " << l;
    }
    EXPECT_NEAR(lambertian_band_factor(0), pi, 1e-15);
    EXPECT_NEAR(lambertian_band_factor(1), 2.0 * pi / 3.0, 1e-15);
    EXPECT_NEAR(lambertian_band_factor(2), pi / 4.0, 1e-15);
    EXPECT_EQ(lambertian_band_factor(3), 0.0);
    EXPECT_NEAR(lambertian_band_factor(4), -pi / 24.0, 1e-15);
    EXPECT_NEAR(lambertian_band_factor(6), pi / 64.0, 1e-15);
    EXPECT_THROW(lambertian_band_factor(-1), Error);
}

TEST(Irradiance, WindowFactors) {
    EXPECT_EQ((ShWindow{WindowKind::None, 0.0}).factor(7), 1.0);
    const ShWindow hanning{WindowKind::Hanning, 4.0};
    EXPECT_DOUBLE_EQ(hanning.factor(0), 1.0);
    EXPECT_NEAR(hanning.factor(2), 0.5, 1e-15);
    EXPECT_NEAR(hanning.factor(1), (1.0 + std::cos(pi / 4.0)) / 2.0, 1e-15);
    EXPECT_EQ(hanning.factor(4), 0.0);
    EXPECT_EQ(hanning.factor(9), 0.0);
    const ShWindow lanczos{WindowKind::Lanczos, 4.0};
    EXPECT_DOUBLE_EQ(lanczos.factor(0), 1.0);
    EXPECT_NEAR(lanczos.factor(2), 2.0 / pi, 1e-15);
    EXPECT_NEAR(lanczos.factor(1), std::sin(pi / 4.0) / (pi / 4.0), 1e-15);
    EXPECT_EQ(lanczos.factor(4), 0.0);
    EXPECT_THROW((ShWindow{WindowKind::Hanning, 0.0}).factor(1), Error);
    EXPECT_THROW((ShWindow{WindowKind::Lanczos, -2.0}).factor(1), Error);
}

TEST(Irradiance, WindowKindNames) {
    for (const WindowKind kind : {WindowKind::None, WindowKind::Hanning, WindowKind::Lanczos}) {
        EXPECT_EQ(window_kind_from_string(to_string(kind)), kind);
    }
    EXPECT_EQ(to_string(WindowKind::Hanning), "hanning");
    EXPECT_EQ(window_kind_from_string("lanczos"), WindowKind::Lanczos);
    EXPECT_EQ(window_kind_from_string("none"), WindowKind::None);
    try {
        window_kind_from_string("hamming");
        FAIL() << "unknown window accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("hamming"), std::string::npos) << e.what();
    }
}

TEST(Irradiance, CoefficientsAreWindowedBandFactorsTimesRadiance) {
    const ShRgb radiance = random_sh(5, 1);
    const ShWindow window{WindowKind::Hanning, 4.5};
    const ShRgb e = irradiance_coefficients(radiance, window);
    ASSERT_EQ(e.order, 5);
    for (int l = 0; l < 5; ++l) {
        for (int m = -l; m <= l; ++m) {
            const int i = sh_index(l, m);
            const double w = (1.0 + std::cos(pi * l / 4.5)) / 2.0;
            const glm::dvec3 expected = lambertian_band_factor(l) * w * radiance.coefficients[i];
            EXPECT_NEAR(glm::length(e.coefficients[i] - expected), 0.0, 1e-15) << l << ", " << m;
        }
    }
}

TEST(Irradiance, MatricesReproduceOrder3Irradiance) {
    const std::vector<glm::dvec3> normals = fibonacci_sphere(300);
    for (const int order : {3, 5}) {
        const ShRgb radiance = random_sh(order, 10 + order);
        const std::array<glm::dmat4, 3> m = irradiance_matrices(radiance);
        const ShRgb e = irradiance_coefficients(radiance.truncated(3));
        // Scale: the sum of |A_l L_lm Y_lm| bounds every term the rounded constants multiply.
        double scale = 0.0;
        for (const glm::dvec3& c : e.coefficients) {
            scale += glm::length(c);
        }
        for (const glm::dvec3& n : normals) {
            const glm::dvec4 h(n, 1.0);
            const glm::dvec3 expected = e.evaluate(n);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(glm::dot(h, m[c] * h), expected[c], 1e-6 * scale);
            }
        }
    }
    EXPECT_THROW(irradiance_matrices(random_sh(2, 1)), Error);
}

TEST(Irradiance, ConstantEnvironmentGivesPiLAtEveryOrder) {
    // The pixel-centre quadrature of the projection is second order in the pixel size: at
    // 2048x1024 the higher bands pick up ~5e-7 relative (measured), at 256x128 ~3e-5.
    const glm::vec3 radiance(0.7f, 1.0f, 2.5f);
    const HdrImage image = test::constant_map(2048, 1024, radiance);
    const std::vector<glm::dvec3> normals = fibonacci_sphere(500);
    for (int order = 1; order <= 9; ++order) {
        const ShProjection p = project_environment(image, {}, order);
        const std::vector<glm::dvec3> e = irradiance_at(p.all, normals);
        for (std::size_t i = 0; i < normals.size(); ++i) {
            for (int c = 0; c < 3; ++c) {
                ASSERT_NEAR(e[i][c] / (pi * radiance[c]), 1.0, 1e-6) << "order " << order;
            }
        }
    }
}

TEST(Irradiance, SinglePixelMatchesTruncatedClampedCosine) {
    const int width = 256, height = 128;
    const std::vector<glm::dvec3> normals = fibonacci_sphere(2000);
    for (const auto& [px, py] : {std::pair{40, 30}, {200, 64}, {7, 0}, {128, 127}}) {
        HdrImage image(width, height);
        image.set(std::size_t(py) * width + px, {1000.0f, 500.0f, 250.0f});
        const glm::dvec3 d = equirect::pixel_direction(px, py, width, height);
        const double intensity = 1000.0 * equirect::pixel_solid_angle(py, width, height);
        const ShProjection p = project_environment(image, {}, 9);
        std::array<double, 3> error_to_clamped{};
        int index = 0;
        for (const int order : {3, 5, 9}) {
            const std::vector<glm::dvec3> e = irradiance_at(p.all.truncated(order), normals);
            double squared = 0.0, norm = 0.0;
            for (std::size_t i = 0; i < normals.size(); ++i) {
                const double t = glm::dot(normals[i], d);
                double expected = 0.0;
                for (int l = 0; l < order; ++l) {
                    expected += lambertian_band_factor(l) * (2.0 * l + 1.0) / (4.0 * pi) *
                                test::legendre_p(l, t) * intensity;
                }
                ASSERT_NEAR(e[i].x, expected, 1e-6 * intensity) << "order " << order;
                ASSERT_NEAR(e[i].z, expected / 4.0, 1e-6 * intensity) << "order " << order;
                const double clamped = intensity * std::max(0.0, t);
                squared += (e[i].x - clamped) * (e[i].x - clamped);
                norm += clamped * clamped;
            }
            error_to_clamped[index++] = std::sqrt(squared / norm);
        }
        std::printf(
            "single pixel (%d, %d): relative RMS to I max(0, n.d): order 3 %.4f, 5 %.4f, "
            "9 %.4f\n",
            px, py, error_to_clamped[0], error_to_clamped[1], error_to_clamped[2]);
        EXPECT_LT(error_to_clamped[1], error_to_clamped[0]);
        EXPECT_LT(error_to_clamped[2], error_to_clamped[1]);
    }
}

TEST(Irradiance, MinRelativeIrradianceIsTheWorstSubset) {
    // Brute force over the 2^3 subsets with subset_coefficients, on the documented normals.
    std::vector<std::uint32_t> sun;
    HdrImage image = sun_map(128, 64, 30, 20, 2, 4000.0f, &sun);
    std::vector<std::uint32_t> second, third;
    for (int x = 90; x < 100; ++x) {
        second.push_back(std::uint32_t(40 * 128 + x));
        image.set(40 * 128 + x, {50.0f, 10.0f, 5.0f});
        third.push_back(std::uint32_t(5 * 128 + x));
        image.set(5 * 128 + x, {3.0f, 30.0f, 60.0f});
    }
    const std::vector<std::vector<std::uint32_t>> masks = {sun, second, third};
    const ShProjection projection = project_environment(image, masks, 5);
    const std::vector<glm::dvec3> normals = fibonacci_sphere(2048);
    for (const ShWindow window :
         {ShWindow{}, ShWindow{WindowKind::Hanning, 6.0}, ShWindow{WindowKind::Lanczos, 3.0}}) {
        glm::dvec3 lowest(HUGE_VAL), highest(-HUGE_VAL);
        for (int subset = 0; subset < 8; ++subset) {
            const std::array<bool, 3> on = {(subset & 1) != 0, (subset & 2) != 0,
                                            (subset & 4) != 0};
            const std::vector<glm::dvec3> e =
                irradiance_at(subset_coefficients(projection, on), normals, window);
            for (const glm::dvec3& value : e) {
                lowest = glm::min(lowest, value);
                if (subset == 7) {
                    highest = glm::max(highest, value);
                }
            }
        }
        const double expected =
            std::min({0.0, lowest.x / highest.x, lowest.y / highest.y, lowest.z / highest.z});
        EXPECT_NEAR(min_relative_irradiance(projection, window), expected, 1e-12)
            << to_string(window.kind);
    }
}

TEST(Irradiance, DeringingWindowIsTheWeakestThatRemovesNegativeIrradiance) {
    std::vector<std::uint32_t> sun;
    const HdrImage image = sun_map(256, 128, 60, 40, 2, 20000.0f, &sun);
    const std::vector<std::vector<std::uint32_t>> masks = {sun};
    for (const int order : {3, 5, 8}) {
        const ShProjection projection = project_environment(image, masks, order);
        const double unwindowed = min_relative_irradiance(projection, {});
        ASSERT_LT(unwindowed, -1e-6) << "the test map should ring at order " << order;
        for (const WindowKind kind : {WindowKind::Hanning, WindowKind::Lanczos}) {
            const ShWindow window = choose_deringing_window(projection, kind);
            ASSERT_EQ(window.kind, kind);
            const double chosen = min_relative_irradiance(projection, window);
            const double weaker = min_relative_irradiance(projection, {kind, window.cutoff * 1.05});
            std::printf("order %d %s: unwindowed %.4f, cutoff %.4f gives %.2e, +5%% gives %.2e\n",
                        order, to_string(kind).c_str(), unwindowed, window.cutoff, chosen, weaker);
            EXPECT_GE(chosen, -1e-9);
            EXPECT_LT(weaker, -1e-9);
        }
    }
}

TEST(Irradiance, DeringingConsidersEverySubset) {
    // A broad bright "light" fills the negative lobes of a small sun: with every light on there
    // is no ringing, but with the broad light off the sun alone rings.
    HdrImage image = test::constant_map(128, 64, {0.0f, 0.0f, 0.0f});
    std::vector<std::uint32_t> sun, broad;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 128; ++x) {
            const std::uint32_t i = std::uint32_t(y * 128 + x);
            if (y >= 30 && y < 32 && x >= 60 && x < 62) {
                image.set(i, glm::vec3(300.0f));
                sun.push_back(i);
            } else {
                image.set(i, glm::vec3(5.0f));
                broad.push_back(i);
            }
        }
    }
    const std::vector<std::vector<std::uint32_t>> masks = {sun, broad};
    const ShProjection projection = project_environment(image, masks, 3);
    const std::vector<glm::dvec3> all_on = irradiance_at(projection.all, fibonacci_sphere(2048));
    for (const glm::dvec3& e : all_on) {
        ASSERT_GT(std::min({e.x, e.y, e.z}), 0.0);
    }
    const ShWindow window = choose_deringing_window(projection, WindowKind::Hanning);
    EXPECT_EQ(window.kind, WindowKind::Hanning);
    EXPECT_GE(min_relative_irradiance(projection, window), -1e-9);
}

TEST(Irradiance, SmoothMapNeedsNoWindow) {
    // A sky gradient: brighter above, no small light.
    HdrImage image(256, 128);
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x < 256; ++x) {
            const glm::dvec3 d = equirect::pixel_direction(x, y, 256, 128);
            const float value = float(1.0 + 0.6 * d.y + 0.2 * d.x);
            image.set(std::size_t(y) * 256 + x, {value, value, 1.2f * value});
        }
    }
    for (const int order : {3, 6}) {
        const ShProjection projection = project_environment(image, {}, order);
        EXPECT_GE(min_relative_irradiance(projection, {}), 0.0);
        EXPECT_EQ(choose_deringing_window(projection, WindowKind::Hanning).kind, WindowKind::None);
        EXPECT_EQ(choose_deringing_window(projection, WindowKind::Lanczos).kind, WindowKind::None);
    }
}
