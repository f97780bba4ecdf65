// The prefiltered residual cube (oer/lighting/specular_environment.hpp): the furnace, a small
// bright disc (where level 0 shows it, energy per level, the peak's place and fall), the
// residual against the map with the lights' pixels zeroed, GL's face order and orientation,
// and the stored form with each way it is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <string>
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
    return options;
}

glm::dvec3 texel(const PrefilteredCube& cube, int level, int face, int i, int j) {
    const int n = cube.face_size >> level;
    const std::size_t at = ((std::size_t(face) * n + j) * n + i) * 3;
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

// Mean radiance of one level over the sphere (sum of radiance x texel solid angle, / 4 pi).
glm::dvec3 level_mean(const PrefilteredCube& cube, int level) {
    const int n = cube.face_size >> level;
    glm::dvec3 sum(0.0);
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                sum += texel(cube, level, face, i, j) * texel_solid_angle(n, i, j);
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
    ASSERT_EQ(cube.levels, 5);
    ASSERT_EQ(cube.rgb_half.size(), 5u);
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
    EXPECT_NEAR(sample_cube(cube, kDiscDirection, 1.0).r /
                    disc_centre_radiance(kDiscRadiance, kDiscRadius, roughness_of_level(1, 5)),
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
    const std::string residual =
        encode_prefiltered_cube(prefilter_residual(map, rig, small_options()));
    EXPECT_EQ(residual, encode_prefiltered_cube(prefilter_map(zeroed, small_options())));
    EXPECT_NE(residual, encode_prefiltered_cube(prefilter_map(map, small_options())));
    // Deterministic: a second run gives the same bytes.
    EXPECT_EQ(residual, encode_prefiltered_cube(prefilter_residual(map, rig, small_options())));
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

TEST(SpecularEnvironment, RoughnessOfLevelIsLevelOverLastLevel) {
    EXPECT_EQ(roughness_of_level(0, 5), 0.0);
    EXPECT_EQ(roughness_of_level(1, 5), 0.25);
    EXPECT_EQ(roughness_of_level(4, 5), 1.0);
    EXPECT_NE(error_of([] { roughness_of_level(5, 5); }).find("level 5 of a cube of 5 levels"),
              std::string::npos);
    EXPECT_NE(error_of([] { roughness_of_level(0, 1); }).find("1 levels"), std::string::npos);
}

TEST(SpecularEnvironment, EncodeDecodeRoundTripsByteExact) {
    const PrefilteredCube cube = prefilter_map(one_disc_map(), small_options());
    const std::string bytes = encode_prefiltered_cube(cube);
    EXPECT_EQ(bytes.substr(0, 8), "OERSPEC1");
    EXPECT_EQ(bytes.size(), 16 + cube.byte_size());
    EXPECT_EQ(cube.byte_size(), std::size_t(2 * 3 * 6 * (32 * 32 + 16 * 16 + 8 * 8 + 4 * 4)));
    const PrefilteredCube decoded = decode_prefiltered_cube(bytes);
    EXPECT_EQ(decoded.face_size, cube.face_size);
    EXPECT_EQ(decoded.levels, cube.levels);
    EXPECT_EQ(decoded.rgb_half, cube.rgb_half);
    EXPECT_EQ(encode_prefiltered_cube(decoded), bytes);
}

TEST(SpecularEnvironment, DecodeRefusesDamagedBytes) {
    const std::string bytes =
        encode_prefiltered_cube(prefilter_map(one_disc_map(), small_options()));
    const auto refused = [](std::string damaged) {
        return error_of([&] { decode_prefiltered_cube(damaged); });
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
        damaged[16 + 2 * index] = char(value & 0xffu);
        damaged[16 + 2 * index + 1] = char(value >> 8);
        return damaged;
    };
    EXPECT_NE(refused(bytes.substr(0, 10)).find("truncated: 10 bytes"), std::string::npos);
    EXPECT_NE(refused(bytes.substr(0, bytes.size() - 1)).find("(truncated)"), std::string::npos);
    EXPECT_NE(refused(bytes + "x").find(std::to_string(bytes.size() + 1) + " bytes, but a cube"),
              std::string::npos);
    std::string magic = bytes;
    magic[0] = 'X';
    EXPECT_NE(refused(magic).find("wrong magic"), std::string::npos);
    std::string version = bytes;
    version[7] = '2';
    EXPECT_NE(refused(version).find("version '2'"), std::string::npos);
    EXPECT_NE(refused(with_u32(8, 48)).find("face_size 48"), std::string::npos);
    EXPECT_NE(refused(with_u32(8, 64)).find("takes"), std::string::npos);  // sizes vs length
    EXPECT_NE(refused(with_u32(12, 7)).find("levels 7"), std::string::npos);
    EXPECT_NE(refused(with_texel(5, 0x7c00)).find("level 0 value 5 is inf"), std::string::npos);
    EXPECT_NE(refused(with_texel(6, 0x7e00)).find("finite and non-negative"), std::string::npos);
    EXPECT_NE(refused(with_texel(7, 0xbc00)).find("value 7 is -1"), std::string::npos);
    EXPECT_NO_THROW(decode_prefiltered_cube(with_texel(8, 0x8000)));  // -0 is not negative
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
