#pragma once
// A literal implementation of the OER thesis's preprocessing (A. Ambrosj, "Occluded Environment
// Maps Rendering", master's thesis, Politecnico di Milano, 2016, sections 4.1-4.2;
// docs/design.md section 2, without our improvements): the baseline that
// bench/preprocess_benchmark.cpp measures oer::build_rig against. Written straightforwardly, the
// way the thesis describes it, neither optimised nor deliberately slowed down:
//   - gaussian blur of the RGB map (separable, sigma = radius / 2, half-width radius, clamped
//     at every border: no wrap across the seam), then luminance
//     l = 179 (0.265 R + 0.670 G + 0.065 B) per pixel;
//   - light and halo thresholds at the 99th and 96th percentiles, both read from one full
//     std::sort of a copy of every luminance value;
//   - k-means in 2-D pixel coordinates over the bright pixels (l >= light threshold), random
//     initial centres drawn from them (std::mt19937, fixed seed), Lloyd (1982) iterations until the
//     assignment is stable or max_iterations; the cluster of greatest mean luminance becomes a
//     light, made of the halo pixels (l >= halo threshold) within 3 max(sigma_x, sigma_y) of
//     its centre, which are removed; repeat with one cluster fewer until n lights;
//   - per light: direction (mean of its pixels' directions, normalised) and luminanceLoss
//     (sum of l over its pixels / sum of l over the map);
//   - 2^n occluded environment maps: for every subset of the lights, a full copy of the map
//     with the pixels of the switched-off lights set to black, projected onto order-3 SH by
//     the 9 closed-form basis functions of Ramamoorthi and Hanrahan at every pixel's direction
//     (computed with sin / cos per pixel), weighted by the exact pixel solid angle of
//     docs/design.md section 3, accumulated in double.
// It calls nothing of the library but the equirect mapping.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/core/image.hpp"

namespace oer::bench {

struct LiteralOptions {
    int light_count = 4;  // n: the number of lights to extract
    int blur_radius = 4;  // gaussian kernel half-width in pixels; sigma = radius / 2
    double light_percentile = 0.99;
    double halo_percentile = 0.96;
    int cluster_count = 10;
    int max_iterations = 100;
    std::uint32_t seed = 5489;  // std::mt19937's default seed
};

struct LiteralLight {
    glm::dvec3 direction{0.0, 1.0, 0.0};  // unit: mean of its pixels' directions, normalised
    double luminance_loss = 0.0;          // sum of l over its pixels / sum of l over the map
    double centre_x = 0.0;                // k-means centre, pixel coordinates
    double centre_y = 0.0;
    double radius = 0.0;                // 3 max(sigma_x, sigma_y), pixels
    std::vector<std::uint32_t> pixels;  // sorted pixel indices y * width + x
};

// Order-3 (9 coefficients) RGB SH, index i = l (l + 1) + m.
using LiteralSh3 = std::array<glm::dvec3, 9>;

struct LiteralResult {
    std::vector<LiteralLight> lights;  // extraction order; fewer than asked if the map runs out
    // 2^n coefficient sets, one per OEM: in oems[s], light k is on when bit k of s is set, so
    // oems.front() has every light off and oems.back() every light on.
    std::vector<LiteralSh3> oems;
    double locate_ms = 0.0;  // wall time of the light finder (phase 1)
    double oems_ms = 0.0;    // wall time of building and projecting the 2^n OEMs (phase 2)
};

// The gaussian-blurred RGB map (clamped borders), then 179 (0.265 R + 0.670 G + 0.065 B).
std::vector<double> literal_luminance(const HdrImage& image, int blur_radius);

// Phase 1: the light finder.
std::vector<LiteralLight> literal_locate_lights(const HdrImage& image,
                                                const LiteralOptions& options);

// The 9 closed-form basis functions at unit direction (x, y, z).
std::array<double, 9> literal_sh3_basis(const glm::dvec3& d);

// Order-3 projection of a whole map, every pixel's direction by sin / cos.
LiteralSh3 literal_project_order3(const HdrImage& image);

// Both phases: the lights and the 2^n OEM coefficient sets.
LiteralResult literal_thesis_preprocess(const HdrImage& image, const LiteralOptions& options);

}  // namespace oer::bench
