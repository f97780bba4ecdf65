// The ground as a shadow catcher (GroundLook::ShadowCatcher) and the floor's fade into the
// background (SceneBounds::ground_weight), against ray-cast geometry and the rig's own SH: over
// white, every pixel outside the box and its shadow is exactly white and every pixel inside is
// darkened by the light's share of the floor's irradiance; over transparency, the alpha is the
// opaque floor's darkening; the floor's coverage follows the fade with the distance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

#include "frame_test_support.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "synthetic_maps.hpp"

namespace {

using namespace oer;
using oer::testing::hits_box;
using oer::testing::linear_rgb;
using oer::testing::make_rig;
using oer::testing::pixel_ray;

class ShadowCatcherTest : public oer::testing::RendererSuite {};

constexpr int kSize = 192;
const glm::dvec3 kLow{-0.4, 0.0, -0.25}, kHigh{0.4, 0.5, 0.25};

// One small bright light high in the sky over a dim surround.
std::shared_ptr<const Rig> one_light_rig() {
    return make_rig(oer::testing::disc_map(512, 256, glm::vec3(0.05f),
                                           {{{0.5, 1.0, 0.3}, 0.02, {5e4f, 5e4f, 5e4f}}}),
                    1, 3);
}

// Straight down at the box: the whole frame is within 3 scene radii of it, inside the fade.
Camera top_camera() {
    Camera camera;
    camera.eye = {0.0f, 6.0f, 0.0f};
    camera.up = {0.0f, 0.0f, -1.0f};
    camera.fov_y = 30.0f;
    return camera;
}

// The grey box on the ground (boxes_on_ground_request; no occlusion, so that the ground's light
// is the rig's SH at +Y less the lights it does not see), in display output.
FrameRequest box_request(std::shared_ptr<const Rig> rig, const Camera& camera) {
    FrameRequest request =
        oer::testing::boxes_on_ground_request(std::move(rig), {{kLow, kHigh}}, camera, kSize);
    request.linear = false;
    return request;
}

// Per pixel: -1 the box, 1 the ground in the light's shadow, 0 the lit ground, 2 within two
// pixels of the shadow's edge (where a shadow map's texels may fall either way).
std::vector<int> ground_classes(const Camera& camera, const glm::dvec3& light) {
    std::vector<int> shadow(kSize * kSize, -1);
    const glm::dvec3 eye(camera.eye);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 ray = pixel_ray(camera, kSize, kSize, x, y);
            if (!hits_box(eye, ray, kLow, kHigh)) {
                shadow[y * kSize + x] = hits_box(eye + (-eye.y / ray.y) * ray, light, kLow, kHigh);
            }
        }
    }
    std::vector<int> classes = shadow;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const int own = shadow[y * kSize + x];
            for (int dy = -2; dy <= 2 && own >= 0; ++dy) {
                for (int dx = -2; dx <= 2; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx >= 0 && ny >= 0 && nx < kSize && ny < kSize &&
                        shadow[ny * kSize + nx] == 1 - own) {
                        classes[y * kSize + x] = 2;
                    }
                }
            }
        }
    }
    return classes;
}

const std::uint8_t* pixel(const Frame& frame, int x, int y) {
    return &frame.display.pixels[(std::size_t(y) * std::size_t(frame.width) + std::size_t(x)) * 4];
}

double luminance(const glm::dvec3& c) {
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

TEST_F(ShadowCatcherTest, OverWhiteOnlyTheShadowDarkensTheBackground) {
    const auto rig = one_light_rig();
    ASSERT_EQ(rig->lights.size(), 1u);
    FrameRequest request = box_request(rig, top_camera());
    request.ground_look = GroundLook::ShadowCatcher;
    request.background = {BackgroundKind::Color, glm::vec3(1.0f)};
    const std::vector<int> classes = ground_classes(top_camera(), rig->lights[0].direction);
    // In the shadow the floor keeps E(all) - E(light) of E(all): the background times that.
    const double open =
        luminance(irradiance_coefficients(rig->sh.all, rig->window).evaluate({0, 1, 0}));
    const double light =
        luminance(irradiance_coefficients(rig->sh.per_light[0], rig->window).evaluate({0, 1, 0}));
    ASSERT_GT(light / open, 0.5);
    const double shadowed = 255.0 * (1.0 - light / open);

    const Frame lit = render(request);
    int white = 0, dark = 0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const int kind = classes[y * kSize + x];
            const std::uint8_t* p = pixel(lit, x, y);
            if (kind == 0) {
                ASSERT_TRUE(p[0] == 255 && p[1] == 255 && p[2] == 255 && p[3] == 255)
                    << x << "," << y << ": " << int(p[0]) << " " << int(p[1]) << " " << int(p[2]);
                ++white;
            } else if (kind == 1) {
                for (int c = 0; c < 3; ++c) {
                    ASSERT_NEAR(p[c], shadowed, 1.0) << x << "," << y;
                }
                ++dark;
            }
        }
    }
    EXPECT_GT(white, 10000);
    EXPECT_GT(dark, 300);

    // Switched off, the light takes its shadow with it: every pixel off the box is white.
    request.lights = {0.0f};
    const Frame off = render(request);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            if (classes[y * kSize + x] >= 0) {
                const std::uint8_t* p = pixel(off, x, y);
                ASSERT_TRUE(p[0] == 255 && p[1] == 255 && p[2] == 255) << x << "," << y;
            }
        }
    }
}

