#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <filesystem>
#include <glm/trigonometric.hpp>
#include "directions.hpp"
#include "oer/core/error.hpp"
#include "oer/core/image.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/light_location.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/sh_projection.hpp"

using namespace oer;
using oer::testing::angle_between;
using std::numbers::pi;

namespace {

// A disc of constant radiance: every pixel whose centre direction lies within radius
// (radians) of centre.
struct Disc {
    glm::dvec3 centre;
    double radius;
    glm::vec3 radiance;
};

glm::dvec3 spherical(double theta_degrees, double phi_degrees) {
    const double t = theta_degrees * pi / 180.0, p = phi_degrees * pi / 180.0;
    return {std::sin(t) * std::cos(p), std::cos(t), std::sin(t) * std::sin(p)};
}

// The map, and per disc the analytic sum of L dOmega over its pixels and its pixel indices.
struct Scene {
    HdrImage image;
    std::vector<glm::dvec3> disc_intensity;
    std::vector<std::vector<std::uint32_t>> disc_pixels;
    glm::dvec3 total_intensity{0.0};
};

Scene make_scene(int width, int height, float background, const std::vector<Disc>& discs) {
    Scene s;
    s.image = HdrImage(width, height);
    s.disc_intensity.assign(discs.size(), glm::dvec3{0.0});
    s.disc_pixels.resize(discs.size());
    const equirect::Grid grid(width, height);
    std::vector<double> min_cos;
    for (const Disc& d : discs) {
        min_cos.push_back(std::cos(d.radius));
    }
    for (int y = 0; y < height; ++y) {
        const double d_omega = grid.row_solid_angle[y];
        for (int x = 0; x < width; ++x) {
            const std::size_t i = std::size_t(y) * width + x;
            const glm::dvec3 dir = grid.direction(x, y);
            glm::vec3 value(background);
            for (std::size_t k = 0; k < discs.size(); ++k) {
                if (glm::dot(dir, discs[k].centre) >= min_cos[k]) {
                    value = discs[k].radiance;
                    s.disc_intensity[k] += glm::dvec3(value) * d_omega;
                    s.disc_pixels[k].push_back(std::uint32_t(i));
                }
            }
            s.image.set(i, value);
            s.total_intensity += glm::dvec3(value) * d_omega;
        }
    }
    return s;
}

double max_relative_error(const glm::dvec3& got, const glm::dvec3& want) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(got[c] / want[c] - 1.0));
    }
    return worst;
}

// Index of the light whose direction is nearest to direction.
std::size_t nearest_light(const LightLocation& found, const glm::dvec3& direction) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < found.lights.size(); ++i) {
        if (angle_between(found.lights[i].direction, direction) <
            angle_between(found.lights[best].direction, direction)) {
            best = i;
        }
    }
    return best;
}

bool contains_all(const std::vector<std::uint32_t>& sorted, const std::vector<std::uint32_t>& of) {
    return std::includes(sorted.begin(), sorted.end(), of.begin(), of.end());
}

// Invariants of every result: sorted disjoint masks, unit directions, finite values, the
// solid angle and angular radius of the pixels, shares in [0, 1] summing to at most 1.
void expect_consistent(const LightLocation& found, const HdrImage& image) {
    const equirect::Grid grid(image.width, image.height);
    std::vector<std::uint32_t> all;
    double shares = 0.0;
    for (const Light& light : found.lights) {
        EXPECT_FALSE(light.pixels.empty());
        EXPECT_TRUE(std::adjacent_find(light.pixels.begin(), light.pixels.end(),
                                       [](auto a, auto b) { return a >= b; }) == light.pixels.end())
            << "pixels not strictly increasing";
        double solid_angle = 0.0;
        for (std::uint32_t p : light.pixels) {
            ASSERT_LT(p, image.pixel_count());
            solid_angle += grid.row_solid_angle[p / std::uint32_t(image.width)];
        }
        EXPECT_NEAR(light.solid_angle, solid_angle, 1e-12 * std::max(1.0, solid_angle));
        EXPECT_NEAR(light.angular_radius, std::acos(1.0 - solid_angle / (2.0 * pi)), 1e-9);
        EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-12);
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(light.intensity[c]));
        }
        EXPECT_GE(light.luminance_share, 0.0);
        EXPECT_LE(light.luminance_share, 1.0 + 1e-12);
        shares += light.luminance_share;
        all.insert(all.end(), light.pixels.begin(), light.pixels.end());
    }
    EXPECT_LE(shares, 1.0 + 1e-12);
    std::sort(all.begin(), all.end());
    EXPECT_TRUE(std::adjacent_find(all.begin(), all.end()) == all.end())
        << "a pixel belongs to two lights";
}

