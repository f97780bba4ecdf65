#pragma once
// Real spherical harmonics in the convention of DESIGN.md section 3: evaluated on world
// unit vectors (x, y, z) with the polynomial forms of the thesis's appendix A
// (Y_1^-1 ~ y, Y_1^0 ~ z, Y_1^1 ~ x, all constants positive: no Condon-Shortley phase),
// orthonormal over the sphere, single index i = l (l + 1) + m. "Order N" means bands
// l = 0 .. N-1, N^2 coefficients.
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
// standard recurrence for associated Legendre functions in z and the polynomial form
// (x + i y)^m in azimuth (no angles, so exact at the poles). 1 <= order <= kMaxShOrder; d is
// used as given (not normalised). Throws oer::Error (InvalidInput) on a bad order or short span.
void sh_evaluate(int order, const glm::dvec3& d, std::span<double> out);

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

}  // namespace oer
