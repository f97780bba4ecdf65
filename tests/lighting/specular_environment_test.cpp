// The prefiltered cubes (oer/lighting/specular_environment.hpp): the furnace, a small bright
// disc (where level 0 shows it, energy per level, the peak's place and fall), the residual
// against the map with the lights' pixels zeroed, each light's cube against its pixels alone,
// a soft box's shape at every roughness against the exact integral, GL's face order and
// orientation, a compact light's peak between levels, and the stored form with each way it is
// refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "synthetic_maps.hpp"

using namespace oer;
using oer::testing::constant_map;
using oer::testing::disc_map;
using oer::testing::DiscLight;

namespace {

constexpr double kPi = std::numbers::pi;

SpecularOptions small_options() {
    SpecularOptions options;
    options.face_size = 32;
    options.levels = 4;
    options.samples = 32;
    options.light_face_size = 16;
    return options;
}

glm::dvec3 texel(const PrefilteredCube& cube, int level, int face, int i, int j, int layer = 0) {
    const int n = cube.face_size >> level;
    const std::size_t at = (((std::size_t(layer) * 6 + face) * n + j) * n + i) * 3;
    const std::vector<std::uint16_t>& texels = cube.rgb_half[std::size_t(level)];
    return {glm::unpackHalf1x16(texels[at]), glm::unpackHalf1x16(texels[at + 1]),
            glm::unpackHalf1x16(texels[at + 2])};
}

// The OpenGL cube-map table (OpenGL 4.6 section 8.13) written out again, independently of the
// library: the direction through (s, t) of a face, faces +X, -X, +Y, -Y, +Z, -Z.
glm::dvec3 gl_direction(int face, double s, double t) {
    const double sc = 2.0 * s - 1.0, tc = 2.0 * t - 1.0;
    const std::array<glm::dvec3, 6> directions = {
        glm::dvec3(1.0, -tc, -sc), glm::dvec3(-1.0, -tc, sc), glm::dvec3(sc, 1.0, tc),
        glm::dvec3(sc, -1.0, -tc), glm::dvec3(sc, -tc, 1.0),  glm::dvec3(-sc, -tc, -1.0)};
    return glm::normalize(directions[std::size_t(face)]);
}

// Exact solid angle of texel (i, j) of an n x n face: the integral of the cube's Jacobian,
// F(x1, y1) - F(x0, y1) - F(x1, y0) + F(x0, y0) with F(x, y) = atan2(x y, sqrt(x^2 + y^2 + 1))
// over the texel's corners in [-1, 1]^2.
double texel_solid_angle(int n, int i, int j) {
    const auto f = [](double x, double y) {
        return std::atan2(x * y, std::sqrt(x * x + y * y + 1));
    };
    const double x0 = 2.0 * i / n - 1.0, x1 = 2.0 * (i + 1) / n - 1.0;
    const double y0 = 2.0 * j / n - 1.0, y1 = 2.0 * (j + 1) / n - 1.0;
    return f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0);
}

// Mean radiance of one level of a layer over the sphere (sum of radiance x texel solid angle, / 4
// pi).
glm::dvec3 level_mean(const PrefilteredCube& cube, int level, int layer = 0) {
    const int n = cube.face_size >> level;
    glm::dvec3 sum(0.0);
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                sum += texel(cube, level, face, i, j, layer) * texel_solid_angle(n, i, j);
            }
        }
    }
    return sum / (4.0 * kPi);
}

glm::dvec3 map_mean(const HdrImage& map) {
    const equirect::Grid grid(map.width, map.height);
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        sum += glm::dvec3(map.rgb(i)) * grid.row_solid_angle[i / std::size_t(map.width)];
    }
    return sum / (4.0 * kPi);
}

template <typename Call>
std::string error_of(const Call& call) {
    try {
        call();
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput) << error.what();
        return error.what();
    }
    ADD_FAILURE() << "no oer::Error thrown";
    return "";
}

// The prefiltering kernel about r of perceptual roughness `roughness` at angle theta from r:
// GGX's D at the half angle theta / 2 (n = v = r), times n.l (Walter et al. 2007, Karis 2013).
double kernel(double theta, double roughness) {
    const double alpha2 = std::pow(roughness, 4.0);
    const double cos_h = std::cos(theta / 2.0);
    const double denominator = cos_h * cos_h * (alpha2 - 1.0) + 1.0;
    return alpha2 / (kPi * denominator * denominator) * std::cos(theta);
}

// The exact prefiltered radiance at the centre of a disc of radiance L and angular radius
// `radius` on black: L times the kernel's share within the disc, by the midpoint rule.
double disc_centre_radiance(double radiance, double radius, double roughness) {
    const auto integral = [&](double to) {
        constexpr int steps = 20000;
        double sum = 0.0;
        for (int k = 0; k < steps; ++k) {
            const double theta = (k + 0.5) * to / steps;
            sum += kernel(theta, roughness) * std::sin(theta);
        }
        return sum * to / steps;
    };
    return radiance * integral(radius) / integral(kPi / 2.0);
}

// The kernel's half width at half maximum, by bisection.
double kernel_half_width(double roughness) {
    double low = 0.0, high = kPi / 2.0;
    for (int k = 0; k < 60; ++k) {
        const double middle = 0.5 * (low + high);
        (kernel(middle, roughness) > 0.5 * kernel(0.0, roughness) ? low : high) = middle;
    }
    return low;
}

// The rig of `light_count` lights the service would build for `map`.
Rig rig_of(const HdrImage& map, int light_count) {
    RigOptions rig_options;
    rig_options.light_count = light_count;
    return build_rig(map, RepairCounts{}, rig_options);
}

const glm::dvec3 kDiscDirection = glm::normalize(glm::dvec3(0.3, 0.5, -0.8));
constexpr double kDiscRadius = 3.0 * kPi / 180.0;
constexpr float kDiscRadiance = 100.0f;

HdrImage one_disc_map() {
    return disc_map(1024, 512, glm::vec3(0.0f),
                    {DiscLight{kDiscDirection, kDiscRadius, glm::vec3(kDiscRadiance)}});
}

}  // namespace

