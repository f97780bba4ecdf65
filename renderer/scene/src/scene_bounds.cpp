#include "oer/scene/scene_bounds.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

#include "oer/mesh/camera.hpp"

namespace oer {

SceneBounds scene_bounds(const std::vector<SceneObject>& objects) {
    std::vector<Bounds> boxes;
    for (const SceneObject& object : objects) {
        boxes.push_back(transformed_bounds(object.mesh->bounds, object.transform));
    }
    SceneBounds scene;
    scene.box = enclosing_bounds(boxes);
    scene.centre = scene.box.centre();
    // The radius follows the scene however small: a floor of 1e-4 fitted the shadow maps, their
    // normal offset and bias of a 1e-6-unit scene to a sphere 190 times too large, detaching its
    // shadows (tests/gl, ShadowsLandWhereGeometryPutsThemAtEveryScale). It stays above float's
    // resolution of the centre's position (2^-23 of it), so that the light's eye, 2 radii from
    // the centre, is a distinct point; a scene of no extent (no objects, one point) keeps 1e-4.
    const float half_diagonal = 0.5f * glm::length(scene.box.max - scene.box.min);
    scene.radius =
        half_diagonal > 0.0f ? std::max(half_diagonal, 1e-6f * glm::length(scene.centre)) : 1e-4f;
    return scene;
}

float SceneBounds::ground_weight(float distance) const {
    const float start = ground_fade_start(), end = ground_half_size();
    const float t = std::clamp((distance - start) / (end - start), 0.0f, 1.0f);
    return 1.0f - t * t * (3.0f - 2.0f * t);
}

}  // namespace oer