void expect_same(const LightLocation& a, const LightLocation& b) {
    ASSERT_EQ(a.lights.size(), b.lights.size());
    EXPECT_EQ(a.note, b.note);
    for (std::size_t i = 0; i < a.lights.size(); ++i) {
        EXPECT_EQ(a.lights[i].direction, b.lights[i].direction);
        EXPECT_EQ(a.lights[i].intensity, b.lights[i].intensity);
        EXPECT_EQ(a.lights[i].solid_angle, b.lights[i].solid_angle);
        EXPECT_EQ(a.lights[i].luminance_share, b.lights[i].luminance_share);
        EXPECT_EQ(a.lights[i].pixels, b.lights[i].pixels);
    }
}

// Three discs of 1.5 degrees on a dim background: an ordinary one, one centred on the seam
// (direction -X, phi = +-pi) and one centred on the pole (+Y).
constexpr double disc_radius = 1.5 * pi / 180.0;
const std::vector<Disc> three_discs = {
    {spherical(60.0, 40.0), disc_radius, {200.0f, 150.0f, 100.0f}},
    {spherical(100.0, 180.0), disc_radius, {100.0f, 120.0f, 150.0f}},
    {{0.0, 1.0, 0.0}, disc_radius, {150.0f, 150.0f, 150.0f}},
};
const char* const disc_names[] = {"ordinary", "seam", "pole"};

// Checks that each disc is found as one light: direction within one pixel's angle, all its
// pixels, intensity and share within 1 %. Prints the measured errors.
void expect_discs_found(const Scene& scene, const LightLocation& found,
                        const std::vector<Disc>& discs, const char* const* names) {
    const double pixel_angle = pi / scene.image.height;
    std::vector<std::size_t> used;
    for (std::size_t k = 0; k < discs.size(); ++k) {
        const std::size_t l = nearest_light(found, discs[k].centre);
        EXPECT_TRUE(std::find(used.begin(), used.end(), l) == used.end()) << names[k];
        used.push_back(l);
        const Light& light = found.lights[l];
        const double direction_error = angle_between(light.direction, discs[k].centre);
        const double intensity_error = max_relative_error(light.intensity, scene.disc_intensity[k]);
        const double expected_share =
            luminance(scene.disc_intensity[k]) / luminance(scene.total_intensity);
        const double share_error = std::abs(light.luminance_share / expected_share - 1.0);
        std::printf(
            "[ measured ] %dx%d %s disc: direction error %.4f px (%.2e rad), intensity error "
            "%.3f %%, share %.4f vs %.4f, %zu pixels (disc %zu)\n",
            scene.image.width, scene.image.height, names[k], direction_error / pixel_angle,
            direction_error, 100.0 * intensity_error, light.luminance_share, expected_share,
            light.pixels.size(), scene.disc_pixels[k].size());
        EXPECT_LE(direction_error, pixel_angle) << names[k];
        EXPECT_LT(intensity_error, 0.01) << names[k];
        EXPECT_LT(share_error, 0.01) << names[k];
        EXPECT_TRUE(contains_all(light.pixels, scene.disc_pixels[k])) << names[k];
    }
}

LightLocationOptions pixels_clustering() {
    LightLocationOptions o;
    o.clustering = Clustering::Pixels;
    return o;
}

}  // namespace

TEST(LightLocation, LuminanceWeights) {
    EXPECT_DOUBLE_EQ(luminance({1.0, 1.0, 1.0}), 179.0);
    EXPECT_DOUBLE_EQ(luminance({1.0, 0.0, 0.0}), 179.0 * 0.265);
    EXPECT_DOUBLE_EQ(luminance({0.0, 1.0, 0.0}), 179.0 * 0.670);
    EXPECT_DOUBLE_EQ(luminance({0.0, 0.0, 1.0}), 179.0 * 0.065);
}

TEST(LightLocation, FindsOrdinarySeamAndPoleDiscsWithDirections) {
    const Scene scene = make_scene(1024, 512, 0.05f, three_discs);
    const LightLocation found = locate_lights(scene.image, 3);
    ASSERT_EQ(found.lights.size(), 3u) << found.note;
    EXPECT_TRUE(found.note.empty()) << found.note;
    expect_consistent(found, scene.image);
    expect_discs_found(scene, found, three_discs, disc_names);
}