// A constant map prefilters to itself at every texel of every level (every kernel is
// normalised), at the default options.
TEST(SpecularEnvironment, FurnaceEveryTexelOfEveryLevelIsTheConstant) {
    const glm::vec3 constant(0.5f, 1.0f, 2.0f);
    const PrefilteredCube cube = prefilter_map(constant_map(512, 256, constant));
    ASSERT_EQ(cube.face_size, 256);
    ASSERT_EQ(cube.levels, 6);
    ASSERT_EQ(cube.rgb_half.size(), 6u);
    double worst = 0.0;
    for (int level = 0; level < cube.levels; ++level) {
        const int n = cube.face_size >> level;
        ASSERT_EQ(cube.rgb_half[std::size_t(level)].size(), std::size_t(6 * n * n * 3));
        for (int face = 0; face < 6; ++face) {
            for (int j = 0; j < n; ++j) {
                for (int i = 0; i < n; ++i) {
                    const glm::dvec3 value = texel(cube, level, face, i, j);
                    for (int c = 0; c < 3; ++c) {
                        worst = std::max(worst, std::abs(value[c] / constant[c] - 1.0));
                    }
                }
            }
        }
    }
    EXPECT_LT(worst, 0.01);
}

// One small bright disc: level 0 shows its radiance and level 1 its exact convolution, every
// level keeps the map's energy (the GGX + n.l kernel is normalised and symmetric in r and l, so
// the mean of P over directions is the mean of L), and the peak stays at the disc and falls
// with roughness. With 64 samples the estimate's error grows with roughness (over 24 random
// directions, relative RMS at the disc's centre 2.7, 6.7, 13.6, 17.7 % at levels 1 to 4), so
// the peak is asked to lie within a third of the kernel's half width at half maximum (or two
// of the level's texels, or the disc).
TEST(SpecularEnvironment, SmallDiscKeepsItsRadianceEnergyAndPlace) {
    const HdrImage map = one_disc_map();
    const PrefilteredCube cube = prefilter_map(map);
    EXPECT_NEAR(sample_cube(cube, kDiscDirection, 0.0).r / kDiscRadiance, 1.0, 0.05);
    EXPECT_NEAR(
        sample_cube(cube, kDiscDirection, 1.0).r /
            disc_centre_radiance(kDiscRadiance, kDiscRadius, roughness_of_level(1, cube.levels)),
        1.0, 0.05);

    const double mean_l = map_mean(map).g;
    double previous_peak = 1e30;
    for (int level = 0; level < cube.levels; ++level) {
        EXPECT_NEAR(level_mean(cube, level).g / mean_l, 1.0, 0.02) << "level " << level;

        const int n = cube.face_size >> level;
        double peak = -1.0;
        glm::dvec3 peak_direction(0.0);
        for (int face = 0; face < 6; ++face) {
            for (int j = 0; j < n; ++j) {
                for (int i = 0; i < n; ++i) {
                    const double value = texel(cube, level, face, i, j).g;
                    if (value > peak) {
                        peak = value;
                        peak_direction = gl_direction(face, (i + 0.5) / n, (j + 0.5) / n);
                    }
                }
            }
        }
        // Two of the level's texels at a face centre are 2 (90 / n) degrees.
        const double allowed =
            std::max({kDiscRadius, 2.0 * (kPi / 2.0) / n,
                      kernel_half_width(roughness_of_level(level, cube.levels)) / 3.0});
        EXPECT_LT(std::acos(std::min(1.0, glm::dot(peak_direction, kDiscDirection))), allowed)
            << "level " << level;
        const double at_disc = sample_cube(cube, kDiscDirection, level).g;
        EXPECT_LT(at_disc, previous_peak) << "level " << level;
        previous_peak = at_disc;
    }
}

// The residual is the map with every light's pixels set to 0, prefiltered: the same bytes as
// prefilter_map of that map, and not those of the whole map.
TEST(SpecularEnvironment, ResidualIsTheMapWithItsLightsZeroed) {
    const HdrImage map =
        disc_map(512, 256, glm::vec3(0.2f, 0.25f, 0.3f),
                 {DiscLight{glm::dvec3(0.2, 1.0, 0.3), 0.08, glm::vec3(400.0f, 380.0f, 350.0f)},
                  DiscLight{glm::dvec3(-1.0, 0.3, -0.4), 0.05, glm::vec3(200.0f, 220.0f, 260.0f)}});
    const Rig rig = build_rig(map, RepairCounts{}, RigOptions{});
    ASSERT_GE(rig.lights.size(), 2u);
    HdrImage zeroed = map;
    for (const Light& light : rig.lights) {
        for (const std::uint32_t index : light.pixels) {
            zeroed.set(index, glm::vec3(0.0f));
        }
    }
    const auto residual = prefilter_residual(map, rig, small_options()).rgb_half;
    EXPECT_EQ(residual, prefilter_map(zeroed, small_options()).rgb_half);
    EXPECT_NE(residual, prefilter_map(map, small_options()).rgb_half);
    // Deterministic: a second run gives the same bytes.
    EXPECT_EQ(residual, prefilter_residual(map, rig, small_options()).rgb_half);
}

