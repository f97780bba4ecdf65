#pragma once
// Ray geometry the frame tests check pixels against, with no GL: the camera ray of a pixel
// (the renderer's own framing: vertical fov, row 0 at the top) and ray casts against spheres and
// axis-aligned boxes. Used by the GL tests (frame_test_support.hpp) and by the integration tests
// that check frames served over HTTP.
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include "oer/mesh/camera.hpp"

namespace oer::testing {

// The camera ray through the centre of pixel (x, y), row 0 at the top.
inline glm::dvec3 pixel_ray(const Camera& camera, int width, int height, int x, int y) {
    const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target - camera.eye));
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double t = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
    const double nx = (2.0 * (x + 0.5) / width - 1.0) * t * width / height;
    const double ny = (1.0 - 2.0 * (y + 0.5) / height) * t;
    return glm::normalize(forward + nx * right + ny * up);
}

// The distance along the unit ray to its first meeting with the sphere, if any.
inline std::optional<double> hit_sphere(glm::dvec3 origin, glm::dvec3 ray, glm::dvec3 centre,
                                        double r) {
    const glm::dvec3 oc = origin - centre;
    const double b = glm::dot(oc, ray), c = glm::dot(oc, oc) - r * r;
    const double disc = b * b - c;
    if (disc < 0.0) {
        return std::nullopt;
    }
    return -b - std::sqrt(disc);
}

// Slab test: does the ray from origin along dir (t > 1e-6) hit the box?
inline bool hits_box(glm::dvec3 origin, glm::dvec3 dir, glm::dvec3 low, glm::dvec3 high) {
    double near_t = 1e-6, far_t = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-12) {
            if (origin[a] < low[a] || origin[a] > high[a]) {
                return false;
            }
            continue;
        }
        double t0 = (low[a] - origin[a]) / dir[a], t1 = (high[a] - origin[a]) / dir[a];
        if (t0 > t1) {
            std::swap(t0, t1);
        }
        near_t = std::max(near_t, t0);
        far_t = std::min(far_t, t1);
    }
    return near_t <= far_t;
}

}  // namespace oer::testing
