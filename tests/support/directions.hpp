#pragma once
// Angles between unit directions, for tests that check where a light or a pixel points.
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace oer::testing {

// The angle in radians between two unit vectors; atan2 of the cross and dot products stays
// accurate near 0 and pi, where acos of the dot product loses half its digits.
inline double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

}  // namespace oer::testing
