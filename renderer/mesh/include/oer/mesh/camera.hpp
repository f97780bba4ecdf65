#pragma once
// Cameras (DESIGN.md section 3: +Y up, the camera looks down its local -Z): look-at, orbit,
// and automatic framing of a scene's bounds.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "oer/mesh/mesh.hpp"

namespace oer {

struct Camera {
    glm::vec3 eye{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_y = 45.0f;
};

// Orbit around target: yaw 0 looks from +Z, positive yaw turns the eye towards +X; positive
// pitch raises it.
struct Orbit {
    float yaw = 30.0f;
    float pitch = 15.0f;
    float distance = 3.0f;
    glm::vec3 target{0.0f};
};

Camera orbit_camera(const Orbit& orbit, float fov_y = 45.0f);

// Looks at the bounds' centre from the default orbit angles, far enough that the bounding
// sphere fits the vertical and horizontal field of view with a margin.
Camera frame_bounds(const Bounds& bounds, float fov_y, float aspect);

// Throws oer::Error (InvalidInput) when eye == target, up is parallel to the view direction,
// a value is not finite, or the field of view is outside (0, 180).
void validate_camera(const Camera& camera);

glm::mat4 view_matrix(const Camera& camera);
glm::mat4 projection_matrix(const Camera& camera, float aspect, float near_plane, float far_plane);

}  // namespace oer
