#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "oer/core/error.hpp"
#include "oer/mesh/camera.hpp"

using namespace oer;

TEST(Camera, OrbitYawZeroLooksFromPlusZAndYawTurnsTowardsPlusX) {
    Orbit orbit;
    orbit.yaw = 0.0f;
    orbit.pitch = 0.0f;
    orbit.distance = 2.0f;
    orbit.target = {1.0f, 0.5f, 0.0f};
    Camera camera = orbit_camera(orbit);
    EXPECT_NEAR(glm::length(camera.eye - glm::vec3(1.0f, 0.5f, 2.0f)), 0.0f, 1e-6f);
    orbit.yaw = 90.0f;
    camera = orbit_camera(orbit);
    EXPECT_NEAR(glm::length(camera.eye - glm::vec3(3.0f, 0.5f, 0.0f)), 0.0f, 1e-5f);
    orbit.pitch = 30.0f;
    camera = orbit_camera(orbit);
    EXPECT_NEAR(camera.eye.y - orbit.target.y, 2.0f * std::sin(glm::radians(30.0f)), 1e-5f);
    EXPECT_NEAR(glm::length(camera.eye - orbit.target), 2.0f, 1e-5f);
}

TEST(Camera, OrbitStraightDownHasAUsableUp) {
    Orbit orbit;
    orbit.pitch = 90.0f;
    EXPECT_NO_THROW(validate_camera(orbit_camera(orbit)));
}

TEST(Camera, InvalidCamerasAreRejected) {
    Camera camera;
    EXPECT_NO_THROW(validate_camera(camera));
    camera.target = camera.eye;
    EXPECT_THROW(validate_camera(camera), Error);
    camera = Camera{};
    camera.up = glm::normalize(camera.target - camera.eye);
    EXPECT_THROW(validate_camera(camera), Error);
    camera = Camera{};
    camera.fov_y = 180.0f;
    EXPECT_THROW(validate_camera(camera), Error);
    camera = Camera{};
    camera.eye.x = std::nanf("");
    EXPECT_THROW(validate_camera(camera), Error);
}

TEST(Camera, TransformedBoundsHoldTheTransformedCorners) {
    const Bounds bounds{{-1.0f, 0.0f, -0.5f}, {1.0f, 2.0f, 0.5f}};
    // 90 degrees about +Y takes x to -z and z to x; then a shift by (10, 0, 0).
    const glm::mat4 transform = glm::translate(glm::mat4(1.0f), glm::vec3(10.0f, 0.0f, 0.0f)) *
                                glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), {0, 1, 0});
    const Bounds box = transformed_bounds(bounds, transform);
    EXPECT_NEAR(glm::length(box.min - glm::vec3(9.5f, 0.0f, -1.0f)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(box.max - glm::vec3(10.5f, 2.0f, 1.0f)), 0.0f, 1e-5f);

    const Bounds scene = enclosing_bounds({bounds, box});
    EXPECT_EQ(scene.min, glm::vec3(-1.0f, 0.0f, -1.0f));
    EXPECT_NEAR(glm::length(scene.max - glm::vec3(10.5f, 2.0f, 1.0f)), 0.0f, 1e-5f);
    const Bounds empty = enclosing_bounds({});
    EXPECT_EQ(empty.min, glm::vec3(-0.5f));
    EXPECT_EQ(empty.max, glm::vec3(0.5f));
}

namespace {

// The largest |x| and |y| in normalised device coordinates of the bounds' corners seen through
// the camera (the frame spans [-1, 1] in each); infinite for a corner behind the eye.
glm::vec2 corners_extent(const Camera& camera, const Bounds& bounds, float aspect) {
    const glm::mat4 view_projection =
        projection_matrix(camera, aspect, 0.01f, 100.0f) * view_matrix(camera);
    glm::vec2 extent{0.0f};
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 clip =
            view_projection * glm::vec4((corner & 1) ? bounds.max.x : bounds.min.x,
                                        (corner & 2) ? bounds.max.y : bounds.min.y,
                                        (corner & 4) ? bounds.max.z : bounds.min.z, 1.0f);
        extent = clip.w > 0.0f ? glm::max(extent, glm::abs(glm::vec2(clip) / clip.w))
                               : glm::vec2(INFINITY);
    }
    return extent;
}

}  // namespace

