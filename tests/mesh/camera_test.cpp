#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
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

TEST(Camera, FramingFitsTheBoundingSphereInBothFieldsOfView) {
    const Bounds bounds{{-1.0f, 0.0f, -0.5f}, {1.0f, 2.0f, 0.5f}};
    const float radius = 0.5f * glm::length(bounds.max - bounds.min);
    for (const float aspect : {0.5f, 1.0f, 2.0f}) {
        const Camera camera = frame_bounds(bounds, 45.0f, aspect);
        const float distance = glm::length(camera.eye - bounds.centre());
        const float half_y = glm::radians(45.0f) / 2.0f;
        const float half_x = std::atan(std::tan(half_y) * aspect);
        // The sphere's angular radius from the eye fits inside the narrower half-angle.
        EXPECT_LE(std::asin(radius / distance), std::min(half_x, half_y) + 1e-5f) << aspect;
        EXPECT_NEAR(glm::length(camera.target - bounds.centre()), 0.0f, 1e-6f);
    }
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
