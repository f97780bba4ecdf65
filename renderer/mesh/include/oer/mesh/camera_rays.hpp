#pragma once
// A camera's rays through a frame's pixels and, the other way, where a point lands in the
// frame, in double precision: the reference renderer's primary rays, the service's pick (the
// surface a pixel shows) and its hotspots' placement all use this one mapping, which is the GL
// renderer's (view_matrix and projection_matrix of camera.hpp: the frame's aspect ratio is
// width / height, pixel (x, y) counts from the top left corner, its centre at +0.5).
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include "oer/mesh/look_at_camera.hpp"

namespace oer {

// Where a point lands: its image position in pixels (y down from the top row) and its depth,
// the distance in front of the camera along the view direction (not along the ray).
struct ImagePoint {
    double x = 0.0;
    double y = 0.0;
    double depth = 0.0;
};

struct CameraRays {
    glm::dvec3 eye, forward, right, up;
    double tan_half_fov = 1.0, aspect = 1.0;
    int width = 1, height = 1;

    // Through image position (x, y) in pixels, y down from the top row.
    glm::dvec3 direction(double x, double y) const {
        const double nx = (2.0 * x / width - 1.0) * tan_half_fov * aspect;
        const double ny = (1.0 - 2.0 * y / height) * tan_half_fov;
        return glm::normalize(forward + nx * right + ny * up);
    }

    // The image position of `point` (possibly outside the frame), or nullopt when it is not in
    // front of the camera.
    std::optional<ImagePoint> project(const glm::dvec3& point) const {
        const glm::dvec3 offset = point - eye;
        const double depth = glm::dot(offset, forward);
        if (!(depth > 0.0)) {
            return std::nullopt;
        }
        const double nx = glm::dot(offset, right) / (depth * tan_half_fov * aspect);
        const double ny = glm::dot(offset, up) / (depth * tan_half_fov);
        return ImagePoint{(nx + 1.0) * 0.5 * width, (1.0 - ny) * 0.5 * height, depth};
    }

    // The size of a pixel at unit depth: a pixel's footprint is this times the depth.
    double pixel_size_per_depth() const { return 2.0 * tan_half_fov / height; }
};

inline CameraRays camera_rays(const Camera& camera, int width, int height) {
    CameraRays rays;
    rays.eye = glm::dvec3(camera.eye);
    rays.forward = glm::normalize(glm::dvec3(camera.target) - rays.eye);
    rays.right = glm::normalize(glm::cross(rays.forward, glm::dvec3(camera.up)));
    rays.up = glm::cross(rays.right, rays.forward);
    rays.tan_half_fov = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
    rays.aspect = double(width) / double(height);
    rays.width = width;
    rays.height = height;
    return rays;
}

}  // namespace oer
