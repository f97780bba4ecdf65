#pragma once
// Normalised associated Legendre functions of the real SH basis of DESIGN.md section 3, by the
// standard three-term recurrence. Shared by sh_evaluate (polynomial form) and the separable
// projection (polar-angle form).
#include <cstddef>

namespace oer::detail {

constexpr int legendre_index(int l, int m) {
    return l * (l + 1) / 2 + m;
}
constexpr int legendre_count(int order) {
    return order * (order + 1) / 2;
}

// For 0 <= m <= l < order (1 <= order <= kMaxShOrder), writes
//   out[legendre_index(l, m)] = sqrt(2 - delta_m0) K_l^m Pbar_l^m(z, s)
// where K_l^m = sqrt((2l + 1) / (4 pi) (l - m)! / (l + m)!) and Pbar_l^m is the associated
// Legendre function without the Condon-Shortley phase, with sin(theta) replaced by s:
// Pbar_l^m(z, s) = s^m d^m/dz^m P_l(z). With s = sin(theta) these are the polar factors of the
// basis (times cos(m phi) or sin(|m| phi)); with s = 1 they are the polynomial factors that
// multiply Re or Im of (x + i y)^m.
void sh_legendre(int order, double z, double s, double* out);

}  // namespace oer::detail