TEST(LightLocation, FindsTheSouthPoleDiscAndASeamDiscOnTheEquator) {
    // The other pole (-Y, the last row) and the seam where it crosses the equator (-X), each
    // also at an exact pixel-corner direction of the grid: the pole is the meeting point of every
    // column, the seam the edge between column W - 1 and column 0.
    const std::vector<Disc> discs = {
        {{0.0, -1.0, 0.0}, disc_radius, {150.0f, 150.0f, 150.0f}},
        {{-1.0, 0.0, 0.0}, disc_radius, {120.0f, 100.0f, 150.0f}},
    };
    const char* const names[] = {"south pole", "seam on the equator"};
    const Scene scene = make_scene(1024, 512, 0.05f, discs);
    const LightLocation found = locate_lights(scene.image, 2);
    ASSERT_EQ(found.lights.size(), 2u) << found.note;
    expect_consistent(found, scene.image);
    expect_discs_found(scene, found, discs, names);
}

TEST(LightLocation, NearlyCoincidentLightsLoseNoPixelAndNoEnergy) {
    // Two discs of 1 degree radius on the equator, 3 degrees apart centre to centre (one degree
    // of sky between them, under three pixels of 1024x512: the blur bridges it) and 2 degrees
    // apart (touching), where the blurred discs are one connected bright region and come out as
    // one light; 8 degrees apart they are two. Whether they come out as one light or two, every
    // pixel of both discs belongs to a light, and the lights' intensity is the discs' (plus a halo
    // of dim sky: at most 1 %).
    for (const double separation : {8.0, 3.0, 2.0}) {
        const std::vector<Disc> discs = {
            {spherical(90.0, 30.0), pi / 180.0, {300.0f, 280.0f, 260.0f}},
            {spherical(90.0, 30.0 + separation), pi / 180.0, {200.0f, 220.0f, 240.0f}},
        };
        const Scene scene = make_scene(1024, 512, 0.05f, discs);
        const LightLocation found = locate_lights(scene.image, 2);
        ASSERT_GE(found.lights.size(), 1u) << found.note;
        expect_consistent(found, scene.image);
        std::vector<std::uint32_t> all;
        glm::dvec3 intensity{0.0};
        for (const Light& light : found.lights) {
            all.insert(all.end(), light.pixels.begin(), light.pixels.end());
            intensity += light.intensity;
        }
        std::sort(all.begin(), all.end());
        const glm::dvec3 discs_intensity = scene.disc_intensity[0] + scene.disc_intensity[1];
        std::printf(
            "[ measured ] discs %.0f degrees apart: %zu lights, intensity %.4f of the discs'\n",
            separation, found.lights.size(), intensity.g / discs_intensity.g);
        for (std::size_t k = 0; k < discs.size(); ++k) {
            EXPECT_TRUE(contains_all(all, scene.disc_pixels[k])) << separation << " disc " << k;
        }
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(intensity[c], discs_intensity[c]) << separation;
            EXPECT_LE(intensity[c], 1.01 * discs_intensity[c]) << separation;
        }
        // One light holding both points between them, weighted by energy: within a pixel of
        // the discs' energy-weighted centre.
        if (found.lights.size() == 1) {
            const glm::dvec3 centre =
                glm::normalize(luminance(scene.disc_intensity[0]) * discs[0].centre +
                               luminance(scene.disc_intensity[1]) * discs[1].centre);
            EXPECT_LE(angle_between(found.lights[0].direction, centre), pi / 512) << separation;
        } else {
            const char* const names[] = {"brighter", "dimmer"};
            expect_discs_found(scene, found, discs, names);
        }
        EXPECT_EQ(found.lights.size(), separation > 5.0 ? 2u : 1u) << separation;
    }
}

TEST(LightLocation, AskingForMoreLightsThanThereAreReturnsFewerWithANote) {
    const std::vector<Disc> two = {three_discs[0], three_discs[1]};
    const Scene scene = make_scene(512, 256, 0.05f, two);
    const LightLocation found = locate_lights(scene.image, 6);
    ASSERT_EQ(found.lights.size(), 2u);
    EXPECT_EQ(found.note, "no bright pixels left after 2 lights (asked for 6)");
    expect_consistent(found, scene.image);
    expect_discs_found(scene, found, two, disc_names);
}

