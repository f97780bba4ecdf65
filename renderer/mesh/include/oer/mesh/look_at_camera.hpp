#pragma once
// A perspective look-at camera (docs/design.md section 3: +Y up, the camera looks down its
// local -Z), apart from camera.hpp so that a mesh (mesh.hpp) can carry the cameras its asset
// brings while camera.hpp frames meshes' bounds.
#include <glm/vec3.hpp>

namespace oer {

struct Camera {
    glm::vec3 eye{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_y = 45.0f;  // vertical field of view, degrees
};

}  // namespace oer
