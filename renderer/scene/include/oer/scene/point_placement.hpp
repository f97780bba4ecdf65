#pragma once
// Points on a scene's surfaces (a shop's hotspots) placed in a frame: where each lands in the
// image and whether the frame shows it, from the frame's depth buffer (FrameRenderer::
// place_points). Plain data and the visibility rule, so that the service, its tests and the
// reference's ray casts state one rule.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace oer {

struct ScenePoint {
    glm::dvec3 position{0.0};  // world space
    glm::dvec3 normal{0.0};    // unit, world space: the side of the surface it is on
};

struct PointPlacement {
    // Image position in pixels, y down from the top row (oer/mesh/camera_rays.hpp), possibly
    // outside the frame; 0, 0 behind the camera.
    double x = 0.0;
    double y = 0.0;
    double depth = 0.0;     // along the view direction; 0 or less behind the camera
    bool in_frame = false;  // in front of the camera and inside the image
    // The normal faces the eye (normal . (eye - position) > 0): a point on the far side of a
    // surface is never shown, even where the surface is thin enough to pass the depth test.
    bool facing = false;
    // No surface of the depth buffer lies in front of the point by more than the tolerance.
    bool unoccluded = false;
    bool visible() const { return in_frame && facing && unoccluded; }
};

// How far in front of a point (in pixel footprints at its depth) a surface of the depth buffer
// may lie and the point still count as shown. The buffer holds the surfaces as drawn, whose
// levels of detail deviate from the full mesh by up to a pixel's footprint (sample_lod_error),
// and is read at the pixel centre nearest the point, up to half a pixel's diagonal away, where
// a surface slanted away from the eye is nearer or farther than at the point itself by that
// distance times the tangent of its slant: three footprints, plus the slant's share for the
// point's own surface (its normal against the direction to the eye, the slant taken at most
// kMaxSlantDegrees: a surface seen more edge-on than that is at its silhouette, where either
// answer may be right).
inline constexpr double kOcclusionTolerancePixels = 3.0;
inline constexpr double kMaxSlantDegrees = 80.0;

// The tolerance, in pixel footprints, for a point whose unit normal is `normal`, seen along the
// unit direction `to_eye` from the point to the eye.
inline double occlusion_tolerance_pixels(const glm::dvec3& normal, const glm::dvec3& to_eye) {
    constexpr double kHalfDiagonal = 0.7072;
    const double min_cos = std::cos(kMaxSlantDegrees * std::numbers::pi / 180.0);
    const double cos_slant = std::clamp(std::abs(glm::dot(normal, to_eye)), min_cos, 1.0);
    return kOcclusionTolerancePixels +
           kHalfDiagonal * std::sqrt(1.0 - cos_slant * cos_slant) / cos_slant;
}

// Whether a point at `point_depth` shows past a surface at `surface_depth` (both along the view
// direction, or both along the ray through the point), a pixel's footprint being
// `pixel_size_per_depth` times the depth, within `tolerance_pixels` footprints.
inline bool unoccluded_by(double point_depth, double surface_depth, double pixel_size_per_depth,
                          double tolerance_pixels = kOcclusionTolerancePixels) {
    return point_depth <= surface_depth + tolerance_pixels * pixel_size_per_depth * point_depth;
}

}  // namespace oer
