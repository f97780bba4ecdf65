#pragma once
// Phase 1 of OER (docs/design.md section 2): find the light sources inside an HDR map, after the
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

// Luminance of docs/design.md section 2 and the thesis's eq. 3.1:
// 179 (0.265 R + 0.670 G + 0.065 B), 179 lm/W being the luminous efficacy of equal-energy white
// light.
double luminance(const glm::dvec3& rgb);

// How a light's energy spreads about its direction, as its shadows need it: a share in a core
// small enough to cast hard shadows, and the rest in a uniform disc (the glow) that softens
// them. A sun and its glow have most of their energy in the core; a soft box has none there.
struct LightProfile {
    double core_share = 0.0;           // in [0, 1]
    double glow_angular_radius = 0.0;  // the glow's half-angle, radians, in [0, pi]
};

// The profile fitted to the light's own radiance `light_sh` (the SH of its pixels alone,
// Rig::sh.per_light) from its bands 0 to 2 about `direction`. By the addition theorem,
// sum_m Y_lm(a) Y_lm(b) = (2l + 1) / (4 pi) P_l(a.b), so band l at d over band 0 there is
// (2l + 1) times the light's Legendre moment <P_l(cos)>. A point core of share f inside a
// uniform disc of cap cosine c has 1 - <P_1> = (1 - f)(1 - c)/2 and 1 - <P_2> =
// (1 - f)(1 - c)(2 + c)/2 (a disc's <P_1> = (1 + c)/2, <P_2> = c(1 + c)/2): their ratio is
// 2 + c, and f follows. A light whose moments no core fits (the ratio outside [1, 3], or f
// below 0) is all glow: the one disc of its mean cosine. Light with no band 2 (order below 3)
// is that disc too; a light whose luminance is not positive is all core, of radius 0.
LightProfile light_profile(const ShRgb& light_sh, const glm::dvec3& direction);

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