// Level 0 of layer k of the lights' cube is light k's pixels alone (black elsewhere) resampled
// at light_face_size, byte for byte as prefilter_map makes it; the lights' levels above keep
// their energy.
TEST(SpecularEnvironment, EachLightsLayerIsItsPixelsAlonePrefiltered) {
    const HdrImage map =
        disc_map(512, 256, glm::vec3(0.2f, 0.25f, 0.3f),
                 {DiscLight{glm::dvec3(0.2, 1.0, 0.3), 0.08, glm::vec3(400.0f, 380.0f, 350.0f)},
                  DiscLight{glm::dvec3(-1.0, 0.3, -0.4), 0.05, glm::vec3(200.0f, 220.0f, 260.0f)}});
    const Rig rig = build_rig(map, RepairCounts{}, RigOptions{});
    ASSERT_GE(rig.lights.size(), 2u);
    const SpecularOptions options;  // the lights' cubes at 128, the residual's at 256
    const SpecularEnvironment specular = prefilter_specular(map, rig, options);
    // Both discs lie wholly above the horizon: each is its own floor layer.
    ASSERT_EQ(specular.lights.layers, int(rig.lights.size()));
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        EXPECT_EQ(specular.floor_layers.at(k), int(k));
    }
    EXPECT_EQ(specular.lights.face_size, 128);
    EXPECT_EQ(specular.lights.levels, specular.residual.levels);
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        HdrImage alone(map.width, map.height);
        for (const std::uint32_t index : rig.lights[k].pixels) {
            alone.set(index, map.rgb(index));
        }
        SpecularOptions light_options = options;
        light_options.face_size = options.light_face_size;
        const PrefilteredCube expected = prefilter_map(alone, light_options);
        const std::vector<std::uint16_t>& all = specular.lights.rgb_half[0];
        const std::size_t per_layer = all.size() / rig.lights.size();
        const std::vector<std::uint16_t> layer(all.begin() + std::ptrdiff_t(k * per_layer),
                                               all.begin() + std::ptrdiff_t((k + 1) * per_layer));
        EXPECT_EQ(layer, expected.rgb_half[0]) << "light " << k;
    }
    // Each light's energy at every level is its energy at level 0 (its kernel sums to 1 about
    // each of its texels); with the residual's it is the whole map's, within the sampled
    // prefiltering's own error on a map with bright discs (the whole map's cube).
    const PrefilteredCube whole = prefilter_map(map, options);
    for (int level = 0; level < options.levels; ++level) {
        glm::dvec3 parts = level_mean(specular.residual, level);
        for (int k = 0; k < specular.lights.layers; ++k) {
            const glm::dvec3 light = level_mean(specular.lights, level, k);
            const glm::dvec3 at_level_0 = level_mean(specular.lights, 0, k);
            std::printf("[ measured ] level %d: light %d's energy over its level 0's %.4f\n", level,
                        k, light.g / at_level_0.g);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(light[c] / at_level_0[c], 1.0, 0.005) << "level " << level;
            }
            parts += light;
        }
        const glm::dvec3 expected = level_mean(whole, level);
        std::printf(
            "[ measured ] level %d: residual and lights over the whole map %.4f %.4f %.4f\n", level,
            parts.r / expected.r, parts.g / expected.g, parts.b / expected.b);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(parts[c] / expected[c], 1.0, 0.04) << "level " << level;
        }
    }
}

// A soft box, a rectangle of 30 x 8 degrees (a planar light seen from its centre), in its own
// cube: at every level its prefiltered radiance along the box's long and short axes is the
// exact integral of its pixels under the prefiltering kernel, so its reflection is as long and
// as narrow as the box at every roughness (a lobe about its direction would be round).
// Tolerance: 5 % of the level's peak (measured 1.2 to 4.5 %, the most at the coarse levels,
// 8 and 4 texels a face at roughness 0.55 and 1, read bilinearly; and the half floats, the source
// texels' size and the 128 texels' bilinear reads).
TEST(SpecularEnvironment, ASoftBoxKeepsItsShapeAtEveryRoughness) {
    const oer::testing::SoftBoxLight box{glm::normalize(glm::dvec3(0.4, 0.5, -0.7)),
                                         glm::radians(15.0), glm::radians(4.0), glm::vec3(50.0f)};
    const glm::dvec3 centre = box.direction, across = box.across(), up = box.up();
    const glm::vec3 radiance = box.radiance;
    const HdrImage map =
        oer::testing::with_soft_boxes(constant_map(1024, 512, glm::vec3(0.1f)), {box});
    const equirect::Grid grid(map.width, map.height);
    std::vector<std::size_t> box_pixels;
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        if (box.contains(grid.direction(i))) {
            box_pixels.push_back(i);
        }
    }
    const Rig rig = rig_of(map, 1);
    ASSERT_EQ(rig.lights.size(), 1u);
    // The light's pixels are the box's (the locator may take a rim of the background with it).
    double light_energy = 0.0, box_energy = 0.0;
    for (const std::uint32_t index : rig.lights[0].pixels) {
        light_energy += map.rgb(index).g * grid.row_solid_angle[index / std::size_t(map.width)];
    }
    for (const std::size_t index : box_pixels) {
        box_energy += radiance.g * grid.row_solid_angle[index / std::size_t(map.width)];
    }
    ASSERT_NEAR(light_energy / box_energy, 1.0, 0.02);
    const PrefilteredCube lights = prefilter_lights(map, rig).cube;

    // The exact P(d) of the light's pixels: sum of L K(d, l) dOmega over the normalisation
    // integral of K over the hemisphere (K = D(h) n.l, n = v = d; `kernel` above).
    const auto exact = [&](const glm::dvec3& d, double roughness) {
        double sum = 0.0;
        for (const std::uint32_t index : rig.lights[0].pixels) {
            const double angle =
                std::acos(std::clamp(glm::dot(d, grid.direction(index)), -1.0, 1.0));
            if (angle < kPi / 2.0) {
                sum += map.rgb(index).g * kernel(angle, roughness) *
                       grid.row_solid_angle[index / std::size_t(map.width)];
            }
        }
        constexpr int steps = 20000;
        double normalisation = 0.0;
        for (int k = 0; k < steps; ++k) {
            const double theta = (k + 0.5) * (kPi / 2.0) / steps;
            normalisation += kernel(theta, roughness) * std::sin(theta);
        }
        return sum / (2.0 * kPi * normalisation * (kPi / 2.0) / steps);
    };
    const auto towards = [&](const glm::dvec3& axis, double degrees) {
        return glm::normalize(std::cos(glm::radians(degrees)) * centre +
                              std::sin(glm::radians(degrees)) * axis);
    };
    for (int level = 1; level < lights.levels; ++level) {
        const double roughness = roughness_of_level(level, lights.levels);
        const double peak = exact(centre, roughness);
        double worst = 0.0;
        for (const double degrees : {0.0, 6.0, 12.0, 18.0, 25.0}) {
            for (const glm::dvec3& axis : {across, up}) {
                const glm::dvec3 d = towards(axis, degrees);
                worst = std::max(
                    worst, std::abs(sample_cube(lights, d, level).g - exact(d, roughness)) / peak);
            }
        }
        // The shape: 12 degrees along the box against 12 degrees across it.
        const double along = sample_cube(lights, towards(across, 12.0), level).g;
        const double sideways = sample_cube(lights, towards(up, 12.0), level).g;
        std::printf(
            "[ measured ] soft box, roughness %.2f: worst error %.4f of the peak %.3f; at 12 "
            "degrees along it %.3f, across it %.3f (exact %.3f, %.3f)\n",
            roughness, worst, peak, along, sideways, exact(towards(across, 12.0), roughness),
            exact(towards(up, 12.0), roughness));
        EXPECT_LT(worst, 0.05) << "roughness " << roughness;
    }
    // Level 0 is the box itself: inside and outside each of its edges.
    EXPECT_NEAR(sample_cube(lights, centre, 0.0).g, radiance.g, 0.01 * radiance.g);
    EXPECT_NEAR(sample_cube(lights, towards(across, 12.0), 0.0).g, radiance.g, 0.01 * radiance.g);
    EXPECT_LT(sample_cube(lights, towards(up, 6.0), 0.0).g, 0.01 * radiance.g);
    EXPECT_LT(sample_cube(lights, towards(across, 18.0), 0.0).g, 0.01 * radiance.g);
}