TEST(LightLocation, PixelsClusteringSplitsTheSeamDisc) {
    // The thesis's 2-D pixel clustering does not know that x = 0 and x = W - 1 are neighbours:
    // the seam disc comes out as two half-discs on opposite edges of the image, each a
    // separate light pointing about (4 / 3 pi) r off the true centre. Clustering on directions
    // finds it whole.
    const std::vector<Disc> two = {three_discs[0], three_discs[1]};
    const Scene scene = make_scene(1024, 512, 0.05f, two);
    const double pixel_angle = pi / scene.image.height;

    const LightLocation directions = locate_lights(scene.image, 4);
    ASSERT_EQ(directions.lights.size(), 2u);
    expect_discs_found(scene, directions, two, disc_names);

    const LightLocation pixels = locate_lights(scene.image, 4, pixels_clustering());
    expect_consistent(pixels, scene.image);
    const std::vector<std::uint32_t>& seam = scene.disc_pixels[1];
    std::vector<std::size_t> holders;  // lights holding some of the seam disc
    for (std::size_t i = 0; i < pixels.lights.size(); ++i) {
        const auto& p = pixels.lights[i].pixels;
        const bool any = std::any_of(seam.begin(), seam.end(), [&](std::uint32_t s) {
            return std::binary_search(p.begin(), p.end(), s);
        });
        if (any) {
            holders.push_back(i);
        }
    }
    ASSERT_EQ(holders.size(), 2u) << "the seam disc should be split in two lights";
    for (std::size_t i : holders) {
        const Light& half = pixels.lights[i];
        const double error = angle_between(half.direction, three_discs[1].centre);
        const double intensity_ratio = half.intensity.g / scene.disc_intensity[1].g;
        std::printf(
            "[ measured ] pixels clustering, seam half-disc: direction error %.2f px, "
            "%.1f %% of the disc's intensity\n",
            error / pixel_angle, 100.0 * intensity_ratio);
        EXPECT_GT(error, pixel_angle);
        EXPECT_GT(intensity_ratio, 0.3);
        EXPECT_LT(intensity_ratio, 0.7);
    }
    // The ordinary disc is found by both.
    const Light& ordinary = pixels.lights[nearest_light(pixels, three_discs[0].centre)];
    EXPECT_LE(angle_between(ordinary.direction, three_discs[0].centre), pixel_angle);
}

TEST(LightLocation, PixelsClusteringFragmentsThePoleDisc) {
    // In pixel space the pole disc is a band across the whole width: k-means cuts it into
    // pieces, and each piece becomes a light of a fraction of the disc.
    const Scene scene = make_scene(1024, 512, 0.05f, three_discs);
    const LightLocation pixels = locate_lights(scene.image, 3, pixels_clustering());
    ASSERT_EQ(pixels.lights.size(), 3u);
    expect_consistent(pixels, scene.image);
    const auto& pole = scene.disc_pixels[2];
    for (const Light& light : pixels.lights) {
        EXPECT_FALSE(contains_all(light.pixels, pole));
        EXPECT_LT(light.intensity.g, 0.5 * scene.disc_intensity[2].g);
    }
}

TEST(LightLocation, ThesisExtentLeavesFragmentsOfAPoleDisc) {
    // Without grow_connected a light is the chosen cluster and the halo within its 3 sigma.
    // The pole disc's many pixels take most of the k-means clusters; the brightest of them is
    // a piece of the disc, and the rest of the disc comes back as further lights.
    const Scene scene = make_scene(1024, 512, 0.05f, three_discs);
    LightLocationOptions thesis;
    thesis.grow_connected = false;
    const LightLocation found = locate_lights(scene.image, 6, thesis);
    expect_consistent(found, scene.image);
    const auto& pole = scene.disc_pixels[2];
    std::size_t pole_lights = 0;
    for (const Light& light : found.lights) {
        const auto in_pole = std::count_if(pole.begin(), pole.end(), [&](std::uint32_t p) {
            return std::binary_search(light.pixels.begin(), light.pixels.end(), p);
        });
        EXPECT_LT(std::size_t(in_pole), pole.size());
        pole_lights += in_pole > 0;
    }
    std::printf("[ measured ] thesis extent: %zu lights, %zu of them share the pole disc\n",
                found.lights.size(), pole_lights);
    EXPECT_GE(pole_lights, 2u);

    // With it (the default), the same map gives the three discs and stops.
    const LightLocation grown = locate_lights(scene.image, 6);
    EXPECT_EQ(grown.lights.size(), 3u);
}

TEST(LightLocation, TwoRunsGiveIdenticalResults) {
    const Scene scene = make_scene(1024, 512, 0.05f, three_discs);
    const LightLocation first = locate_lights(scene.image, 5);
    ASSERT_EQ(first.lights.size(), 3u);
    expect_same(first, locate_lights(scene.image, 5));
    expect_same(locate_lights(scene.image, 5, pixels_clustering()),
                locate_lights(scene.image, 5, pixels_clustering()));
    // Another seed clusters differently but finds the same lights.
    LightLocationOptions other_seed;
    other_seed.seed = 12345;
    const LightLocation reseeded = locate_lights(scene.image, 3, other_seed);
    ASSERT_EQ(reseeded.lights.size(), 3u);
    expect_discs_found(scene, reseeded, three_discs, disc_names);
}

