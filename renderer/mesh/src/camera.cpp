#include "oer/mesh/camera.hpp"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "oer/core/error.hpp"

namespace oer {

namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

float framing_distance(float pitch, const glm::vec3& target, const Bounds& bounds, float fov_y,
                       float aspect) {
    // Every yaw of the product about the vertical axis through the target: the cylinder about
    // that axis through the bounds' farthest corner, from the bounds' bottom to their top. It
    // turns into itself with the yaw, so the distance does not change while a turntable turns
    // (model-viewer frames the same solid, its idealAspect the cylinder's width over height).
    float radius = 0.0f;
    for (int corner = 0; corner < 4; ++corner) {
        const glm::vec2 d{((corner & 1) ? bounds.max.x : bounds.min.x) - target.x,
                          ((corner & 2) ? bounds.max.z : bounds.min.z) - target.z};
        radius = std::max(radius, glm::length(d));
    }
    // The circles at the top and bottom as polygons of kSides vertices circumscribing them
    // (radius / cos(pi / kSides)), so that fitting the vertices fits the circles.
    constexpr int kSides = 32;
    radius /= std::cos(glm::pi<float>() / float(kSides));
    // The camera's frame at yaw 0 (the cylinder's framing is the same at every yaw): towards
    // the eye w, right r, up u.
    const float p = glm::radians(pitch);
    const glm::vec3 w{0.0f, std::sin(p), std::cos(p)};
    const glm::vec3 r{1.0f, 0.0f, 0.0f};
    const glm::vec3 u = glm::cross(r, -w);
    const float tan_y = std::tan(glm::radians(fov_y) * 0.5f);
    const float tan_x = tan_y * std::max(aspect, 1e-3f);
    // A point at depth D - p.w with horizontal offset |p.r| fits the half field of view
    // tan_x with the margin when D >= p.w + margin |p.r| / tan_x; likewise vertically. The
    // margin keeps the silhouette off the frame's edges.
    constexpr float margin = 1.08f;
    float distance = 1e-6f;
    for (const float height : {bounds.min.y - target.y, bounds.max.y - target.y}) {
        for (int i = 0; i < kSides; ++i) {
            const float a = 2.0f * glm::pi<float>() * float(i) / float(kSides);
            const glm::vec3 point{radius * std::cos(a), height, radius * std::sin(a)};
            const float depth = glm::dot(point, w);
            distance = std::max({distance, depth + margin * std::abs(glm::dot(point, r)) / tan_x,
                                 depth + margin * std::abs(glm::dot(point, u)) / tan_y});
        }
    }
    return distance;
}

}  // namespace

Camera orbit_camera(const Orbit& orbit, float fov_y) {
    const float yaw = glm::radians(orbit.yaw);
    const float pitch = glm::radians(orbit.pitch);
    const glm::vec3 offset{std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                           std::cos(pitch) * std::cos(yaw)};
    Camera camera;
    camera.target = orbit.target;
    camera.eye = orbit.target + orbit.distance * offset;
    camera.fov_y = fov_y;
    // Straight above or below, +Y is parallel to the view: use the yaw's forward instead.
    camera.up = std::abs(std::cos(pitch)) < 1e-4f ? glm::vec3(-std::sin(yaw), 0.0f, -std::cos(yaw))
                                                  : glm::vec3(0.0f, 1.0f, 0.0f);
    return camera;
}

Bounds transformed_bounds(const Bounds& bounds, const glm::mat4& transform) {
    Bounds box;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 local{(corner & 1) ? bounds.max.x : bounds.min.x,
                              (corner & 2) ? bounds.max.y : bounds.min.y,
                              (corner & 4) ? bounds.max.z : bounds.min.z};
        const glm::vec3 world = glm::vec3(transform * glm::vec4(local, 1.0f));
        box.min = corner == 0 ? world : glm::min(box.min, world);
        box.max = corner == 0 ? world : glm::max(box.max, world);
    }
    return box;
}

Bounds enclosing_bounds(const std::vector<Bounds>& boxes) {
    if (boxes.empty()) {
        return {glm::vec3(-0.5f), glm::vec3(0.5f)};
    }
    Bounds box = boxes.front();
    for (const Bounds& other : boxes) {
        box.min = glm::min(box.min, other.min);
        box.max = glm::max(box.max, other.max);
    }
    return box;
}

Camera frame_orbit(float yaw, float pitch, const std::optional<glm::vec3>& target,
                   const std::optional<float>& distance, const Bounds& bounds, float fov_y,
                   float aspect) {
    Orbit orbit;
    orbit.yaw = yaw;
    orbit.pitch = pitch;
    orbit.target = target.value_or(bounds.centre());
    orbit.distance =
        distance.value_or(framing_distance(pitch, orbit.target, bounds, fov_y, aspect));
    return orbit_camera(orbit, fov_y);
}

float pitch_above_floor(float pitch, const std::optional<glm::vec3>& target,
                        const std::optional<float>& distance, const Bounds& bounds, float fov_y,
                        float aspect, float floor_y) {
    // How far the eye at pitch p is above the clearance (the automatic distance changes with
    // the pitch, so the eye's height is no closed form of it).
    const auto headroom = [&](float p) {
        const Camera camera = frame_orbit(0.0f, p, target, distance, bounds, fov_y, aspect);
        const float clearance = glm::length(camera.eye - camera.target) *
                                std::sin(glm::radians(kFloorClearanceDegrees));
        return camera.eye.y - floor_y - clearance;
    };
    if (headroom(pitch) >= 0.0f) {
        return pitch;
    }
    float low = pitch, high = 90.0f;
    if (headroom(high) < 0.0f) {
        throw Error(ErrorKind::InvalidInput,
                    "camera: no orbit pitch keeps the eye above the floor at y = " +
                        std::to_string(floor_y) + " (the target is below it or too close to it)");
    }
    // Bisection to a thousandth of a degree, then the side that clears the floor.
    while (high - low > 1e-3f) {
        const float middle = 0.5f * (low + high);
        (headroom(middle) >= 0.0f ? high : low) = middle;
    }
    return high;
}

Camera frame_bounds(const Bounds& bounds, float fov_y, float aspect) {
    const Orbit angles;
    return frame_orbit(angles.yaw, angles.pitch, std::nullopt, std::nullopt, bounds, fov_y, aspect);
}

void validate_camera(const Camera& camera) {
    const auto fail = [](const std::string& message) {
        throw Error(ErrorKind::InvalidInput, "camera: " + message);
    };
    if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up) ||
        !std::isfinite(camera.fov_y)) {
        fail("every value must be finite");
    }
    if (!(camera.fov_y > 0.0f && camera.fov_y < 180.0f)) {
        fail("fov_y must be in (0, 180) degrees");
    }
    const glm::vec3 forward = camera.target - camera.eye;
    if (glm::length(forward) <= 1e-6f * std::max(1.0f, glm::length(camera.eye))) {
        fail("eye and target coincide");
    }
    if (glm::length(camera.up) == 0.0f ||
        glm::length(glm::cross(glm::normalize(forward), glm::normalize(camera.up))) < 1e-4f) {
        fail("up is zero or parallel to the view direction");
    }
}

glm::mat4 view_matrix(const Camera& camera) {
    return glm::lookAt(camera.eye, camera.target, camera.up);
}

glm::mat4 projection_matrix(const Camera& camera, float aspect, float near_plane, float far_plane) {
    return glm::perspective(glm::radians(camera.fov_y), aspect, near_plane, far_plane);
}

}  // namespace oer