// The automatic framing fits the cylinder about the vertical axis that holds the bounds at every
// yaw (a product on a turntable): at every yaw the corners stay inside the frame with its 8 %
// margin, the distance does not change with the yaw, and the product fills the frame: at some
// yaw a corner reaches the margin (the bounding sphere used before left a tall product at 41 %
// of a portrait frame's height).
TEST(Camera, FramingFitsTheProductAtEveryYawAndFillsTheFrame) {
    for (const Bounds& bounds : {Bounds{{-0.3f, 0.0f, -0.2f}, {0.3f, 1.6f, 0.2f}},     // tall
                                 Bounds{{-1.0f, 0.0f, -0.5f}, {1.0f, 0.4f, 0.5f}}}) {  // wide
        for (const float aspect : {0.5f, 1.0f, 2.0f}) {
            for (const float pitch : {-10.0f, 15.0f, 60.0f, 90.0f}) {
                const float distance = glm::length(
                    frame_orbit(0.0f, pitch, std::nullopt, std::nullopt, bounds, 45.0f, aspect)
                        .eye -
                    bounds.centre());
                float largest = 0.0f;
                for (int yaw = -180; yaw < 180; yaw += 3) {
                    const Camera camera = frame_orbit(float(yaw), pitch, std::nullopt, std::nullopt,
                                                      bounds, 45.0f, aspect);
                    EXPECT_NEAR(glm::length(camera.eye - camera.target), distance,
                                1e-5f * distance);
                    const glm::vec2 extent = corners_extent(camera, bounds, aspect);
                    EXPECT_LE(std::max(extent.x, extent.y), 1.0f / 1.08f + 1e-4f)
                        << "aspect " << aspect << " pitch " << pitch << " yaw " << yaw;
                    largest = std::max({largest, extent.x, extent.y});
                }
                EXPECT_GT(largest, 0.85f) << "aspect " << aspect << " pitch " << pitch;
            }
        }
    }
}

TEST(Camera, FrameOrbitTakesTheMissingTargetAndDistanceFromTheBounds) {
    const Bounds bounds{{-0.3f, 0.0f, -0.2f}, {0.3f, 1.6f, 0.2f}};
    for (const float aspect : {0.5f, 4.0f / 3.0f, 2.0f}) {
        const Camera framed =
            frame_orbit(60.0f, 20.0f, std::nullopt, std::nullopt, bounds, 45.0f, aspect);
        EXPECT_EQ(framed.target, bounds.centre());
        // The automatic framing (the default orbit angles) frames the same cylinder: at the
        // orbit's own pitch, its distance.
        const Camera automatic = frame_bounds(bounds, 45.0f, aspect);
        EXPECT_NEAR(glm::length(automatic.eye - automatic.target),
                    glm::length(frame_orbit(Orbit{}.yaw, Orbit{}.pitch, std::nullopt, std::nullopt,
                                            bounds, 45.0f, aspect)
                                    .eye -
                                bounds.centre()),
                    1e-5f);
        const Camera expected =
            orbit_camera({60.0f, 20.0f, glm::length(framed.eye - framed.target), bounds.centre()});
        EXPECT_NEAR(glm::length(framed.eye - expected.eye), 0.0f, 1e-5f);
        const glm::vec2 framed_extent = corners_extent(framed, bounds, aspect);
        EXPECT_LE(std::max(framed_extent.x, framed_extent.y), 1.0f) << aspect;
        // A target off the centre moves back far enough to keep the whole scene in the frame.
        const Camera off_centre = frame_orbit(-120.0f, 60.0f, glm::vec3(0.3f, 0.0f, 0.2f),
                                              std::nullopt, bounds, 30.0f, aspect);
        EXPECT_EQ(off_centre.target, glm::vec3(0.3f, 0.0f, 0.2f));
        const glm::vec2 off_centre_extent = corners_extent(off_centre, bounds, aspect);
        EXPECT_LE(std::max(off_centre_extent.x, off_centre_extent.y), 1.0f) << aspect;
    }
    // Given ones win.
    const Camera given =
        frame_orbit(0.0f, 0.0f, glm::vec3(1.0f, 2.0f, 3.0f), 5.0f, bounds, 45.0f, 1.0f);
    EXPECT_EQ(given.target, glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_NEAR(glm::length(given.eye - glm::vec3(1.0f, 2.0f, 8.0f)), 0.0f, 1e-5f);
    const Camera distance_only = frame_orbit(0.0f, 0.0f, std::nullopt, 5.0f, bounds, 45.0f, 1.0f);
    EXPECT_NEAR(glm::length(distance_only.eye - (bounds.centre() + glm::vec3(0, 0, 5))), 0.0f,
                1e-5f);
}