TEST(LightLocation, PercentilesCountPixelsSoAPoleDiscUsesMoreOfTheBudget) {
    // A known limit of the thesis's thresholds, kept: at 512x256 the 1.5 degree pole disc
    // covers 1280 pixels against 15 for the same disc at the equator, so most of the top 1 %
    // of pixels is the pole's. The seam disc, dimmer and blurred to a third of its peak, is
    // not bright at all: two lights, not three.
    const Scene scene = make_scene(512, 256, 0.05f, three_discs);
    const LightLocation found = locate_lights(scene.image, 3);
    ASSERT_EQ(found.lights.size(), 2u);
    EXPECT_EQ(found.note, "no bright pixels left after 2 lights (asked for 3)");
    EXPECT_TRUE(contains_all(found.lights[0].pixels, scene.disc_pixels[2]));
    EXPECT_TRUE(contains_all(found.lights[1].pixels, scene.disc_pixels[0]));
}

TEST(LightLocation, OnePixelSunOnTheSeam) {
    const int w = 512, h = 256;
    HdrImage image(w, h);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, {1.0f, 1.0f, 1.0f});
    }
    const int sx = 0, sy = 90;
    const std::uint32_t sun = std::uint32_t(sy * w + sx);
    image.set(sun, {1e6f, 1e6f, 1e6f});
    const double sun_intensity = 1e6 * equirect::pixel_solid_angle(sy, w, h);

    const LightLocation found = locate_lights(image, 1);
    ASSERT_EQ(found.lights.size(), 1u);
    expect_consistent(found, image);
    const Light& light = found.lights[0];
    EXPECT_TRUE(std::binary_search(light.pixels.begin(), light.pixels.end(), sun));
    const double error = light.intensity.g / sun_intensity - 1.0;
    std::printf(
        "[ measured ] one-pixel sun: %zu pixels, intensity error %.2e, direction error "
        "%.3f px\n",
        light.pixels.size(), error,
        angle_between(light.direction, equirect::pixel_direction(sx, sy, w, h)) / (pi / h));
    EXPECT_GE(error, 0.0);
    EXPECT_LT(error, 0.01);
    EXPECT_LT(angle_between(light.direction, equirect::pixel_direction(sx, sy, w, h)),
              0.01 * pi / h);
    EXPECT_GT(light.luminance_share, 0.99 * sun_intensity / (sun_intensity + 4.0 * pi));

    // Asked for more: the sun's blurred neighbourhood went with it, nothing else is bright.
    const LightLocation more = locate_lights(image, 4);
    ASSERT_EQ(more.lights.size(), 1u);
    EXPECT_EQ(more.note, "no bright pixels left after 1 light (asked for 4)");
}

TEST(LightLocation, OnePixelSunAtThePole) {
    const int w = 256, h = 128;
    HdrImage image(w, h);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, {0.5f, 0.5f, 0.5f});
    }
    const std::uint32_t sun = 37;  // row 0
    image.set(sun, {5e5f, 5e5f, 5e5f});
    const double sun_intensity = 5e5 * equirect::pixel_solid_angle(0, w, h);
    const LightLocation found = locate_lights(image, 3);
    ASSERT_GE(found.lights.size(), 1u);
    expect_consistent(found, image);
    const Light& light = found.lights[0];
    EXPECT_TRUE(std::binary_search(light.pixels.begin(), light.pixels.end(), sun));
    EXPECT_NEAR(light.intensity.r / sun_intensity, 1.0, 0.01);
}

