#pragma once
// What the GL renderer's tests share: a render thread with one FrameRenderer for a suite, rigs
// of chosen light counts and orders, the camera ray of a pixel and ray casts against spheres
// and boxes (the geometry the frames are checked against), and a linear frame's pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/lighting/rig.hpp"

namespace oer::testing {

inline std::shared_ptr<const Rig> make_rig(const HdrImage& map, std::optional<int> lights,
                                           int order) {
    RigOptions options;
    options.light_count = lights;
    options.sh_order = order;
    return std::make_shared<const Rig>(build_rig(map, {}, options));
}

// The camera ray through the centre of pixel (x, y), row 0 at the top.
inline glm::dvec3 pixel_ray(const Camera& camera, int width, int height, int x, int y) {
    const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target - camera.eye));
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double t = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
    const double nx = (2.0 * (x + 0.5) / width - 1.0) * t * width / height;
    const double ny = (1.0 - 2.0 * (y + 0.5) / height) * t;
    return glm::normalize(forward + nx * right + ny * up);
}

// The distance along the unit ray to its first meeting with the sphere, if any.
inline std::optional<double> hit_sphere(glm::dvec3 origin, glm::dvec3 ray, glm::dvec3 centre,
                                        double r) {
    const glm::dvec3 oc = origin - centre;
    const double b = glm::dot(oc, ray), c = glm::dot(oc, oc) - r * r;
    const double disc = b * b - c;
    if (disc < 0.0) {
        return std::nullopt;
    }
    return -b - std::sqrt(disc);
}

// Slab test: does the ray from origin along dir (t > 1e-6) hit the box?
inline bool hits_box(glm::dvec3 origin, glm::dvec3 dir, glm::dvec3 low, glm::dvec3 high) {
    double near_t = 1e-6, far_t = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-12) {
            if (origin[a] < low[a] || origin[a] > high[a]) {
                return false;
            }
            continue;
        }
        double t0 = (low[a] - origin[a]) / dir[a], t1 = (high[a] - origin[a]) / dir[a];
        if (t0 > t1) {
            std::swap(t0, t1);
        }
        near_t = std::max(near_t, t0);
        far_t = std::min(far_t, t1);
    }
    return near_t <= far_t;
}

inline glm::dvec3 linear_rgb(const Frame& frame, int x, int y) {
    const float* p = &frame.linear[(std::size_t(y) * frame.width + x) * 4];
    return {p[0], p[1], p[2]};
}
inline float linear_alpha(const Frame& frame, int x, int y) {
    return frame.linear[(std::size_t(y) * frame.width + x) * 4 + 3];
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

    static inline RenderThread* thread_ = nullptr;
    static inline std::shared_ptr<FrameRenderer> renderer_;
};

}  // namespace oer::testing