// Faces in GL's order and orientation: a map coloured by the dominant axis of each direction
// reads back each face's colour at its centre (raw texels and sample_cube), and a map linear
// in the direction has, at every texel of level 0, the value of GL's table's direction.
TEST(SpecularEnvironment, FacesFollowTheGlCubeMapTable) {
    const std::array<glm::vec3, 6> colours = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 1),
                                              glm::vec3(0, 1, 0), glm::vec3(1, 0, 1),
                                              glm::vec3(0, 0, 1), glm::vec3(1, 1, 0)};
    const std::array<glm::dvec3, 6> axes = {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0),
                                            glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0),
                                            glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)};
    HdrImage axis_map(512, 256), linear_map(512, 256);
    const equirect::Grid grid(512, 256);
    for (std::size_t i = 0; i < axis_map.pixel_count(); ++i) {
        const glm::dvec3 d = grid.direction(i);
        int dominant = 0;
        for (int face = 1; face < 6; ++face) {
            if (glm::dot(d, axes[std::size_t(face)]) > glm::dot(d, axes[std::size_t(dominant)])) {
                dominant = face;
            }
        }
        axis_map.set(i, colours[std::size_t(dominant)]);
        linear_map.set(i, glm::vec3(d + glm::dvec3(2.0)));
    }
    const PrefilteredCube axis_cube = prefilter_map(axis_map, small_options());
    const int n = axis_cube.face_size;
    for (int face = 0; face < 6; ++face) {
        const glm::dvec3 expected(colours[std::size_t(face)]);
        const glm::dvec3 raw = texel(axis_cube, 0, face, n / 2, n / 2);
        const glm::dvec3 sampled = sample_cube(axis_cube, axes[std::size_t(face)], 0.0);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(raw[c], expected[c], 1e-3) << "face " << face << " channel " << c;
            EXPECT_NEAR(sampled[c], expected[c], 1e-3) << "face " << face << " channel " << c;
        }
    }

    const PrefilteredCube linear_cube = prefilter_map(linear_map, small_options());
    double worst = 0.0;
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 expected = gl_direction(face, (i + 0.5) / n, (j + 0.5) / n) + 2.0;
                const glm::dvec3 value = texel(linear_cube, 0, face, i, j);
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::abs(value[c] - expected[c]));
                }
            }
        }
    }
    EXPECT_LT(worst, 5e-3);
}

// sample_cube is trilinear: between two levels it blends them linearly, and past the last
// level it clamps.
TEST(SpecularEnvironment, SampleCubeBlendsLevels) {
    const PrefilteredCube cube = prefilter_map(one_disc_map(), small_options());
    const glm::dvec3 d = kDiscDirection;
    const double level1 = sample_cube(cube, d, 1.0).g, level2 = sample_cube(cube, d, 2.0).g;
    ASSERT_GT(std::abs(level1 - level2), 0.01 * level1);
    EXPECT_NEAR(sample_cube(cube, d, 1.25).g, 0.75 * level1 + 0.25 * level2, 1e-9 * level1);
    EXPECT_EQ(sample_cube(cube, d, 10.0), sample_cube(cube, d, cube.levels - 1.0));
}

// The levels are denser at low roughness, and the lod of a level's roughness is the level.
TEST(SpecularEnvironment, RoughnessOfLevelAndLodOfRoughnessAreInverses) {
    EXPECT_EQ(roughness_of_level(0, 5), 0.0);
    EXPECT_NEAR(roughness_of_level(1, 5), 1.0 - std::sqrt(0.75), 1e-15);  // 0.134
    EXPECT_EQ(roughness_of_level(2, 5), 1.0 - std::sqrt(0.5));
    EXPECT_EQ(roughness_of_level(4, 5), 1.0);
    for (int levels = 2; levels <= 8; ++levels) {
        for (int level = 0; level < levels; ++level) {
            EXPECT_NEAR(lod_of_roughness(roughness_of_level(level, levels), levels), level, 1e-12);
        }
    }
    EXPECT_EQ(lod_of_roughness(2.0, 5), 4.0);  // clamped to roughness 1
    EXPECT_EQ(lod_of_roughness(-1.0, 5), 0.0);
    EXPECT_NE(error_of([] { roughness_of_level(5, 5); }).find("level 5 of a cube of 5 levels"),
              std::string::npos);
    EXPECT_NE(error_of([] { roughness_of_level(0, 1); }).find("1 levels"), std::string::npos);
}