TEST(LightLocation, TinyMaps) {
    // 1x1: uniform, nothing to find.
    HdrImage one(1, 1);
    one.set(0, {2.0f, 2.0f, 2.0f});
    LightLocation found = locate_lights(one, 3);
    EXPECT_TRUE(found.lights.empty());
    EXPECT_EQ(found.note, "map is uniform: no pixel is brighter than the rest");

    // 2x1: the brighter pixel is the light, the whole map's luminance is its.
    HdrImage two(2, 1);
    two.set(1, {5.0f, 5.0f, 5.0f});
    found = locate_lights(two, 3);
    ASSERT_EQ(found.lights.size(), 1u);
    expect_consistent(found, two);
    EXPECT_EQ(found.lights[0].pixels, (std::vector<std::uint32_t>{1}));
    EXPECT_NEAR(found.lights[0].luminance_share, 1.0, 1e-12);
    EXPECT_NEAR(found.lights[0].direction.z, 1.0, 1e-12);  // pixel 1 of 2 looks along +Z
    EXPECT_FALSE(found.note.empty());

    // 1x4096: one column, a bright spot half way down.
    HdrImage column(1, 4096);
    for (std::size_t i = 0; i < column.pixel_count(); ++i) {
        column.set(i, {0.1f, 0.1f, 0.1f});
    }
    column.set(1000, {100.0f, 100.0f, 100.0f});
    for (Clustering c : {Clustering::Directions, Clustering::Pixels}) {
        LightLocationOptions o;
        o.clustering = c;
        found = locate_lights(column, 2, o);
        ASSERT_GE(found.lights.size(), 1u);
        expect_consistent(found, column);
        const Light& light = found.lights[0];
        EXPECT_TRUE(std::binary_search(light.pixels.begin(), light.pixels.end(), 1000u));
        EXPECT_LT(angle_between(light.direction, equirect::pixel_direction(0, 1000, 1, 4096)),
                  pi / 4096);
    }
}

TEST(LightLocation, BlackAndUniformMapsHaveNoLights) {
    const HdrImage black(64, 32);
    LightLocation found = locate_lights(black, 4);
    EXPECT_TRUE(found.lights.empty());
    EXPECT_EQ(found.note, "map is black: no pixel carries any luminance");

    HdrImage uniform(64, 32);
    for (std::size_t i = 0; i < uniform.pixel_count(); ++i) {
        uniform.set(i, {0.3f, 0.6f, 0.9f});
    }
    found = locate_lights(uniform, 4);
    EXPECT_TRUE(found.lights.empty());
    EXPECT_EQ(found.note, "map is uniform: no pixel is brighter than the rest");
    EXPECT_EQ(found.bright_pixel_count, 0u);

    // Asking for nothing is not "fewer than asked".
    EXPECT_TRUE(locate_lights(uniform, 0).note.empty());
}

TEST(LightLocation, FewerBrightPixelsThanClusters) {
    // Five single bright pixels, no blur: five bright pixels for ten clusters. Each becomes
    // one light, brightest first.
    const int w = 256, h = 128;
    HdrImage image(w, h);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, {0.05f, 0.05f, 0.05f});
    }
    const std::uint32_t spikes[5] = {10 * w + 20, 40 * w + 200, 64 * w + 128, 100 * w + 5,
                                     120 * w + 250};
    for (int i = 0; i < 5; ++i) {
        image.set(spikes[i], glm::vec3(float(100 * (i + 1))));
    }
    LightLocationOptions o;
    o.blur_radius = 0.0;
    o.cluster_count = 10;
    const LightLocation found = locate_lights(image, 10, o);
    EXPECT_EQ(found.bright_pixel_count, 5u);
    ASSERT_EQ(found.lights.size(), 5u);
    EXPECT_EQ(found.note, "no bright pixels left after 5 lights (asked for 10)");
    expect_consistent(found, image);
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(found.lights[i].pixels, (std::vector<std::uint32_t>{spikes[4 - i]})) << i;
    }

    // With the default blur each spike is a small blob, still one light each (not in order
    // of brightness: a cluster holding only the core of a dimmer blob can have a greater mean
    // blurred luminance than half of a brighter one).
    const LightLocation blurred = locate_lights(image, 10);
    ASSERT_EQ(blurred.lights.size(), 5u) << blurred.note;
    EXPECT_EQ(blurred.note, "no bright pixels left after 5 lights (asked for 10)");
    expect_consistent(blurred, image);
    for (std::uint32_t spike : spikes) {
        EXPECT_EQ(std::count_if(blurred.lights.begin(), blurred.lights.end(),
                                [&](const Light& l) {
                                    return std::binary_search(l.pixels.begin(), l.pixels.end(),
                                                              spike);
                                }),
                  1)
            << spike;
    }

    // cluster_count bounds the number of lights. With one cluster, the thesis's light is the
    // whole cluster, every bright pixel; the connected core is the brightest spike alone.
    o.cluster_count = 1;
    o.grow_connected = false;
    const LightLocation bounded = locate_lights(image, 5, o);
    ASSERT_EQ(bounded.lights.size(), 1u);
    EXPECT_EQ(bounded.note, "cluster_count 1 allows at most 1 light (asked for 5)");
    EXPECT_TRUE(contains_all(bounded.lights[0].pixels,
                             {spikes[0], spikes[1], spikes[2], spikes[3], spikes[4]}));
    o.grow_connected = true;
    const LightLocation connected = locate_lights(image, 5, o);
    ASSERT_EQ(connected.lights.size(), 1u);
    EXPECT_EQ(connected.lights[0].pixels, (std::vector<std::uint32_t>{spikes[4]}));
}

