#pragma once
// Private: the one-channel gaussian blur behind oer::blur_equirect (light_location.hpp).
#include <vector>

namespace oer::detail {

// Largest blur radius accepted, in pixels: a kernel of 2 * 1024 + 1 taps already averages over
// a quarter of a 4096-pixel-wide map; larger radii are rejected rather than run for minutes.
inline constexpr double max_blur_radius = 1024.0;

// Normalised gaussian taps for offsets -r .. r, r = ceil(radius), sigma = radius / 2; {1} for
// radius 0. Throws oer::Error(InvalidInput) for a radius that is negative, not finite or above
// max_blur_radius.
std::vector<float> gaussian_kernel(double radius);

// Blurs a width x height single-channel image in place: horizontal pass wrapping across the
// seam (x modulo width, also for kernels wider than the image), then vertical pass clamped at
// the poles. scratch holds width * height floats of working space (its contents are lost).
void blur_equirect_in_place(float* values, int width, int height, double radius, float* scratch);

}  // namespace oer::detail
