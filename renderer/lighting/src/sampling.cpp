#include "oer/lighting/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace oer::sampling {

using std::numbers::pi;

double radical_inverse(std::uint32_t i) {
    // The bits reversed by swapping halves, then quarters, ... then neighbours.
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return double(i) * 0x1p-32;
}

glm::dvec2 hammersley(std::uint32_t i, std::uint32_t count) {
    return {double(i) / double(count), radical_inverse(i)};
}

GgxHalfVector ggx_half_vector(double alpha2, double u, double phi) {
    // Walter et al. 2007, eq. 35: tan^2 theta = alpha^2 u / (1 - u), written for cos^2 theta.
    const double cos2_theta = (1.0 - u) / (1.0 + (alpha2 - 1.0) * u);
    const double cos_theta = std::sqrt(cos2_theta);
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos2_theta));
    return {{sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta}, cos2_theta};
}

double ggx_distribution(double alpha2, double cos2_theta) {
    const double denominator = cos2_theta * (alpha2 - 1.0) + 1.0;
    return alpha2 / (pi * denominator * denominator);
}

glm::dvec3 cosine_direction(const glm::dvec3& n, double u1, double u2) {
    // The concentric map of [-1, 1]^2 onto the unit disc (Shirley and Chiu 1997).
    const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
    double r = 0.0, phi = 0.0;
    if (a != 0.0 || b != 0.0) {
        if (std::abs(a) > std::abs(b)) {
            r = a;
            phi = (pi / 4.0) * (b / a);
        } else {
            r = b;
            phi = pi / 2.0 - (pi / 4.0) * (a / b);
        }
    }
    const double x = r * std::cos(phi), y = r * std::sin(phi);
    const double z = std::sqrt(std::max(0.0, 1.0 - x * x - y * y));
    const TangentFrame frame = tangent_frame(n);
    return glm::normalize(x * frame.t + y * frame.s + z * n);
}

TangentFrame tangent_frame(const glm::dvec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double p = -1.0 / (sign + n.z), q = n.x * n.y * p;
    return {{1.0 + sign * n.x * n.x * p, sign * q, -sign * n.x}, {q, sign + n.y * n.y * p, -n.y}};
}

glm::dvec3 ggx_visible_normal(const glm::dvec3& v, double alpha, double u1, double u2) {
    // The view direction stretched to the hemisphere configuration (alpha 1).
    const glm::dvec3 vh = glm::normalize(glm::dvec3(alpha * v.x, alpha * v.y, v.z));
    // An orthonormal basis about it (Heitz's T1, T2).
    const double length_squared = vh.x * vh.x + vh.y * vh.y;
    const glm::dvec3 t1 = length_squared > 0.0
                              ? glm::dvec3(-vh.y, vh.x, 0.0) / std::sqrt(length_squared)
                              : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 t2 = glm::cross(vh, t1);
    // A uniform point on the disc, warped to the projected hemisphere's visible half.
    const double r = std::sqrt(u1), phi = 2.0 * pi * u2;
    const double p1 = r * std::cos(phi);
    const double s = 0.5 * (1.0 + vh.z);
    const double p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * r * std::sin(phi);
    const glm::dvec3 nh =
        p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    // Back to the ellipsoid configuration.
    return glm::normalize(glm::dvec3(alpha * nh.x, alpha * nh.y, std::max(0.0, nh.z)));
}

}  // namespace oer::sampling
