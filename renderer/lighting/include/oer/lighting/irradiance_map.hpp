#pragma once
// Equirectangular irradiance maps: E(n) at every output pixel's direction, from SH or from the
// exact reference (thesis eq. 2.1).
#include <cstddef>

#include "oer/core/image.hpp"
#include "oer/lighting/sh.hpp"

namespace oer {

// irradiance: coefficients A_l w_l L_lm (see irradiance_coefficients).
HdrImage irradiance_map_from_sh(const ShRgb& irradiance, int width, int height);

// The exact irradiance; reference_samples bounds the work (see ReferenceIrradiance).
HdrImage irradiance_map_exact(const HdrImage& environment_map, int width, int height,
                              std::size_t reference_samples);

}  // namespace oer