// An opaque floor hides the map below the horizon (y < 0): a light wholly above is its own
// floor layer, one wholly below has none (-1), and one across the horizon gets a layer of its
// pixels above it alone, after the rig's lights, equal to the prefiltering of a map holding
// only those pixels; its energy at every level is its level 0's (the kernel sums to 1): within
// 1.5 %, 1.3 % at roughness 1's faces of 4 x 4 texels, where the part's edge on the horizon
// falls across texels.
TEST(SpecularEnvironment, ALightAcrossTheHorizonHasAFloorLayerOfItsPixelsAbove) {
    const HdrImage map =
        disc_map(512, 256, glm::vec3(0.05f),
                 {DiscLight{glm::dvec3(0.3, 0.8, 0.5), 0.08, glm::vec3(500.0f)},
                  DiscLight{glm::dvec3(1.0, 0.05, 0.0), 0.15, glm::vec3(300.0f)},
                  DiscLight{glm::dvec3(-0.5, -0.7, 0.4), 0.08, glm::vec3(400.0f)}});
    const Rig rig = rig_of(map, 3);
    ASSERT_EQ(rig.lights.size(), 3u);
    const equirect::Grid grid(map.width, map.height);
    const SpecularOptions options;
    const SpecularEnvironment specular = prefilter_specular(map, rig, options);
    ASSERT_EQ(specular.floor_layers.size(), 3u);
    int straddling = 0;
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        std::size_t above = 0;
        HdrImage above_alone(map.width, map.height);
        for (const std::uint32_t index : rig.lights[k].pixels) {
            if (grid.direction(index).y > 0.0) {
                ++above;
                above_alone.set(index, map.rgb(index));
            }
        }
        const int floor_layer = specular.floor_layers[k];
        if (above == rig.lights[k].pixels.size()) {
            EXPECT_EQ(floor_layer, int(k));
            continue;
        }
        if (above == 0) {
            EXPECT_EQ(floor_layer, -1);
            continue;
        }
        ++straddling;
        ASSERT_EQ(floor_layer, int(rig.lights.size()));
        SpecularOptions light_options = options;
        light_options.face_size = options.light_face_size;
        const PrefilteredCube expected = prefilter_map(above_alone, light_options);
        const std::vector<std::uint16_t>& all = specular.lights.rgb_half[0];
        const std::size_t per_layer = all.size() / std::size_t(specular.lights.layers);
        const std::vector<std::uint16_t> layer(
            all.begin() + std::ptrdiff_t(std::size_t(floor_layer) * per_layer),
            all.begin() + std::ptrdiff_t(std::size_t(floor_layer + 1) * per_layer));
        EXPECT_EQ(layer, expected.rgb_half[0]);
        const glm::dvec3 whole = level_mean(specular.lights, 0, int(k));
        const glm::dvec3 part = level_mean(specular.lights, 0, floor_layer);
        std::printf("[ measured ] light %zu across the horizon: %.3f of its energy above\n", k,
                    part.g / whole.g);
        EXPECT_GT(part.g, 0.2 * whole.g);
        EXPECT_LT(part.g, 0.8 * whole.g);
        for (int level = 1; level < options.levels; ++level) {
            EXPECT_NEAR(level_mean(specular.lights, level, floor_layer).g / part.g, 1.0, 0.015)
                << "level " << level;
        }
    }
    EXPECT_EQ(straddling, 1);
    EXPECT_EQ(specular.lights.layers, 4);
}

// The disc's map with its rig: one light.
SpecularEnvironment one_disc_specular() {
    const HdrImage map = one_disc_map();
    const Rig rig = build_rig(map, RepairCounts{}, RigOptions{});
    return prefilter_specular(map, rig, small_options());
}

TEST(SpecularEnvironment, EncodeDecodeRoundTripsByteExact) {
    const SpecularEnvironment specular = one_disc_specular();
    ASSERT_EQ(specular.lights.layers, 1);
    const std::string bytes = encode_specular_environment(specular);
    EXPECT_EQ(bytes.substr(0, 8), "OERSPEC3");
    EXPECT_EQ(bytes.size(), 36 + 4 + specular.byte_size());
    EXPECT_EQ(specular.residual.byte_size(),
              std::size_t(2 * 3 * 6 * (32 * 32 + 16 * 16 + 8 * 8 + 4 * 4)));
    EXPECT_EQ(specular.lights.byte_size(),
              std::size_t(2 * 3 * 6 * (16 * 16 + 8 * 8 + 4 * 4 + 2 * 2)));
    const SpecularEnvironment decoded = decode_specular_environment(bytes);
    for (const auto& [got, want] : {std::pair{&decoded.residual, &specular.residual},
                                    std::pair{&decoded.lights, &specular.lights}}) {
        EXPECT_EQ(got->face_size, want->face_size);
        EXPECT_EQ(got->levels, want->levels);
        EXPECT_EQ(got->layers, want->layers);
        EXPECT_EQ(got->rgb_half, want->rgb_half);
    }
    EXPECT_EQ(decoded.floor_layers, specular.floor_layers);
    EXPECT_EQ(encode_specular_environment(decoded), bytes);
}

