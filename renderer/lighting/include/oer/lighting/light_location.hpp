#pragma once
// Phase 1 of OER (DESIGN.md section 2): find the light sources inside an HDR map, after the
// light location of A. Ambrosj, "Occluded Environment Maps Rendering", master's thesis,
// Politecnico di Milano, 2016, section 4.1 (the improvements over it are marked below).
// Luminance, blurred (gaussian, wrapping across the seam); light and halo thresholds at two
// percentiles of the blurred luminance, by selection; k-means (k-means++ seeding, fixed seed)
// over the bright pixels; the cluster of greatest mean blurred luminance becomes a light: the
// halo pixels within 3 sigma of its centre, and its own members, are removed; repeat with one
// cluster fewer.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/core/image.hpp"
#include "oer/lighting/sh.hpp"

namespace oer {

enum class Clustering {
    Directions,  // on unit direction vectors (angular distance): seam and poles are seamless
    Pixels,      // the thesis's 2-D pixel coordinates, kept for comparison: a light straddling
                 // the seam (or spread along a pole's rows) comes out split or displaced
};

struct LightLocationOptions {
    // Gaussian kernel half-width in pixels, in [0, 1024]; sigma = radius / 2.
    double blur_radius = 4.0;
    double light_percentile = 0.99;  // in (0, 1)
    double halo_percentile = 0.96;   // in (0, 1), <= light_percentile
    int cluster_count = 10;          // in [1, 256]; also bounds the number of lights found
    Clustering clustering = Clustering::Directions;
    std::uint64_t seed = 0x5eed;  // k-means++ seeding: same input, same lights
    // Improvement over the thesis: a light's core is the connected region of remaining bright
    // pixels (8-neighbours, across the seam and the poles) around the chosen cluster's
    // brightest member, measured before its centre and sigma. A light larger than one k-means
    // cluster (a window, a sun's glow, a disc at a pole) is taken whole instead of leaving
    // fragments that become extra lights, and a cluster spanning several separate lamps gives
    // one lamp. false: the thesis's cluster members. Directions only: Clustering::Pixels is
    // the thesis's algorithm as published.
    bool grow_connected = true;
};

struct Light {
    // Unit, towards the light: the luminance-energy-weighted mean direction of its pixels,
    // sum(lum(L) dOmega dir), normalised; if that sum vanishes (black pixels), the plain mean
    // of its pixels' directions; if that vanishes too, the centre its pixels were taken around.
    glm::dvec3 direction{0.0, 1.0, 0.0};
    glm::dvec3 intensity{0.0};          // sum of L * dOmega over its pixels
    double solid_angle = 0.0;           // sum of dOmega, steradians
    double angular_radius = 0.0;        // of the cap with that solid angle, radians
    double luminance_share = 0.0;       // sum(lum dOmega) of its pixels / of the whole map
    std::vector<std::uint32_t> pixels;  // sorted pixel indices y * width + x
};

struct LightLocation {
    std::vector<Light> lights;  // in extraction order (brightest cluster first)
    std::string note;           // why fewer than asked, when that happens; empty otherwise
    // Diagnostics: the thresholds (blurred luminance) and the sizes of the two sets before
    // any light was taken.
    double light_threshold = 0.0;
    double halo_threshold = 0.0;
    std::size_t bright_pixel_count = 0;
    std::size_t halo_pixel_count = 0;
};

// Luminance of DESIGN.md section 2 and the thesis's eq. 3.1: 179 (0.265 R + 0.670 G + 0.065 B),
// 179 lm/W being the luminous efficacy of equal-energy white light.
double luminance(const glm::dvec3& rgb);

// The half-angle of the uniform disc about `direction` whose luminance has the same mean cosine
// as the light's own radiance `light_sh` (the SH of its pixels alone, Rig::sh.per_light), from
// its bands 0 and 1: by the addition theorem, sum_m Y_1m(a) Y_1m(b) = 3/(4 pi) a.b, so the
// band-1 part at d over the band-0 part is 3 <cos(angle to d)>; a disc of half-angle a has
// <cos> = (1 + cos a) / 2. A light whose energy sits in a bright core inside a dim halo (a sun
// and its glow) has a far smaller one than its pixels' extent (Light::angular_radius): it is
// what sizes the light's penumbrae. In [0, pi]; 0 when the light's luminance is not positive.
double energy_angular_radius(const ShRgb& light_sh, const glm::dvec3& direction);

// Gaussian blur, separable, wrapping horizontally across the seam, clamped at the poles
// (sigma = radius / 2, half-width ceil(radius), radius 0 copies). Throws oer::Error
// (InvalidInput) for an empty image or a radius outside [0, 1024].
HdrImage blur_equirect(const HdrImage& image, double radius);
// The same on one channel of width * height values (locate_lights blurs luminance only).
std::vector<float> blur_equirect_channel(const std::vector<float>& values, int width, int height,
                                         double radius);

// Extracts up to max_lights lights (at most options.cluster_count). Never throws for degenerate
// maps (uniform, black, too few bright pixels): returns fewer lights and says why in note.
// Throws oer::Error(InvalidInput) for max_lights < 0, an empty image, or options out of range,
// and oer::Error(LimitExceeded) for more than 2^32 pixels. Expects repaired radiance
// (image_io.hpp) and reads unrepaired values as repair_radiance would leave them: NaN and
// negative as 0, +Inf as the largest finite float.
LightLocation locate_lights(const HdrImage& image, int max_lights,
                            const LightLocationOptions& options = {});

}  // namespace oer
