// SH rotation (sh_rotation.hpp): the rotated coefficients evaluate to the function turned, the
// same as turning the map and projecting it again, and compose as rotations do.
#include "oer/lighting/sh_rotation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "oer/core/error.hpp"
#include "oer/core/image.hpp"
#include "oer/lighting/sh_projection.hpp"

namespace oer {
namespace {

glm::dmat3 axis_rotation(glm::dvec3 axis, double angle) {
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis)));
}

ShRgb random_sh(int order, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    ShRgb sh(order);
    for (glm::dvec3& c : sh.coefficients) {
        c = {uniform(random), uniform(random), uniform(random)};
    }
    return sh;
}

glm::dvec3 random_direction(std::mt19937& random) {
    std::normal_distribution<double> normal;
    return glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
}

TEST(ShRotation, RotatedCoefficientsEvaluateToTheTurnedFunction) {
    for (const int order : {1, 3, 9, kMaxShOrder}) {
        SCOPED_TRACE("order " + std::to_string(order));
        const ShRgb f = random_sh(order, 7u + unsigned(order));
        const glm::dmat3 rotation = axis_rotation({0.3, -0.8, 0.5}, 1.1);
        const ShRgb g = rotate_sh(f, rotation);
        std::mt19937 random(11);
        double worst = 0.0;
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 d = random_direction(random);
            const glm::dvec3 expected = f.evaluate(glm::transpose(rotation) * d);
            worst = std::max(worst, glm::length(g.evaluate(d) - expected));
        }
        EXPECT_LT(worst, 1e-9 * order * order);
    }
}

TEST(ShRotation, RotationsComposeAndTheIdentityChangesNothing) {
    const ShRgb f = random_sh(7, 3u);
    const glm::dmat3 a = axis_rotation({1, 0, 0}, 0.4);
    const glm::dmat3 b = axis_rotation({0, 1, 1}, -2.0);
    const ShRgb twice = rotate_sh(rotate_sh(f, a), b);
    const ShRgb once = rotate_sh(f, b * a);
    const ShRgb same = rotate_sh(f, glm::dmat3(1.0));
    for (std::size_t i = 0; i < f.coefficients.size(); ++i) {
        EXPECT_LT(glm::length(twice.coefficients[i] - once.coefficients[i]), 1e-12) << i;
        EXPECT_LT(glm::length(same.coefficients[i] - f.coefficients[i]), 1e-13) << i;
    }
}

// Turning an equirect map about +Y by a whole number of columns permutes its pixels, so its
// projection is exactly the projection of the unturned map, rotated.
TEST(ShRotation, MatchesTurningTheMapAndProjectingAgain) {
    const int width = 256, height = 128, shift = 37;
    HdrImage map(width, height);
    HdrImage turned(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float value = float(1.0 + std::sin(0.11 * x * x + 0.3 * y) +
                                      (x > 40 && x < 60 && y > 20 && y < 35 ? 50.0 : 0.0));
            map.at(x, y)[0] = value;
            map.at(x, y)[1] = 0.5f * value;
            map.at(x, y)[2] = float(y);
        }
    }
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c) {
                turned.at((x + shift) % width, y)[c] = map.at(x, y)[c];
            }
        }
    }
    const int order = 9;
    const ShRgb original = project_environment(map, {}, order).all;
    const ShRgb reprojected = project_environment(turned, {}, order).all;
    // docs/design.md section 3: u = (phi + pi) / 2 pi with phi = atan2(z, x); a shift of `shift`
    // columns adds alpha to phi, a turn about +Y taking x towards z.
    const double alpha = 2.0 * std::numbers::pi * shift / width;
    const glm::dmat3 rotation(std::cos(alpha), 0.0, std::sin(alpha), 0.0, 1.0, 0.0,
                              -std::sin(alpha), 0.0, std::cos(alpha));
    const ShRgb rotated = rotate_sh(original, rotation);
    double scale = 0.0;
    for (const glm::dvec3& c : reprojected.coefficients) {
        scale = std::max(scale, glm::length(c));
    }
    for (std::size_t i = 0; i < rotated.coefficients.size(); ++i) {
        EXPECT_LT(glm::length(rotated.coefficients[i] - reprojected.coefficients[i]), 1e-9 * scale)
            << "coefficient " << i;
    }
}

TEST(ShRotation, RefusesMatricesThatAreNotOrthogonalAndBandsOutOfRange) {
    try {
        sh_band_transform(2, glm::dmat3(2.0));
        FAIL() << "a scaling accepted";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("not orthogonal"), std::string::npos)
            << error.what();
    }
    EXPECT_THROW(sh_band_transform(kMaxShOrder, glm::dmat3(1.0)), Error);
    EXPECT_THROW(sh_band_transform(-1, glm::dmat3(1.0)), Error);
}

}  // namespace
}  // namespace oer