TEST(SpecularEnvironment, DecodeRefusesDamagedBytes) {
    const std::string bytes = encode_specular_environment(one_disc_specular());
    const auto refused = [](std::string damaged) {
        return error_of([&] { decode_specular_environment(damaged); });
    };
    const auto with_u32 = [&](std::size_t offset, std::uint32_t value) {
        std::string damaged = bytes;
        for (int byte = 0; byte < 4; ++byte) {
            damaged[offset + std::size_t(byte)] = char((value >> (8 * byte)) & 0xffu);
        }
        return damaged;
    };
    const auto with_texel = [&](std::size_t index, std::uint16_t value) {
        std::string damaged = bytes;
        damaged[40 + 2 * index] = char(value & 0xffu);
        damaged[40 + 2 * index + 1] = char(value >> 8);
        return damaged;
    };
    EXPECT_NE(refused(bytes.substr(0, 10)).find("truncated: 10 bytes"), std::string::npos);
    EXPECT_NE(refused(bytes.substr(0, 38)).find("truncated: 38 bytes, the header and 1 floor"),
              std::string::npos);
    EXPECT_NE(refused(bytes.substr(0, bytes.size() - 1)).find("(truncated)"), std::string::npos);
    EXPECT_NE(refused(bytes + "x").find(std::to_string(bytes.size() + 1) + " bytes, but its cubes"),
              std::string::npos);
    std::string magic = bytes;
    magic[0] = 'X';
    EXPECT_NE(refused(magic).find("wrong magic"), std::string::npos);
    std::string version = bytes;
    version[7] = '2';  // before the lights' floor layers
    EXPECT_NE(refused(version).find("version '2'"), std::string::npos);
    EXPECT_NE(refused(with_u32(8, 48)).find("the residual's cube: face_size 48"),
              std::string::npos);
    EXPECT_NE(refused(with_u32(8, 64)).find("take"), std::string::npos);  // sizes vs length
    EXPECT_NE(refused(with_u32(12, 7)).find("levels 7"), std::string::npos);
    EXPECT_NE(refused(with_u32(16, 2)).find("the residual's cube: 2 layers"), std::string::npos);
    EXPECT_NE(refused(with_u32(32 - 4, 129)).find("the lights' cube: 129 layers, at most 128"),
              std::string::npos);
    EXPECT_NE(refused(with_u32(32 - 4, 2)).find("take"), std::string::npos);
    EXPECT_NE(
        refused(with_u32(32, 2)).find("2 lights, at most 64 and at most the lights' cube's 1"),
        std::string::npos);
    EXPECT_NE(refused(with_u32(32, 65)).find("65 lights, at most 64"), std::string::npos);
    EXPECT_NE(refused(with_u32(36, 1)).find("light 0's floor layer 1 is neither -1 nor a layer"),
              std::string::npos);
    EXPECT_NE(refused(with_u32(36, 0xfffffffeu)).find("light 0's floor layer -2"),
              std::string::npos);
    EXPECT_NO_THROW(decode_specular_environment(with_u32(36, 0xffffffffu)));  // -1: none
    EXPECT_NE(refused(with_u32(24, 3)).find("the lights' cube has 3 levels, the residual's 4"),
              std::string::npos);
    EXPECT_NE(refused(with_texel(5, 0x7c00)).find("level 0 value 5 is inf"), std::string::npos);
    EXPECT_NE(refused(with_texel(6, 0x7e00)).find("finite and non-negative"), std::string::npos);
    EXPECT_NE(refused(with_texel(7, 0xbc00)).find("value 7 is -1"), std::string::npos);
    EXPECT_NO_THROW(decode_specular_environment(with_texel(8, 0x8000)));  // -0 is not negative
}

TEST(SpecularEnvironment, RefusesOptionsOutOfRangeAndThesisRigs) {
    const HdrImage map = constant_map(64, 32, glm::vec3(1.0f));
    const auto refused = [&](int face_size, int levels, int samples) {
        SpecularOptions options;
        options.face_size = face_size;
        options.levels = levels;
        options.samples = samples;
        return error_of([&] { prefilter_map(map, options); });
    };
    EXPECT_NE(refused(2, 2, 64).find("face_size 2 is not a power of two in [4, 2048]"),
              std::string::npos);
    EXPECT_NE(refused(48, 2, 64).find("face_size 48"), std::string::npos);
    EXPECT_NE(refused(4096, 2, 64).find("face_size 4096"), std::string::npos);
    EXPECT_NE(refused(16, 1, 64).find("levels 1 is not in [2, 5]"), std::string::npos);
    EXPECT_NE(refused(16, 6, 64).find("levels 6 is not in [2, 5]"), std::string::npos);
    EXPECT_NE(refused(16, 5, 0).find("samples 0 is not in [1, 4096]"), std::string::npos);
    EXPECT_NE(refused(16, 5, 4097).find("samples 4097"), std::string::npos);

    HdrImage negative = map;
    negative.pixels[3 * (2 * 64 + 5) + 1] = -1.0f;
    EXPECT_NE(error_of([&] {
                  prefilter_map(negative, small_options());
              }).find("map pixel (5, 2) channel 1 is -1"),
              std::string::npos);

    RigOptions thesis;
    thesis.model = LightingModel::Thesis;
    const Rig thesis_rig = build_rig(map, RepairCounts{}, thesis);
    EXPECT_NE(error_of([&] {
                  prefilter_residual(map, thesis_rig, small_options());
              }).find("thesis, which has no specular term"),
              std::string::npos);
    const Rig rig = build_rig(map, RepairCounts{}, RigOptions{});
    EXPECT_NE(error_of([&] {
                  prefilter_residual(constant_map(128, 64, glm::vec3(1.0f)), rig, small_options());
              }).find("the map is 128x64, the rig was built from a 64x32 map"),
              std::string::npos);
}

// A real world: the residual of Blender's studio (its lights removed) keeps its energy at
// every level, and its reflection at roughness 0 is the map itself.
TEST(SpecularEnvironment, BlenderStudioResidualKeepsItsEnergy) {
    const std::string path = "/usr/share/blender/datafiles/studiolights/world/studio.exr";
    if (!std::filesystem::exists(path)) {
        GTEST_SKIP() << "no " << path
                     << ": install blender-data (scripts/setup-debian.sh --with-test-data)";
    }
    const LoadedImage studio = load_image_file(path);
    const Rig rig = build_rig(studio.image, studio.repaired, RigOptions{});
    ASSERT_GE(rig.lights.size(), 1u);
    HdrImage residual = studio.image;
    for (const Light& light : rig.lights) {
        for (const std::uint32_t index : light.pixels) {
            residual.set(index, glm::vec3(0.0f));
        }
    }
    const PrefilteredCube cube = prefilter_residual(studio.image, rig);
    const glm::dvec3 mean_l = map_mean(residual);
    for (int level = 0; level < cube.levels; ++level) {
        const glm::dvec3 mean_p = level_mean(cube, level);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(mean_p[c] / mean_l[c], 1.0, 0.02) << "level " << level << " channel " << c;
        }
    }
}

