#pragma once
// Projection of an equirectangular map onto SH (docs/design.md section 3):
//   L_lm = sum over pixels L(pixel) Y_lm(dir) dOmega      (no 1/4pi)
// for the whole map and for each light's own pixels in one call, accumulated in double.
// Projection is linear, so the coefficients of the map with any set of lights switched off
// are c(all) - sum over lights L off of c(L) (docs/design.md section 2, phase 2).
#include <cstdint>
#include <span>
#include <vector>

#include "oer/core/image.hpp"
#include "oer/lighting/sh.hpp"

namespace oer {

struct ShProjection {
    ShRgb all;                     // the whole map
    std::vector<ShRgb> per_light;  // each light's own pixels
    // The same over the rows above the horizon only (y < height / 2, directions with y > 0; an
    // odd height's middle row, on the horizon, counts below): what a point above an infinite
    // ground plane can see of the map (the ground as lighting, docs/design.md section 2). Empty
    // when not projected.
    ShRgb all_above_horizon;
    std::vector<ShRgb> per_light_above_horizon;
};

// The residual map (the map without its lights' pixels) above the horizon:
// all_above_horizon - sum over lights of per_light_above_horizon, at `order` (at most the
// projection's). Throws oer::Error (InvalidInput) when the projection has no above-horizon part.
ShRgb residual_above_horizon(const ShProjection& projection, int order);

// light_pixels[k] lists the pixel indices (y * width + x) of light k; lists are disjoint (for
// subsets to mean anything) and best sorted (fastest; any order gives the same result).
// Separable: per row, azimuthal Fourier sums times polar Legendre factors, in double; maps of
// 64 Ki pixels or more use 2 threads, with a fixed split, so results are deterministic.
// Throws oer::Error (InvalidInput) on an order outside [1, kMaxShOrder], an empty or
// inconsistent image, or a pixel index outside the map.
ShProjection project_environment(const HdrImage& image,
                                 std::span<const std::vector<std::uint32_t>> light_pixels,
                                 int order);

// Coefficients with lights switched on or off: c(all) - sum over k with on[k] false of c(k).
// on.size() must equal per_light.size() (else oer::Error InvalidInput); likewise below.
ShRgb subset_coefficients(const ShProjection& projection, std::span<const bool> on);

// Fractional visibility v_k in [0, 1] (else oer::Error): c(all) - sum (1 - v_k) c(k).
ShRgb visibility_coefficients(const ShProjection& projection, std::span<const double> visibility);

}  // namespace oer
