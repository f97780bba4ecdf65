#pragma once
// Angles between unit directions, for tests that check where a light or a pixel points, and
// integrals over the hemisphere of directions by a plain midpoint rule.
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace oer::testing {

// The angle in radians between two unit vectors; atan2 of the cross and dot products stays
// accurate near 0 and pi, where acos of the dot product loses half its digits.
inline double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// The integral of f(l) over the hemisphere of unit directions l about +z, by a midpoint rule
// in (theta, phi), each cell weighted by its exact solid angle: a quadrature without importance
// sampling, to check the tables that sample.
template <typename T, typename F>
T hemisphere_integral(int rows, int columns, F f) {
    constexpr double pi = std::numbers::pi;
    T sum{};
    for (int t = 0; t < rows; ++t) {
        const double theta0 = 0.5 * pi * t / rows, theta1 = 0.5 * pi * (t + 1) / rows;
        const double theta = 0.5 * (theta0 + theta1);
        const double cell = (std::cos(theta0) - std::cos(theta1)) * 2.0 * pi / columns;
        for (int p = 0; p < columns; ++p) {
            const double phi = 2.0 * pi * (p + 0.5) / columns;
            const glm::dvec3 l(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
            sum += f(l) * cell;
        }
    }
    return sum;
}

}  // namespace oer::testing