// Between two levels a compact light's layer is read at light_lod: the reflection's peak of
// discs of 1, 2 and 4 degrees at roughness 0.05 to 0.95 against the exact integral (within
// 13 %; measured 0.88 to 1.06 of it, the most at 0.1 for the smallest disc, where the mirror
// level and the first differ most). Read at the lod's fraction, the peak is 1.4 to 1.7 times
// the exact one at roughness 0.2 and 0.3: the sharp level's peak diluted once.
TEST(SpecularEnvironment, ACompactLightsPeakBetweenLevelsIsTheExactOne) {
    const glm::dvec3 direction = glm::normalize(glm::dvec3(0.3, 0.6, -0.7));
    double worst_light_lod = 0.0, worst_fraction = 0.0;
    for (const double degrees : {1.0, 2.0, 4.0}) {
        const double radius = glm::radians(degrees);
        const HdrImage map =
            disc_map(2048, 1024, glm::vec3(0.0f), {{direction, radius, glm::vec3(1000.0f)}});
        const Rig rig = rig_of(map, 1);
        ASSERT_EQ(rig.lights.size(), 1u);
        const PrefilteredCube lights = prefilter_lights(map, rig).cube;
        for (int step = 1; step < 20; ++step) {
            const double roughness = 0.05 * step;
            const double exact = disc_centre_radiance(1000.0, radius, roughness);
            const double read = sample_cube(lights, direction,
                                            light_lod(roughness, lights.levels,
                                                      disc_spread(rig.lights[0].angular_radius)))
                                    .g;
            const double blended =
                sample_cube(lights, direction, lod_of_roughness(roughness, lights.levels)).g;
            worst_light_lod = std::max(worst_light_lod, std::abs(read / exact - 1.0));
            worst_fraction = std::max(worst_fraction, std::abs(blended / exact - 1.0));
            EXPECT_NEAR(read / exact, 1.0, 0.13) << degrees << " degrees, roughness " << roughness;
        }
    }
    std::printf(
        "[ measured ] compact lights' peaks: worst %.3f off at light_lod, %.3f at the "
        "lod's fraction\n",
        worst_light_lod, worst_fraction);
}

// A sun: a core of `core_radius` with 85 % of the energy, inside a glow of 10 degrees
// (L_c Omega_c = 5.67 L_g (Omega_g - Omega_c)), on black.
const glm::dvec3 kSunDirection = glm::normalize(glm::dvec3(0.3, 0.6, -0.7));
const double kSunGlowRadius = glm::radians(10.0);
constexpr float kSunGlowRadiance = 20.0f;

float sun_core_radiance(double core_radius) {
    return float(5.67 * kSunGlowRadiance * (std::cos(core_radius) - std::cos(kSunGlowRadius)) /
                 (1.0 - std::cos(core_radius)));
}

HdrImage sun_map(double core_radius, float scale = 1.0f) {
    return disc_map(
        2048, 1024, glm::vec3(0.0f),
        {{kSunDirection, kSunGlowRadius, glm::vec3(scale * kSunGlowRadiance)},
         {kSunDirection, core_radius, glm::vec3(scale * sun_core_radiance(core_radius))}});
}

// A sun: a core of 0.3 or 0.5 degrees (the sky's sun is 0.27) with 85 % of the energy, inside
// a glow of 10 degrees, taken as one light. Read at light_lod of the light's spread (its core
// and glow, light_profile's fit), its reflection's peak is the exact one within 15 % from
// roughness 0.25; read as a disc of the light's whole angular radius, as before the spread,
// it is up to 2.4 times too bright (measured). Below 0.25 the first level itself, prefiltered
// from faces of 64 texels (1.4 degrees) at the default light_face_size of 128, holds a
// sub-degree core's peak at 0.67 to 0.74 of the exact one, which no blend weight restores: the
// figure is printed, not asserted.
TEST(SpecularEnvironment, ASunsPeakBetweenLevelsFollowsItsCoreAndGlow) {
    const glm::dvec3 direction = kSunDirection;
    for (const double core_degrees : {0.3, 0.5}) {
        const double core_radius = glm::radians(core_degrees), glow_radius = kSunGlowRadius;
        const float glow_radiance = kSunGlowRadiance;
        const float core_radiance = sun_core_radiance(core_radius);
        const HdrImage map = sun_map(core_radius);
        const Rig rig = rig_of(map, 1);
        ASSERT_EQ(rig.lights.size(), 1u);
        const Light& sun = rig.lights[0];
        const LightProfile profile = light_profile(rig.sh.per_light[0], sun.direction);
        EXPECT_NEAR(profile.core_share, 0.85, 0.05);
        const LightSpread spread = light_spread(sun.angular_radius, profile);
        const PrefilteredCube lights = prefilter_lights(map, rig).cube;
        double worst_spread = 0.0, worst_sharp = 0.0, worst_disc = 0.0;
        for (int step = 1; step < 20; ++step) {
            const double roughness = 0.05 * step;
            const double exact = disc_centre_radiance(core_radiance, core_radius, roughness) +
                                 disc_centre_radiance(glow_radiance, glow_radius, roughness) -
                                 disc_centre_radiance(glow_radiance, core_radius, roughness);
            const double read =
                sample_cube(lights, direction, light_lod(roughness, lights.levels, spread)).g;
            const double as_disc =
                sample_cube(lights, direction,
                            light_lod(roughness, lights.levels, disc_spread(sun.angular_radius)))
                    .g;
            worst_disc = std::max(worst_disc, std::abs(as_disc / exact - 1.0));
            if (roughness < 0.25) {
                worst_sharp = std::max(worst_sharp, std::abs(read / exact - 1.0));
                continue;
            }
            worst_spread = std::max(worst_spread, std::abs(read / exact - 1.0));
            EXPECT_NEAR(read / exact, 1.0, 0.15)
                << "core " << core_degrees << " degrees, roughness " << roughness;
        }
        std::printf(
            "[ measured ] a sun of core %.1f degrees (core share %.3f, glow %.1f degrees): its "
            "peak worst %.3f off at its spread from roughness 0.25, %.3f below; %.3f as a disc\n",
            core_degrees, profile.core_share, glm::degrees(profile.glow_angular_radius),
            worst_spread, worst_sharp, worst_disc);
    }
}

