#pragma once
// Irradiance from radiance SH (Ramamoorthi and Hanrahan 2001, "An Efficient Representation
// for Irradiance Environment Maps"): E(n) = sum A_l w_l L_lm Y_lm(n), with the clamped-cosine
// band factors A_l of sh.hpp (lambertian_band_factor) and an optional per-band window w_l against
// ringing.
#include <array>
#include <span>
#include <string>

#include <glm/mat4x4.hpp>

#include "oer/lighting/sh.hpp"
#include "oer/lighting/sh_projection.hpp"

namespace oer {

enum class WindowKind { None, Hanning, Lanczos };

// Per-band window, as applied to SH in P.-P. Sloan, "Deringing Spherical Harmonics", SIGGRAPH
// Asia 2017 Technical Briefs. Hanning (the Hann window; R. B. Blackman and J. W. Tukey, "The
// Measurement of Power Spectra", 1958): w_l = (1 + cos(pi l / cutoff)) / 2 for l < cutoff,
// else 0. Lanczos (the sigma factors of C. Lanczos, "Applied Analysis", 1956):
// w_l = sinc(pi l / cutoff) for l < cutoff, else 0 (sinc(x) = sin x / x).
// A larger cutoff is a weaker window; None is w_l = 1. factor() throws oer::Error
// (InvalidInput) for a Hanning or Lanczos window whose cutoff is not a positive number.
struct ShWindow {
    WindowKind kind = WindowKind::None;
    double cutoff = 0.0;
    double factor(int l) const;
};
std::string to_string(WindowKind kind);
WindowKind window_kind_from_string(const std::string& name);  // throws oer::Error

// Irradiance coefficients A_l w_l L_lm of radiance coefficients L_lm.
ShRgb irradiance_coefficients(const ShRgb& radiance, const ShWindow& window = {});

// For order >= 3: per channel, the 4x4 matrix M of Ramamoorthi and Hanrahan 2001 such that
// E(n) = n^T M n with n = (x, y, z, 1), built from the first 9 radiance coefficients.
std::array<glm::dmat4, 3> irradiance_matrices(const ShRgb& radiance);

// window: auto (after Sloan, "Deringing Spherical Harmonics", 2017): the weakest window of the
// given kind (largest cutoff) such that the irradiance of every on/off subset of the lights is
// non-negative over the sphere, i.e. min_relative_irradiance >= -1e-9 (rounding). Since the
// composed coefficients are affine in each light's visibility, checking the 2^n subsets covers
// every fractional visibility too. One window (one cutoff) serves every subset. Returns kind
// None when no window is needed (or kind is None). Search: a 64-step scan of cutoffs in
// (0, 4 order] (extended by doubling while still non-negative) from the top, then bisection
// above the largest non-negative step. If even the strongest window rings (only possible with
// negative radiance) the strongest window tried is returned.
ShWindow choose_deringing_window(const ShProjection& projection, WindowKind kind);

// On the normals fibonacci_sphere(2048) (reference_irradiance.hpp), per RGB channel: the
// smallest windowed irradiance of any on/off subset of the lights, divided by the largest
// windowed irradiance of the full map (every light on) in that channel; the minimum over the
// channels whose largest irradiance is positive, and at most 0 (0 when nothing is negative).
// Negative means ringing. The minimum over the 2^n subsets is computed exactly without
// enumerating them: at each normal the worst subset switches off exactly the lights whose own
// irradiance there is positive.
double min_relative_irradiance(const ShProjection& projection, const ShWindow& window);

}  // namespace oer
