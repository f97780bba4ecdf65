// The literal thesis baseline of the preprocessing benchmark (bench/support/literal_thesis.hpp):
// its figures must be right for the benchmark's comparison to mean anything.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "literal_thesis.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/sh_projection.hpp"

using namespace oer;
using namespace oer::bench;
using std::numbers::pi;

namespace {

glm::dvec3 direction_of(double azimuth_degrees, double elevation_degrees) {
    const double phi = azimuth_degrees * pi / 180.0;
    const double elevation = elevation_degrees * pi / 180.0;
    return {std::cos(elevation) * std::cos(phi), std::sin(elevation),
            std::cos(elevation) * std::sin(phi)};
}

struct SkyDisc {
    glm::dvec3 centre;
    double radius_degrees;
    glm::vec3 radiance;
};

// A dim sky, brightest towards +X, with bright discs. (A sky whose brightest pixels form a
// band, at the horizon or the zenith, draws the thesis's pixel-space clusters into the band
// and merges discs near it with the sky: the literal algorithm's weakness, not tested here.)
HdrImage sky_with_discs(int width, int height, const std::vector<SkyDisc>& discs) {
    HdrImage image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d = equirect::pixel_direction(x, y, width, height);
            glm::vec3 value = glm::vec3(0.2f, 0.22f, 0.25f) * float(1.0 + 0.3 * d.x);
            for (const SkyDisc& disc : discs) {
                if (glm::dot(d, disc.centre) >= std::cos(disc.radius_degrees * pi / 180.0)) {
                    value = disc.radiance;
                }
            }
            image.set(std::size_t(y) * std::size_t(width) + std::size_t(x), value);
        }
    }
    return image;
}

// Share of the map's (unblurred) luminance inside the disc: what the light of that disc
// should report as luminanceLoss, up to the few sky pixels of its halo.
double disc_share(const HdrImage& image, const SkyDisc& disc) {
    double inside = 0.0, total = 0.0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const float* p = image.at(x, y);
            const double l = 0.265 * p[0] + 0.670 * p[1] + 0.065 * p[2];
            total += l;
            if (glm::dot(equirect::pixel_direction(x, y, image.width, image.height), disc.centre) >=
                std::cos(disc.radius_degrees * pi / 180.0)) {
                inside += l;
            }
        }
    }
    return inside / total;
}

// The first 9 real SH in closed form with exact constants, written here (not taken from the
// code under test).
std::array<double, 9> closed_form_sh3(const glm::dvec3& d) {
    const double c0 = 0.5 / std::sqrt(pi), c1 = std::sqrt(3.0 / (4.0 * pi)),
                 c2 = 0.5 * std::sqrt(15.0 / pi), c3 = 0.25 * std::sqrt(5.0 / pi),
                 c4 = 0.25 * std::sqrt(15.0 / pi);
    return {c0,
            c1 * d.y,
            c1 * d.z,
            c1 * d.x,
            c2 * d.x * d.y,
            c2 * d.y * d.z,
            c3 * (3.0 * d.z * d.z - 1.0),
            c2 * d.x * d.z,
            c4 * (d.x * d.x - d.y * d.y)};
}

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
}

}  // namespace

TEST(LiteralThesis, ConstantMapProjectsOntoTheFirstCoefficientOnly) {
    const int w = 256, h = 128;
    const glm::vec3 radiance(1.0f, 0.5f, 2.0f);
    HdrImage image(w, h);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, radiance);
    }
    const LiteralSh3 c = literal_project_order3(image);
    for (int channel = 0; channel < 3; ++channel) {
        // The exact solid angles sum to 4 pi, so c_00 = L Y_00 4 pi = 2 sqrt(pi) L.
        const double expected = 2.0 * std::sqrt(pi) * radiance[channel];
        EXPECT_NEAR(c[0][channel], expected, 1e-12 * expected);
        // Odd in x, y or z: zero by the symmetry of the pixel grid, to rounding.
        for (const int i : {1, 2, 3, 4, 5, 7}) {
            EXPECT_NEAR(c[i][channel], 0.0, 1e-9 * expected) << "coefficient " << i;
        }
        // 3 z^2 - 1 and x^2 - y^2 vanish only in the limit: the pixel-centre sampling of each
        // row's direction leaves an O((pi / H)^2) error.
        for (const int i : {6, 8}) {
            EXPECT_NEAR(c[i][channel], 0.0, std::pow(pi / h, 2) * expected) << "coefficient " << i;
        }
    }
}

TEST(LiteralThesis, BasisIsOrthonormalUnderTheProjection) {
    // A map whose radiance is Y_i projects onto coefficient i only, with value 1.
    const int w = 512, h = 256;
    for (int i = 0; i < 9; ++i) {
        HdrImage image(w, h);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const float value =
                    float(closed_form_sh3(equirect::pixel_direction(x, y, w, h))[i]);
                image.set(std::size_t(y) * w + x, glm::vec3(value));
            }
        }
        const LiteralSh3 c = literal_project_order3(image);
        for (int j = 0; j < 9; ++j) {
            EXPECT_NEAR(c[j].g, i == j ? 1.0 : 0.0, 2e-4) << "Y_" << i << " onto " << j;
        }
    }
}