TEST_F(ShadowCatcherTest, OverTransparencyTheAlphaIsTheOpaqueFloorsDarkening) {
    const auto rig = one_light_rig();
    FrameRequest opaque = box_request(rig, top_camera());
    opaque.linear = true;
    opaque.background.kind = BackgroundKind::Transparent;
    opaque.shadows.filter = ShadowFilter::Pcf;  // soft: the penumbra's partial alphas too
    const Frame floor = render(opaque);
    opaque.shadows.enabled = false;
    const Frame open_floor = render(opaque);

    FrameRequest catcher = opaque;
    catcher.shadows.enabled = true;
    catcher.linear = false;
    catcher.ground_look = GroundLook::ShadowCatcher;
    for (const double intensity : {1.0, 0.5}) {
        catcher.shadows.intensity = intensity;
        const Frame shadow = render(catcher);
        const std::vector<int> classes = ground_classes(top_camera(), rig->lights[0].direction);
        double largest_error = 0.0;
        int partial = 0;
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                if (classes[y * kSize + x] < 0) {
                    continue;
                }
                const double darkening = 1.0 - luminance(linear_rgb(floor, x, y)) /
                                                   luminance(linear_rgb(open_floor, x, y));
                const std::uint8_t* p = pixel(shadow, x, y);
                EXPECT_EQ(p[0] + p[1] + p[2], 0) << "the shadow is black, " << x << "," << y;
                largest_error =
                    std::max(largest_error, std::abs(p[3] / 255.0 - intensity * darkening));
                partial += darkening > 0.1 && darkening < 0.9;
            }
        }
        // One 8-bit step of rounding and the floor frame's float precision.
        EXPECT_LT(largest_error, 1.0 / 255.0 + 1e-3) << intensity;
        EXPECT_GT(partial, 50) << "a penumbra of partial alphas";
    }
}

TEST_F(ShadowCatcherTest, SoftnessScalesThePenumbra) {
    // A light of 8 degrees' radius: its penumbra on the ground is wide at softness 1.
    const auto rig =
        make_rig(oer::testing::disc_map(512, 256, glm::vec3(0.05f),
                                        {{{0.5, 1.0, 0.3}, 0.14, {500.0f, 500.0f, 500.0f}}}),
                 1, 3);
    ASSERT_EQ(rig->lights.size(), 1u);
    FrameRequest request = box_request(rig, top_camera());
    request.ground_look = GroundLook::ShadowCatcher;
    request.background.kind = BackgroundKind::Transparent;
    request.shadows.filter = ShadowFilter::Pcf;
    const auto penumbra_pixels = [&](double softness) {
        request.shadows.softness = softness;
        const Frame frame = render(request);
        int count = 0;
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                const int alpha = pixel(frame, x, y)[3];
                count += alpha > 25 && alpha < 230;
            }
        }
        return count;
    };
    const int soft = penumbra_pixels(1.0), hard = penumbra_pixels(0.0);
    EXPECT_GT(soft, 3 * hard) << soft << " against " << hard;
}

TEST_F(ShadowCatcherTest, TheFloorFadesIntoTheBackgroundWithDistance) {
    // High above, a wide field: the whole fade, from 5 to 20 scene radii, is in the frame.
    const auto rig = one_light_rig();
    Camera camera = top_camera();
    camera.eye = {0.0f, 12.0f, 0.0f};
    camera.fov_y = 100.0f;
    FrameRequest request = box_request(rig, camera);
    request.linear = true;
    request.background.kind = BackgroundKind::Transparent;
    const Frame frame = render(request);
    const SceneBounds scene = scene_bounds(request.objects);
    const glm::dvec3 eye(camera.eye);
    int full = 0, fading = 0, gone = 0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 ray = pixel_ray(camera, kSize, kSize, x, y);
            if (hits_box(eye, ray, kLow, kHigh)) {
                continue;
            }
            const glm::dvec3 point = eye + (-eye.y / ray.y) * ray;
            const double distance =
                glm::length(glm::dvec2(point.x - scene.centre.x, point.z - scene.centre.z));
            const double expected = scene.ground_weight(float(distance));
            // A pixel spans 0.28 scene radii here: the weight at its centre within 0.03.
            EXPECT_NEAR(oer::testing::linear_alpha(frame, x, y), expected, 0.03)
                << x << "," << y << " at " << distance;
            full += expected == 1.0;
            fading += expected > 0.05 && expected < 0.95;
            gone += expected == 0.0;
        }
    }
    EXPECT_GT(full, 500);
    EXPECT_GT(fading, 5000);
    EXPECT_GT(gone, 1000);
}

}  // namespace