TEST(LightLocation, NonFiniteRadianceDoesNotThrow) {
    Scene scene = make_scene(256, 128, 0.05f, {three_discs[0]});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    scene.image.set(5, {nan, 1.0f, 1.0f});
    scene.image.set(7000, {inf, inf, inf});
    scene.image.set(9000, {-inf, 0.0f, 0.0f});
    const LightLocation found = locate_lights(scene.image, 3);
    ASSERT_GE(found.lights.size(), 1u);
    expect_consistent(found, scene.image);
}

TEST(LightLocation, InvalidArgumentsThrowInvalidInput) {
    const Scene scene = make_scene(64, 32, 0.05f, {three_discs[0]});
    auto expect_invalid = [&](const HdrImage& image, int max_lights, const LightLocationOptions& o,
                              const std::string& what) {
        try {
            locate_lights(image, max_lights, o);
            ADD_FAILURE() << "no error for " << what;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput) << what;
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    const LightLocationOptions defaults;
    expect_invalid(scene.image, -1, defaults, "max_lights");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (double p : {0.0, 1.0, -0.5, 1.5, nan}) {
        LightLocationOptions o;
        o.light_percentile = p;
        expect_invalid(scene.image, 3, o, "light_percentile");
        o = {};
        o.halo_percentile = p;
        expect_invalid(scene.image, 3, o, "halo_percentile");
    }
    LightLocationOptions inverted;
    inverted.light_percentile = 0.9;
    inverted.halo_percentile = 0.95;
    expect_invalid(scene.image, 3, inverted, "above light_percentile");
    for (int clusters : {0, -3, 257}) {
        LightLocationOptions o;
        o.cluster_count = clusters;
        expect_invalid(scene.image, 3, o, "cluster_count");
    }
    for (double r : {-1.0, nan, 5000.0}) {
        LightLocationOptions o;
        o.blur_radius = r;
        expect_invalid(scene.image, 3, o, "blur_radius");
    }
    expect_invalid(HdrImage(), 3, defaults, "empty");
    HdrImage truncated = scene.image;
    truncated.pixels.pop_back();
    expect_invalid(truncated, 3, defaults, "pixel buffer");
}

TEST(LightLocation, LocatesLightsIn2048x1024) {
    const Scene scene = make_scene(2048, 1024, 0.05f, three_discs);
    locate_lights(scene.image, 4);  // warm-up
    std::vector<double> ms;
    LightLocation found;
    for (int i = 0; i < 5; ++i) {
        const auto start = std::chrono::steady_clock::now();
        found = locate_lights(scene.image, 4);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count());
    }
    std::sort(ms.begin(), ms.end());
    std::printf(
        "[ measured ] locate_lights 2048x1024, 4 lights asked: min %.1f ms, median %.1f "
        "ms\n",
        ms.front(), ms[ms.size() / 2]);
    ASSERT_EQ(found.lights.size(), 3u);
    expect_consistent(found, scene.image);
    expect_discs_found(scene, found, three_discs, disc_names);
}

TEST(LightLocation, Slow8192x4096) {
    const Scene scene = make_scene(8192, 4096, 0.05f, three_discs);
    const auto start = std::chrono::steady_clock::now();
    const LightLocation found = locate_lights(scene.image, 4);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ measured ] locate_lights 8192x4096: %.1f ms, %zu bright pixels\n", seconds * 1e3,
                found.bright_pixel_count);
    EXPECT_LT(seconds, 20.0);
    ASSERT_EQ(found.lights.size(), 3u) << found.note;
    expect_consistent(found, scene.image);
    expect_discs_found(scene, found, three_discs, disc_names);
}

