#pragma once
// Cameras (docs/design.md section 3: +Y up, the camera looks down its local -Z): look-at, orbit,
// and automatic framing of a scene's bounds.
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "oer/mesh/look_at_camera.hpp"
#include "oer/mesh/mesh.hpp"

namespace oer {

// Orbit around target: yaw 0 looks from +Z, positive yaw turns the eye towards +X; positive
// pitch raises it.
struct Orbit {
    float yaw = 30.0f;
    float pitch = 15.0f;
    float distance = 3.0f;
    glm::vec3 target{0.0f};
};

Camera orbit_camera(const Orbit& orbit, float fov_y = 45.0f);

// The axis-aligned box around `bounds` placed by `transform` (its eight corners transformed).
Bounds transformed_bounds(const Bounds& bounds, const glm::mat4& transform);

// The box around every one of `boxes` (a scene's objects, each transformed): the bounds the
// automatic framing frames and the shadow maps cover. With none, the unit cube about the origin.
Bounds enclosing_bounds(const std::vector<Bounds>& boxes);

// An orbit camera whose target and distance may be left to the automatic framing: the target
// defaults to the bounds' centre, the distance to the one from which the cylinder about the
// vertical axis through the target that holds the bounds at every yaw (a product on a
// turntable) fits the vertical and horizontal field of view at this pitch with an 8 % margin,
// like model-viewer's framing: the whole scene is in the frame at any yaw, the distance does
// not change with the yaw, and a tall product fills a portrait frame's height as a wide one
// fills a landscape frame's width. The framing depends on the pitch, the field of view and the
// aspect ratio alone, never on the size in pixels.
Camera frame_orbit(float yaw, float pitch, const std::optional<glm::vec3>& target,
                   const std::optional<float>& distance, const Bounds& bounds, float fov_y,
                   float aspect);

// The floor's clearance: an orbit over a floor keeps its eye at least distance * sin(3 degrees)
// above the floor plane, so that the floor is seen from above, never edge-on or from below.
inline constexpr float kFloorClearanceDegrees = 3.0f;

// The orbit's pitch, raised where it must be so that frame_orbit's eye (with the same target,
// distance, bounds, field of view and aspect) keeps kFloorClearanceDegrees above the floor plane
// y = floor_y (model-viewer clamps its orbit to min-camera-orbit the same way): `pitch` itself
// when its eye is high enough. Throws oer::Error (InvalidInput) when no pitch up to 90 degrees
// is (the target is below the floor, or too close to it for the distance given).
float pitch_above_floor(float pitch, const std::optional<glm::vec3>& target,
                        const std::optional<float>& distance, const Bounds& bounds, float fov_y,
                        float aspect, float floor_y);

// The automatic framing: frame_orbit from the default orbit angles, target and distance both
// taken from the bounds.
Camera frame_bounds(const Bounds& bounds, float fov_y, float aspect);

// Throws oer::Error (InvalidInput) when eye == target, up is parallel to the view direction,
// a value is not finite, or the field of view is outside (0, 180).
void validate_camera(const Camera& camera);

glm::mat4 view_matrix(const Camera& camera);
glm::mat4 projection_matrix(const Camera& camera, float aspect, float near_plane, float far_plane);

}  // namespace oer
