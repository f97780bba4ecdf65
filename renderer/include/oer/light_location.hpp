#pragma once
// Phase 1 of OER (DESIGN.md section 2): find the light sources inside an HDR map.
// Blur (gaussian, wrapping across the seam), luminance, percentile thresholds by selection,
// k-means (k-means++ seeding, fixed seed) over the bright pixels; the cluster of greatest mean
// luminance becomes a light and its pixels within 3 max(sigma) of its centre (taken from the
// halo set) are removed; repeat with one cluster fewer.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/image.hpp"

namespace oer {

enum class Clustering {
    Directions,  // on unit direction vectors (angular distance): seam and poles are seamless
    Pixels,      // the thesis's 2-D pixel coordinates, kept for comparison
};

struct LightLocationOptions {
    double blur_radius = 4.0;  // gaussian kernel half-width in pixels; sigma = radius / 2
    double light_percentile = 0.99;
    double halo_percentile = 0.96;
    int cluster_count = 10;
    Clustering clustering = Clustering::Directions;
    std::uint64_t seed = 0x5eed;  // k-means++ seeding: same input, same lights
};

struct Light {
    glm::dvec3 direction{0.0, 1.0, 0.0};  // unit, towards the light (luminance-weighted mean)
    glm::dvec3 intensity{0.0};            // sum of L * dOmega over its pixels
    double solid_angle = 0.0;             // sum of dOmega, steradians
    double angular_radius = 0.0;          // of the cap with that solid angle, radians
    double luminance_share = 0.0;         // sum(lum dOmega) of its pixels / of the whole map
    std::vector<std::uint32_t> pixels;    // sorted pixel indices y * width + x
};

struct LightLocation {
    std::vector<Light> lights;  // in extraction order (brightest cluster first)
    std::string note;           // why fewer than asked, when that happens; empty otherwise
};

// Luminance of DESIGN.md section 2: 179 (0.265 R + 0.670 G + 0.065 B).
double luminance(const glm::dvec3& rgb);

// Gaussian blur, separable, wrapping horizontally across the seam, clamped at the poles.
HdrImage blur_equirect(const HdrImage& image, double radius);

// Extracts up to max_lights lights. Never throws for degenerate maps (uniform, black, too few
// bright pixels): returns fewer lights and says why in note.
LightLocation locate_lights(const HdrImage& image, int max_lights,
                            const LightLocationOptions& options = {});

}  // namespace oer
