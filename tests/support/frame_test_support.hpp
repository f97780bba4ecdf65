#pragma once
// What the GL renderer's tests share: a render thread with one FrameRenderer for a suite, rigs
// of chosen light counts and orders, the ray geometry the frames are checked against
// (ray_geometry.hpp), and a linear frame's pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/lighting/rig.hpp"
#include "ray_geometry.hpp"
#include "test_meshes.hpp"

namespace oer::testing {

// A camera 3.5 units in front of the origin on +z, looking at it with a 40 degree vertical
// field: the unit sphere and box of the frame tests fill the middle half of the frame.
inline Camera front_camera() {
    Camera camera;
    camera.eye = {0.0f, 0.0f, 3.5f};
    camera.fov_y = 40.0f;
    return camera;
}

inline std::shared_ptr<const Rig> make_rig(const HdrImage& map, std::optional<int> lights,
                                           int order) {
    RigOptions options;
    options.light_count = lights;
    options.sh_order = order;
    return std::make_shared<const Rig>(build_rig(map, {}, options));
}

// One object-free request of the rig: camera, square size, no ground, one sample, linear output
// over transparency.
inline FrameRequest linear_request(std::shared_ptr<const Rig> rig, const Camera& camera, int size) {
    FrameRequest request;
    request.rig = std::move(rig);
    request.camera = camera;
    request.width = request.height = size;
    request.ground = false;
    request.background.kind = BackgroundKind::Transparent;
    request.samples = 1;
    request.linear = true;
    return request;
}

// Grey boxes (low, high corners) standing on the ground, hard shadows from a 2048 map, one
// sample, linear output over transparency: the set-up of the tests that compare shadows with
// ray-cast geometry, which change the filter, the map or the output where they need to.
inline FrameRequest boxes_on_ground_request(
    std::shared_ptr<const Rig> rig, const std::vector<std::pair<glm::dvec3, glm::dvec3>>& boxes,
    const Camera& camera, int size) {
    FrameRequest request = linear_request(std::move(rig), camera, size);
    request.ground = true;
    for (const auto& [low, high] : boxes) {
        request.objects.push_back({std::make_shared<const Mesh>(oer::testing::box(
                                       glm::vec3(low), glm::vec3(high), glm::vec3(0.5f))),
                                   glm::mat4(1.0f), std::nullopt});
    }
    request.shadows.filter = ShadowFilter::Hard;
    request.shadows.resolution = 2048;
    return request;
}

inline glm::dvec3 linear_rgb(const Frame& frame, int x, int y) {
    const float* p = &frame.linear[(std::size_t(y) * frame.width + x) * 4];
    return {p[0], p[1], p[2]};
}
inline float linear_alpha(const Frame& frame, int x, int y) {
    return frame.linear[(std::size_t(y) * frame.width + x) * 4 + 3];
}

inline std::shared_ptr<const Mesh> shared(Mesh mesh) {
    return std::make_shared<const Mesh>(std::move(mesh));
}

// A unit sphere at the origin with one material (256 segments, 128 rings).
inline std::shared_ptr<const Mesh> sphere_of(const Material& material) {
    Mesh mesh = uv_sphere({0, 0, 0}, 1.0f, 256, 128, glm::vec3(1.0f));
    mesh.materials[0] = material;
    return shared(std::move(mesh));
}

// The unit sphere's normal seen through pixel (x, y), or nothing for pixels that miss it or
// lie within about a pixel of its silhouette.
inline std::optional<glm::dvec3> sphere_normal(const Camera& camera, int size, int x, int y,
                                               glm::dvec3 centre = {0, 0, 0}, double radius = 1.0) {
    const glm::dvec3 eye(camera.eye);
    const glm::dvec3 ray = pixel_ray(camera, size, size, x, y);
    const auto t = hit_sphere(eye, ray, centre, radius);
    if (!t) {
        return std::nullopt;
    }
    const glm::dvec3 n = glm::normalize(eye + *t * ray - centre);
    return glm::dot(n, -ray) > 0.2 ? std::optional(n) : std::nullopt;
}

// A render thread and a FrameRenderer on it, made for a suite and shared by its tests.
class RendererSuite : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        thread_ = new RenderThread();
        renderer_ = thread_->submit([] { return std::make_shared<FrameRenderer>(); }).get();
    }
    static void TearDownTestSuite() {
        thread_->submit([] { renderer_.reset(); }).get();
        delete thread_;
        thread_ = nullptr;
    }
    static Frame render(const FrameRequest& request) {
        return thread_->submit([&request] { return renderer_->render(request); }).get();
    }
    static std::size_t cached_shadow_maps() {
        return thread_->submit([] { return renderer_->cached_shadow_maps(); }).get();
    }
    static std::size_t specular_uploads() {
        return thread_->submit([] { return renderer_->specular_uploads(); }).get();
    }
    static std::size_t transferred_irradiance_reuses() {
        return thread_->submit([] { return renderer_->transferred_irradiance_reuses(); }).get();
    }

    static inline RenderThread* thread_ = nullptr;
    static inline std::shared_ptr<FrameRenderer> renderer_;
};

}  // namespace oer::testing