namespace {

// A map lit by a core disc (half-angle core_degrees, radiance core) inside a halo disc
// (halo_degrees, radiance halo) about direction d, black elsewhere; the SH (order 3) of the
// halo's pixels (core included): a light's own SH, as Rig::sh.per_light holds it.
ShRgb disc_light_sh(const glm::dvec3& d, double core_degrees, double core, double halo_degrees,
                    double halo) {
    const int width = 1024, height = 512;
    HdrImage image(width, height);
    std::vector<std::uint32_t> pixels;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const double angle = std::acos(
                std::clamp(glm::dot(equirect::pixel_direction(x, y, width, height), d), -1.0, 1.0));
            const auto index = std::uint32_t(y * width + x);
            if (angle <= glm::radians(halo_degrees)) {
                const double radiance = angle <= glm::radians(core_degrees) ? core : halo;
                image.set(index, glm::vec3(float(radiance)));
                pixels.push_back(index);
            }
        }
    }
    const std::vector<std::vector<std::uint32_t>> lights{pixels};
    return project_environment(image, lights, 3).per_light[0];
}

}  // namespace

TEST(LightLocationLightProfile, AUniformDiscIsAllGlowOfItsOwnHalfAngle) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, 0.8, -0.5));
    for (const double degrees : {5.0, 10.0, 25.0}) {
        const LightProfile profile = light_profile(disc_light_sh(d, degrees, 1.0, degrees, 1.0), d);
        EXPECT_NEAR(profile.core_share, 0.0, 0.05) << degrees << " degree disc";
        EXPECT_NEAR(glm::degrees(profile.glow_angular_radius), degrees, 0.05 * degrees + 0.3)
            << degrees << " degree disc";
    }
}

TEST(LightLocationLightProfile, ASunInItsGlowIsACoreAndTheGlow) {
    // A 1-degree core 1000 times brighter than its 20-degree glow: the core holds 0.71 of the
    // energy (1000 x 1^2 against 20^2 - 1). One disc of the light's mean cosine would be 10.7
    // degrees wide, the penumbra of neither.
    const glm::dvec3 d = glm::normalize(glm::dvec3(-0.6, 0.2, 0.7));
    const LightProfile profile = light_profile(disc_light_sh(d, 1.0, 1000.0, 20.0, 1.0), d);
    std::printf(
        "[ measured ] 1-degree sun in a 20-degree glow: core share %.3f, glow %.2f "
        "degrees\n",
        profile.core_share, glm::degrees(profile.glow_angular_radius));
    EXPECT_NEAR(profile.core_share, 1000.0 / (1000.0 + 20.0 * 20.0 - 1.0), 0.03);
    EXPECT_NEAR(glm::degrees(profile.glow_angular_radius), 20.0, 1.0);
}

TEST(LightLocationLightProfile, AnUnlitLightIsAPointAndALowOrderOneDisc) {
    const glm::dvec3 d(0.0, 1.0, 0.0);
    const LightProfile unlit = light_profile(ShRgb(3), d);
    EXPECT_EQ(unlit.core_share, 1.0);
    EXPECT_EQ(unlit.glow_angular_radius, 0.0);
    // Bands 0 and 1 alone cannot tell a core from a glow: the one disc of the mean cosine.
    const LightProfile two_bands =
        light_profile(disc_light_sh(d, 1.0, 1000.0, 20.0, 1.0).truncated(2), d);
    EXPECT_EQ(two_bands.core_share, 0.0);
    EXPECT_NEAR(glm::degrees(two_bands.glow_angular_radius), 10.7, 0.7);
}

TEST(LightLocationLightProfile, BlenderWorldsLightsAgainstTheirExtent) {
    const std::string directory = "/usr/share/blender/datafiles/studiolights/world/";
    for (const std::string world : {"sunrise", "city", "studio"}) {
        if (!std::filesystem::exists(directory + world + ".exr")) {
            GTEST_SKIP() << "no Blender worlds: install blender-data";
        }
        const LoadedImage loaded = load_image_file(directory + world + ".exr");
        const Rig rig = build_rig(loaded.image, loaded.repaired, {});
        for (std::size_t k = 0; k < rig.lights.size(); ++k) {
            const LightProfile profile =
                light_profile(rig.sh.per_light[k], rig.lights[k].direction);
            std::printf(
                "[ measured ] %s light %zu: extent %.1f degrees, core share %.2f, glow "
                "%.1f degrees\n",
                world.c_str(), k, glm::degrees(rig.lights[k].angular_radius), profile.core_share,
                glm::degrees(profile.glow_angular_radius));
            // sunrise's one light is a sun in its haze: most of its energy in the core. The
            // studio's are soft boxes, lit across their whole extent: most of it in the glow.
            if (world == "sunrise") {
                EXPECT_GT(profile.core_share, 0.7) << world << " light " << k;
            } else if (world == "studio") {
                EXPECT_LT(profile.core_share, 0.5) << world << " light " << k;
                EXPECT_LT(profile.glow_angular_radius, rig.lights[k].angular_radius)
                    << world << " light " << k;
            }
        }
    }
}
