#pragma once
// The bounds of a frame's scene, from its objects: what the automatic framing frames, the shadow
// maps cover and the ground plane spans. One definition for the GL renderer and the reference
// renderer (renderer/reference), so that both light, shadow and ground the same scene.
#include <vector>

#include "oer/mesh/mesh.hpp"
#include "oer/scene/frame_request.hpp"

namespace oer {

struct SceneBounds {
    Bounds box;  // world space, of every object's transformed mesh bounds
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
    // Half the side of the square ground plane under the scene (at the box's lowest y): 20
    // radii, far enough that its edge is rarely in view and casts nothing onto the scene.
    float ground_half_size() const { return 20.0f * radius; }
    // How much of the ground is drawn at horizontal distance `distance` from the centre: all of
    // it within ground_fade_start(), none from ground_half_size() on, smoothstep between, round
    // about the centre so that the square's corners never show. Beyond that the background
    // shows, so that a low camera sees a horizon, not the edge of a slab (shade.frag's ground
    // and the reference renderer compose the same way).
    float ground_fade_start() const { return 5.0f * radius; }
    float ground_weight(float distance) const;
};

SceneBounds scene_bounds(const std::vector<SceneObject>& objects);

}  // namespace oer