// Between two levels the blend of their kernels has a light's peak (light_lod) but not its
// shape: a spike of the sharp level on the wide level's skirt. A sun's core (0.3 degrees, 85 %
// of its energy) is nearly a point, whose exact reflection is its energy times the kernel at
// the roughness itself; light_core_correction adds what the blend lacks of that. Its
// reflection's profile, from the core out to three half widths of the kernel along a great
// circle, against the exact prefiltering of the map's pixels (a direct sum), relative RMS:
// 0.098, 0.079, 0.053 at roughness 0.3, 0.45, 0.7 against the blend's 0.195, 0.143, 0.134.
// Bounds: under 0.6 of the blend's, and 0.11. (Below the second level, roughness 0.23, there is
// no correction.)
TEST(SpecularEnvironment, ASunsCoreReflectsWithTheExactKernelBetweenLevels) {
    const double core_radius = glm::radians(0.3);
    const HdrImage map = sun_map(core_radius);
    const Rig rig = rig_of(map, 1);
    ASSERT_EQ(rig.lights.size(), 1u);
    const Light& sun = rig.lights[0];
    const LightSpread spread =
        light_spread(sun.angular_radius, light_profile(rig.sh.per_light[0], sun.direction));
    const PrefilteredCube lights = prefilter_lights(map, rig).cube;
    const double core_energy = light_core_energy(sun, spread, lights.levels).g;
    EXPECT_NEAR(core_energy, spread.core_share * sun.intensity.g, 1e-9 * core_energy);
    // The sun's pixels, each as its energy and direction.
    const equirect::Grid grid(map.width, map.height);
    std::vector<std::pair<double, glm::dvec3>> pixels;
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        if (map.rgb(i).g > 0.0f) {
            pixels.emplace_back(map.rgb(i).g * grid.row_solid_angle[i / std::size_t(map.width)],
                                grid.direction(i));
        }
    }
    const glm::dvec3 across = glm::normalize(glm::cross(kSunDirection, glm::dvec3(0.0, 1.0, 0.0)));
    for (const double roughness : {0.3, 0.45, 0.7}) {
        // The kernel's integral over the sphere, by the midpoint rule, normalises it.
        double integral = 0.0;
        constexpr int steps = 20000;
        for (int k = 0; k < steps; ++k) {
            const double theta = (k + 0.5) * (kPi / 2.0) / steps;
            integral += kernel(theta, roughness) * std::sin(theta) * (kPi / 2.0) / steps;
        }
        integral *= 2.0 * kPi;
        double blend_error = 0.0, corrected_error = 0.0, total = 0.0;
        const double reach = 3.0 * kernel_half_width(roughness);
        for (int step = 0; step <= 24; ++step) {
            const double theta = reach * step / 24.0;
            const glm::dvec3 r = std::cos(theta) * kSunDirection + std::sin(theta) * across;
            double exact = 0.0;
            for (const auto& [energy, l] : pixels) {
                exact +=
                    energy * kernel(std::acos(std::clamp(glm::dot(r, l), -1.0, 1.0)), roughness);
            }
            exact /= integral;
            const double read =
                sample_cube(lights, r, light_lod(roughness, lights.levels, spread)).g;
            const double corrected =
                read + core_energy * light_core_correction(roughness, lights.levels, spread,
                                                           glm::dot(r, sun.direction));
            blend_error += (read - exact) * (read - exact);
            corrected_error += (corrected - exact) * (corrected - exact);
            total += exact * exact;
        }
        blend_error = std::sqrt(blend_error / total);
        corrected_error = std::sqrt(corrected_error / total);
        std::printf(
            "[ measured ] a sun's reflection at roughness %.2f, relative RMS over its "
            "profile: %.3f with its core's kernel, %.3f the levels' blend alone\n",
            roughness, corrected_error, blend_error);
        EXPECT_LT(corrected_error, 0.6 * blend_error) << "roughness " << roughness;
        EXPECT_LT(corrected_error, 0.11) << "roughness " << roughness;
    }
}

// A sun whose core's reflection at the second level passes the largest half float, to which
// the layer's texels are clamped, gets no core correction: the layer does not hold its core as
// the kernel, and the correction would be out of all proportion to it. The 0.3-degree sun
// above, a thousand times as bright (its core's peak there about 3e5): 0. At its own radiance
// it keeps its core's energy, and a cube of three levels gets none (no level of it is
// corrected).
TEST(SpecularEnvironment, ACoreBeyondTheHalfFloatRangeIsNotCorrected) {
    const Rig rig = rig_of(sun_map(glm::radians(0.3), 1000.0f), 1);
    ASSERT_EQ(rig.lights.size(), 1u);
    const LightSpread spread = light_spread(
        rig.lights[0].angular_radius, light_profile(rig.sh.per_light[0], rig.lights[0].direction));
    ASSERT_GT(spread.core_share * rig.lights[0].intensity.g, 0.0);
    EXPECT_EQ(light_core_energy(rig.lights[0], spread, 6), glm::dvec3(0.0));

    const Rig sun = rig_of(sun_map(glm::radians(0.3)), 1);
    ASSERT_EQ(sun.lights.size(), 1u);
    const LightSpread sun_spread = light_spread(
        sun.lights[0].angular_radius, light_profile(sun.sh.per_light[0], sun.lights[0].direction));
    EXPECT_GT(light_core_energy(sun.lights[0], sun_spread, 6).g, 0.0);
    EXPECT_EQ(light_core_energy(sun.lights[0], sun_spread, 3), glm::dvec3(0.0));
}