TEST(LiteralThesis, BasisMatchesTheClosedFormsOfRamamoorthiAndHanrahan) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    const std::array<double, 9> y = literal_sh3_basis(d);
    const double expected[9] = {0.282095,
                                0.488603 * d.y,
                                0.488603 * d.z,
                                0.488603 * d.x,
                                1.092548 * d.x * d.y,
                                1.092548 * d.y * d.z,
                                0.315392 * (3.0 * d.z * d.z - 1.0),
                                1.092548 * d.x * d.z,
                                0.546274 * (d.x * d.x - d.y * d.y)};
    for (int i = 0; i < 9; ++i) {
        EXPECT_NEAR(y[i], expected[i], 1e-6) << i;
    }
}

TEST(LiteralThesis, BlurClampsAtTheSeamInsteadOfWrapping) {
    const int w = 64, h = 32;
    HdrImage image(w, h);
    for (int y = 0; y < h; ++y) {
        image.set(std::size_t(y) * w, glm::vec3(1.0f));  // a bright first column
    }
    const std::vector<double> l = literal_luminance(image, 4);
    const double full = 179.0 * (0.265 + 0.670 + 0.065);
    for (int y = 0; y < h; ++y) {
        EXPECT_GT(l[std::size_t(y) * w], 0.2 * full);
        EXPECT_GT(l[std::size_t(y) * w + 4], 0.0);
        EXPECT_EQ(l[std::size_t(y) * w + w - 1], 0.0) << "the blur wrapped across the seam";
    }
    // Clamping keeps a constant map constant, borders included.
    HdrImage constant(w, h);
    for (std::size_t i = 0; i < constant.pixel_count(); ++i) {
        constant.set(i, glm::vec3(2.0f));
    }
    for (const double value : literal_luminance(constant, 4)) {
        EXPECT_NEAR(value, 2.0 * full, 1e-4);
    }
}

TEST(LiteralThesis, FindsASingleDiscWithinTwoPixels) {
    const int w = 512, h = 256;
    const glm::dvec3 centre = direction_of(40.0, 30.0);
    const SkyDisc disc{centre, 3.0, glm::vec3(50.0f, 45.0f, 40.0f)};
    const HdrImage image = sky_with_discs(w, h, {disc});
    LiteralOptions options;
    options.light_count = 1;
    const std::vector<LiteralLight> lights = literal_locate_lights(image, options);
    ASSERT_EQ(lights.size(), 1u);
    EXPECT_LT(angle_between(lights[0].direction, centre), 2.0 * pi / h)
        << "found centre at pixel (" << lights[0].centre_x << ", " << lights[0].centre_y << ")";
    const double share = disc_share(image, disc);
    EXPECT_NEAR(lights[0].luminance_loss, share, 0.1 * share);
}

TEST(LiteralThesis, ThreeDiscsGiveThreeLightsAndEightOccludedMaps) {
    const int w = 512, h = 256;
    const std::vector<SkyDisc> discs = {
        {direction_of(-100.0, 20.0), 3.5, glm::vec3(40.0f, 38.0f, 30.0f)},
        {direction_of(0.0, 45.0), 2.5, glm::vec3(60.0f, 70.0f, 90.0f)},
        {direction_of(110.0, 10.0), 2.0, glm::vec3(120.0f, 80.0f, 50.0f)},
    };
    const HdrImage image = sky_with_discs(w, h, discs);
    LiteralOptions options;
    options.light_count = 3;
    const LiteralResult result = literal_thesis_preprocess(image, options);
    ASSERT_EQ(result.lights.size(), 3u);
    ASSERT_EQ(result.oems.size(), 8u);

    // Each disc found once, within two pixels; masks disjoint; shares add up to at most 1.
    std::vector<bool> matched(discs.size(), false);
    std::vector<bool> claimed(image.pixel_count(), false);
    double shares = 0.0;
    for (const LiteralLight& light : result.lights) {
        std::size_t nearest = 0;
        for (std::size_t k = 1; k < discs.size(); ++k) {
            if (angle_between(light.direction, discs[k].centre) <
                angle_between(light.direction, discs[nearest].centre)) {
                nearest = k;
            }
        }
        EXPECT_FALSE(matched[nearest]) << "disc " << nearest << " found twice";
        matched[nearest] = true;
        EXPECT_LT(angle_between(light.direction, discs[nearest].centre), 2.0 * pi / h)
            << "disc " << nearest;
        for (const std::uint32_t i : light.pixels) {
            EXPECT_FALSE(claimed[i]) << "pixel " << i << " in two lights";
            claimed[i] = true;
        }
        const double share = disc_share(image, discs[nearest]);
        EXPECT_NEAR(light.luminance_loss, share, 0.1 * share) << "disc " << nearest;
        shares += light.luminance_loss;
    }
    EXPECT_LE(shares, 1.0);

    // All on is the plain map; every subset is the map with the lights off blackened, whose
    // coefficients the library's separable projection (oer::project_environment, an
    // independent implementation of the same sum) gives to rounding.
    for (std::size_t s = 0; s < result.oems.size(); ++s) {
        HdrImage occluded = image;
        for (std::size_t k = 0; k < 3; ++k) {
            if (!((s >> k) & 1u)) {
                for (const std::uint32_t i : result.lights[k].pixels) {
                    occluded.set(i, glm::vec3(0.0f));
                }
            }
        }
        const ShRgb expected = project_environment(occluded, {}, 3).all;
        for (int i = 0; i < 9; ++i) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(result.oems[s][i][c], expected.coefficients[i][c], 1e-9)
                    << s << " " << i;
            }
        }
    }
    // Switching any light off lowers c_00.
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t all_but_k = 7u & ~(std::size_t(1) << k);
        EXPECT_LT(result.oems[all_but_k][0].g, result.oems[7][0].g);
    }
}
