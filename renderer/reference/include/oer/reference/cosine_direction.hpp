#pragma once
// Directions of density cos / pi about a normal, shared by the reference renderer's cosine lobe
// and the transfer bake's hemisphere rays (renderer/transfer), so that both sample the same way.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace oer::reference {

// A direction about unit n with density cos / pi for (u1, u2) uniform in [0, 1)^2: Malley's
// method, a uniform disc sample (Shirley and Chiu's concentric map, "A Low Distortion Map Between
// Disk and Square", 1997) lifted onto the hemisphere. The concentric map keeps the square's
// strata compact on the disc, so stratified (u1, u2) give stratified directions.
inline glm::dvec3 cosine_direction(const glm::dvec3& n, double u1, double u2) {
    constexpr double kPi = std::numbers::pi;
    const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
    double r = 0.0, phi = 0.0;
    if (a != 0.0 || b != 0.0) {
        if (std::abs(a) > std::abs(b)) {
            r = a;
            phi = (kPi / 4.0) * (b / a);
        } else {
            r = b;
            phi = kPi / 2.0 - (kPi / 4.0) * (a / b);
        }
    }
    const double x = r * std::cos(phi), y = r * std::sin(phi);
    const double z = std::sqrt(std::max(0.0, 1.0 - x * x - y * y));
    // An orthonormal basis about n (Duff et al., "Building an Orthonormal Basis, Revisited",
    // JCGT 2017).
    const double sign = std::copysign(1.0, n.z);
    const double p = -1.0 / (sign + n.z), q = n.x * n.y * p;
    const glm::dvec3 t(1.0 + sign * n.x * n.x * p, sign * q, -sign * n.x);
    const glm::dvec3 s(q, sign + n.y * n.y * p, -n.y);
    return glm::normalize(x * t + y * s + z * n);
}

}  // namespace oer::reference
