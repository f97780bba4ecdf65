#pragma once
// The real spherical-harmonic basis, its normalisation and the Lambertian band factors A_l:
// everything about the SH basis lives in this file and sh.cpp. Projection onto the basis is
// sh_projection.hpp; irradiance and windowing are irradiance.hpp.
//
// Convention (docs/design.md section 3): real SH evaluated on world unit vectors (x, y, z), polar
// axis z, all constants positive (no Condon-Shortley phase), single index i = l (l + 1) + m,
// orthonormal over the sphere. "Order N" means bands l = 0 .. N-1, N^2 coefficients.
//
// Basis. With z = cos(theta) and x + i y = sin(theta) e^(i phi),
//   Y_l^0      = K_l^0 P_l^0(z)
//   Y_l^m      = sqrt(2) K_l^m Pbar_l^m(z) Re (x + i y)^m          (m > 0)
//   Y_l^-m     = sqrt(2) K_l^m Pbar_l^m(z) Im (x + i y)^m          (m > 0)
//   K_l^m      = sqrt((2l + 1) / (4 pi) (l - m)! / (l + m)!)
// where Pbar_l^m(z) = d^m/dz^m P_l(z) is the associated Legendre polynomial without the
// Condon-Shortley phase and without its sin^m(theta) factor (that factor is in (x + i y)^m),
// so the basis is a polynomial in x, y, z and needs no angle (exact at the poles). Bands 0 .. 3
// in closed form, the first 16 functions of the thesis's appendix A (A. Ambrosj, "Occluded
// Environment Maps Rendering", Politecnico di Milano, 2016), with exact constants:
//   Y_0^0  = 1/2 sqrt(1/pi)                       (0.282095)
//   Y_1^-1 = sqrt(3/(4 pi)) y,  Y_1^0 = sqrt(3/(4 pi)) z,  Y_1^1 = sqrt(3/(4 pi)) x   (0.488603)
//   Y_2^-2 = 1/2 sqrt(15/pi) x y,  Y_2^-1 = 1/2 sqrt(15/pi) y z,  Y_2^1 = 1/2 sqrt(15/pi) x z
//   Y_2^0  = 1/4 sqrt(5/pi) (3 z^2 - 1),  Y_2^2 = 1/4 sqrt(15/pi) (x^2 - y^2)
//   Y_3^-3 = 1/4 sqrt(35/(2 pi)) y (3 x^2 - y^2),  Y_3^-2 = 1/2 sqrt(105/pi) x y z
//   Y_3^-1 = 1/4 sqrt(21/(2 pi)) y (5 z^2 - 1),    Y_3^0  = 1/4 sqrt(7/pi) z (5 z^2 - 3)
//   Y_3^1  = 1/4 sqrt(21/(2 pi)) x (5 z^2 - 1),    Y_3^2  = 1/4 sqrt(105/pi) z (x^2 - y^2)
//   Y_3^3  = 1/4 sqrt(35/(2 pi)) x (x^2 - 3 y^2)
// Every order, these included, is evaluated by one recurrence (sh_evaluate), which the tests
// compare with the closed forms above (tests/lighting/sh_test.cpp).
//
// Recurrence (Press, Teukolsky, Vetterling, Flannery, "Numerical Recipes", 3rd ed., 2007,
// section 6.7, in its normalised form; the unnormalised one is in R. Green, "Spherical
// Harmonic Lighting: The Gritty Details", 2003). For N_l^m = K_l^m Pbar_l^m (times sqrt(2)
// for m > 0) and s = sin(theta) (or 1 for the polynomial form):
//   N_0^0     = 1 / (2 sqrt(pi))
//   N_m^m     = sqrt((2m + 1) / (2m)) s N_{m-1}^{m-1}            (times sqrt(2) at m = 1)
//   N_{m+1}^m = sqrt(2m + 3) z N_m^m
//   N_l^m     = a_lm z N_{l-1}^m - b_lm N_{l-2}^m,
//     a_lm = sqrt((4 l^2 - 1) / (l^2 - m^2)),
//     b_lm = sqrt(((l - 1)^2 - m^2) (2l + 1) / ((2l - 3) (l^2 - m^2))).
// Re and Im of (x + i y)^m follow from (x + i y)^m = (x + i y)^(m-1) (x + i y).
//
// Lambertian band factors A_l (Ramamoorthi and Hanrahan, "An Efficient Representation for
// Irradiance Environment Maps", SIGGRAPH 2001, where A_l is derived). Irradiance is the
// convolution of radiance with the clamped cosine max(0, n . w), a kernel symmetric about n.
// By the Funk-Hecke theorem a zonal kernel k(n . w) scales band l by 2 pi times the integral
// of k(z) P_l(z) over [-1, 1], so
//   E_lm = A_l L_lm,   A_l = 2 pi * integral over z in [0, 1] of z P_l(z) dz.
// With P_0 = 1 and P_1 = z: A_0 = pi, A_1 = 2 pi / 3. For odd l > 1, z P_l(z) is even and P_l
// is orthogonal to z on [-1, 1], so A_l = 0. For even l, Rodrigues' formula and integration
// by parts give
//   A_l = 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2),
// A_2 = pi / 4, A_4 = -pi / 24, A_6 = pi / 64, ... (docs/design.md section 3). The tests compare
// them with the integral itself (tests/lighting/irradiance_test.cpp).
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace oer {

inline constexpr int kMaxShOrder = 16;

constexpr int sh_index(int l, int m) {
    return l * (l + 1) + m;
}
constexpr int sh_count(int order) {
    return order * order;
}

// Writes the order^2 basis values at unit direction d into out (size >= order^2), by the
// recurrence above in z and the polynomial form (x + i y)^m in azimuth (no angles, so exact at
// the poles). 1 <= order <= kMaxShOrder; d is used as given (not normalised). Throws
// oer::Error (InvalidInput) on a bad order or short span.
void sh_evaluate(int order, const glm::dvec3& d, std::span<double> out);

// A_l of the header comment: A_0 = pi, A_1 = 2 pi / 3, A_l = 0 for odd l > 1, the closed form
// for even l. Throws oer::Error (InvalidInput) for l < 0.
double lambertian_band_factor(int l);

// RGB coefficients of one function on the sphere.
struct ShRgb {
    int order = 0;
    std::vector<glm::dvec3> coefficients;  // order^2 entries

    ShRgb() = default;
    explicit ShRgb(int order_) : order(order_), coefficients(sh_count(order_), glm::dvec3(0.0)) {}

    // Value of the expansion at unit direction d.
    glm::dvec3 evaluate(const glm::dvec3& d) const;
    // The first order_^2 coefficients (1 <= order_ <= order, else oer::Error).
    ShRgb truncated(int order_) const;
    // Element-wise; the orders must match (else oer::Error InvalidInput).
    ShRgb& operator+=(const ShRgb& other);
    ShRgb& operator-=(const ShRgb& other);
    ShRgb& operator*=(double factor);
};

// The normalised associated Legendre factors N_l^m of the recurrence above, shared by
// sh_evaluate (polynomial form, s = 1) and the separable projection (polar-angle form,
// s = sin(theta), sh_projection.cpp); not meant for other callers.
namespace detail {

constexpr int legendre_index(int l, int m) {
    return l * (l + 1) / 2 + m;
}
constexpr int legendre_count(int order) {
    return order * (order + 1) / 2;
}

// For 0 <= m <= l < order (1 <= order <= kMaxShOrder), writes out[legendre_index(l, m)] =
// N_l^m(z, s) = sqrt(2 - delta_m0) K_l^m s^m Pbar_l^m(z). With s = sin(theta) these are the
// polar factors of the basis (times cos(m phi) or sin(|m| phi)); with s = 1 they are the
// polynomial factors that multiply Re or Im of (x + i y)^m.
void sh_legendre(int order, double z, double s, double* out);

}  // namespace detail

}  // namespace oer
