// The GL renderer on this machine's EGL (llvmpipe here and in CI), checked against numbers
// computed independently of it: analytic sphere normals, ray-cast shadow geometry, and the
// rig's SH irradiance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "base64.hpp"
#include "frame_test_support.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "prefiltered_cubes.hpp"
#include "process_memory.hpp"
#include "synthetic_maps.hpp"
#include "test_meshes.hpp"

using namespace oer;
using oer::testing::DiscLight;
using oer::testing::front_camera;
using oer::testing::hit_sphere;
using oer::testing::hits_box;
using oer::testing::linear_alpha;
using oer::testing::linear_rgb;
using oer::testing::make_rig;
using oer::testing::pixel_ray;

namespace {

// Three lights from distinct directions over a dim sky.
HdrImage three_light_map() {
    return oer::testing::disc_map(512, 256, glm::vec3(0.3f),
                                  {{{1.0, 1.2, 0.0}, 0.05, {400.0f, 380.0f, 350.0f}},
                                   {{-0.6, 1.2, 0.8}, 0.05, {200.0f, 260.0f, 400.0f}},
                                   {{-0.5, 1.0, -0.9}, 0.05, {300.0f, 250.0f, 200.0f}}});
}

// The unit sphere's normal seen through pixel (x, y), or nothing for pixels that miss it or
// graze its silhouette (within about a pixel of the edge).
std::optional<glm::dvec3> sphere_normal_in_frame(const Camera& camera, int width, int height, int x,
                                                 int y) {
    const glm::dvec3 eye(camera.eye);
    const glm::dvec3 ray = pixel_ray(camera, width, height, x, y);
    const auto t = hit_sphere(eye, ray, {0, 0, 0}, 1.0);
    if (!t || glm::length(glm::cross(ray, eye)) > 0.97) {
        return std::nullopt;
    }
    return glm::normalize(eye + *t * ray);
}

// The display transform of premultiplied radiance (alpha: coverage) with the CPU's tone map,
// as the shaders apply it: exposure, tone map, sRGB, then over the background color by
// coverage. Display values in [0, 1].
glm::dvec3 display_color(glm::dvec4 radiance, const FrameRequest& request) {
    const double alpha = std::clamp(radiance.a, 0.0, 1.0);
    const float exposure_scale = float(std::exp2(request.exposure));
    const glm::vec3 linear =
        alpha > 0.0 ? glm::vec3(glm::max(glm::dvec3(radiance) / alpha, 0.0)) * exposure_scale
                    : glm::vec3(0.0f);
    const glm::vec3 mapped = tone_map(linear, request.tonemap);
    const glm::dvec3 display{srgb_encode(mapped.r), srgb_encode(mapped.g), srgb_encode(mapped.b)};
    return glm::mix(glm::dvec3(request.background.color), display, alpha);
}

class FrameRendererTest : public oer::testing::RendererSuite {
  protected:
    static FrameRequest sphere_request(std::shared_ptr<const Rig> rig, const Camera& camera) {
        FrameRequest request;
        request.rig = std::move(rig);
        request.objects.push_back({std::make_shared<const Mesh>(oer::testing::uv_sphere(
                                       {0, 0, 0}, 1.0f, 256, 128, glm::vec3(1.0f))),
                                   glm::mat4(1.0f), std::nullopt});
        request.camera = camera;
        request.width = 128;
        request.height = 128;
        request.ground = false;
        request.background.kind = BackgroundKind::Transparent;
        request.samples = 1;
        request.linear = true;
        return request;
    }
};

// One box of boxes_on_ground_request, its shadows from a finer map (4096).
FrameRequest box_on_ground_request(std::shared_ptr<const Rig> rig, glm::dvec3 low, glm::dvec3 high,
                                   const Camera& camera, int size) {
    FrameRequest request =
        oer::testing::boxes_on_ground_request(std::move(rig), {{low, high}}, camera, size);
    request.shadows.resolution = 4096;
    return request;
}

// glTF-Sample-Models' BoxTextured with its base-color image replaced by a grey width x height
// PNG, loaded as an upload would be.
Mesh box_textured_with(const std::string& root, int width, int height) {
    std::ifstream file(root + "BoxTextured-glTF-Embedded/BoxTextured.gltf");
    std::string gltf{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    const std::string marker = "data:image/png;base64,";
    const std::size_t start = gltf.find(marker);
    if (start == std::string::npos) {
        throw std::runtime_error("BoxTextured.gltf has no embedded PNG");
    }
    const std::size_t end = gltf.find('"', start);
    Rgba8Image image;
    image.width = width;
    image.height = height;
    image.pixels.assign(std::size_t(width) * std::size_t(height) * 4, 128);
    gltf.replace(start, end - start, marker + oer::testing::base64(encode_png(image)));
    return load_mesh_memory(std::as_bytes(std::span(gltf)), "BoxTextured.gltf", MeshFormat::Gltf);
}

}  // namespace

TEST_F(FrameRendererTest, WhiteSphereUnderAConstantEnvironmentHasItsRadiance) {
    const glm::vec3 radiance{0.5f, 1.0f, 2.0f};
    const auto rig = make_rig(oer::testing::constant_map(256, 128, radiance), 0, 3);
    const Frame frame = render(sphere_request(rig, front_camera()));
    int checked = 0;
    for (int y = 1; y < frame.height - 1; ++y) {
        for (int x = 1; x < frame.width - 1; ++x) {
            bool interior = true;  // away from the silhouette: every neighbour covered
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    interior = interior && linear_alpha(frame, x + dx, y + dy) == 1.0f;
                }
            }
            if (!interior) {
                continue;
            }
            const glm::dvec3 got = linear_rgb(frame, x, y);
            for (int c = 0; c < 3; ++c) {
                ASSERT_NEAR(got[c], radiance[c], 0.01 * radiance[c]) << x << "," << y;
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 3000);
}

TEST_F(FrameRendererTest, SpherePixelsMatchTheRigsShIrradianceAtTheirNormals) {
    const auto rig = make_rig(three_light_map(), 3, 5);
    for (const double yaw : {0.0, 90.0}) {
        FrameRequest request = sphere_request(rig, front_camera());
        request.shadows.enabled = false;
        request.environment_yaw = yaw;
        const Frame frame = render(request);
        const ShRgb irradiance = irradiance_coefficients(rig->sh.all, rig->window);
        double largest = 0.0;
        for (int y = 0; y < 128; ++y) {
            for (int x = 0; x < 128; ++x) {
                const auto n = equirect::pixel_direction(x, y, 128, 64);
                largest = std::max(largest, irradiance.evaluate(n).g / std::numbers::pi);
            }
        }
        int checked = 0;
        for (int y = 0; y < frame.height; ++y) {
            for (int x = 0; x < frame.width; ++x) {
                const auto normal =
                    sphere_normal_in_frame(*request.camera, frame.width, frame.height, x, y);
                if (!normal) {
                    continue;
                }
                // The environment turned by yaw lights n as the unturned one lights n turned back.
                const glm::dvec3 expected =
                    irradiance.evaluate(equirect::rotate_yaw(*normal, -yaw)) / std::numbers::pi;
                const glm::dvec3 got = linear_rgb(frame, x, y);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_NEAR(got[c], expected[c], 0.01 * std::abs(expected[c]) + 0.002 * largest)
                        << "pixel " << x << "," << y << " yaw " << yaw;
                }
                ++checked;
            }
        }
        EXPECT_GT(checked, 3000);
    }
}

namespace {

// Ground pixels of a box_on_ground_request classified by the lights whose shadow covers them
// (bit k: light k's), keeping only pixels whose neighbours two pixels away agree (away from
// every edge); -1 for the others.
std::vector<int> shadow_classes(const Rig& rig, const FrameRequest& request, glm::dvec3 low,
                                glm::dvec3 high) {
    const Camera& camera = *request.camera;
    const SceneBounds scene = scene_bounds(request.objects);
    const auto occluders = [&](int x, int y) -> std::optional<int> {
        const glm::dvec3 ray = pixel_ray(camera, request.width, request.height, x, y);
        const glm::dvec3 eye(camera.eye);
        if (ray.y >= 0.0 || hits_box(eye, ray, low, high)) {
            return std::nullopt;
        }
        const glm::dvec3 ground = eye + (-eye.y / ray.y) * ray;
        // Only the floor drawn whole: farther out it fades into the background.
        if (glm::length(glm::dvec2(ground.x - scene.centre.x, ground.z - scene.centre.z)) >
            scene.ground_fade_start()) {
            return std::nullopt;
        }
        int mask = 0;
        for (std::size_t k = 0; k < rig.lights.size(); ++k) {
            if (hits_box(ground, rig.lights[k].direction, low, high)) {
                mask |= 1 << k;
            }
        }
        return mask;
    };
    std::vector<int> classes(std::size_t(request.width * request.height), -1);
    for (int y = 2; y < request.height - 2; ++y) {
        for (int x = 2; x < request.width - 2; ++x) {
            const auto mask = occluders(x, y);
            bool stable = mask.has_value();
            for (const auto& [dx, dy] : {std::pair{-2, 0}, {2, 0}, {0, -2}, {0, 2}}) {
                stable = stable && occluders(x + dx, y + dy) == mask;
            }
            if (stable) {
                classes[std::size_t(y * request.width + x)] = *mask;
            }
        }
    }
    return classes;
}

// A box on the ground under the three-light map, seen from above at 160x160, and each ground
// pixel's set of lights that reach it by ray casting (shadow_classes): the scene of the tests that
// check a light's SH contribution where it reaches and where it is shadowed.
struct BoxShadowScene {
    std::shared_ptr<const Rig> rig;
    FrameRequest request;
    std::vector<int> classes;
};

BoxShadowScene box_shadow_scene() {
    const auto rig = make_rig(three_light_map(), 3, 3);
    const glm::dvec3 low{-0.3, 0.0, -0.3}, high{0.3, 0.6, 0.3};
    Camera camera;
    camera.eye = {0.0f, 4.0f, 3.0f};
    camera.fov_y = 50.0f;
    FrameRequest request = box_on_ground_request(rig, low, high, camera, 160);
    std::vector<int> classes = shadow_classes(*rig, request, low, high);
    return {rig, std::move(request), std::move(classes)};
}

}  // namespace

TEST_F(FrameRendererTest, ShadowsTakeExactlyTheirLightsShContribution) {
    const BoxShadowScene box = box_shadow_scene();
    ASSERT_EQ(box.rig->lights.size(), 3u);
    const std::shared_ptr<const Rig>& rig = box.rig;
    FrameRequest request = box.request;

    const std::vector<int>& classes = box.classes;
    std::vector<glm::dvec3> ground_irradiance;  // E_k(+Y) of each light
    for (int k = 0; k < 3; ++k) {
        ground_irradiance.push_back(
            irradiance_coefficients(rig->sh.per_light[k], rig->window).evaluate({0, 1, 0}));
    }
    int shadowed_pixels[3] = {0, 0, 0};
    for (int subset = 0; subset < 8; ++subset) {
        request.lights = {subset & 1 ? 1.0f : 0.0f, subset & 2 ? 1.0f : 0.0f,
                          subset & 4 ? 1.0f : 0.0f};
        request.shadows.enabled = true;
        const Frame shadowed = render(request);
        request.shadows.enabled = false;
        const Frame unshadowed = render(request);
        for (int y = 0; y < request.height; ++y) {
            for (int x = 0; x < request.width; ++x) {
                const int mask = classes[std::size_t(y * request.width + x)];
                if (mask < 0) {
                    continue;
                }
                glm::dvec3 expected_difference{0.0};
                for (int k = 0; k < 3; ++k) {
                    if ((mask & subset) & (1 << k)) {
                        expected_difference -= 0.8 / std::numbers::pi * ground_irradiance[k];
                        ++shadowed_pixels[k];
                    }
                }
                const glm::dvec3 difference =
                    linear_rgb(shadowed, x, y) - linear_rgb(unshadowed, x, y);
                const double scale = glm::length(linear_rgb(unshadowed, x, y));
                ASSERT_NEAR(glm::length(difference - expected_difference), 0.0, 1e-4 * scale + 1e-6)
                    << "pixel " << x << "," << y << " in the shadow of lights " << mask
                    << ", lights on " << subset;
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_GT(shadowed_pixels[k], 100) << "light " << k << " cast no checked shadow";
    }
}

TEST_F(FrameRendererTest, ALightsWeightScalesItsShContributionWhereItReaches) {
    // E = E(all) - sum_k (1 - w_k v_k) E(k) (docs/design.md section 2): from weight w to w', a
    // ground pixel changes by (w' - w) v_k E_k(+Y) albedo / pi, the whole step where light k
    // reaches it (v = 1) and nothing in its shadow (v = 0).
    const BoxShadowScene box = box_shadow_scene();
    ASSERT_EQ(box.rig->lights.size(), 3u);
    const std::shared_ptr<const Rig>& rig = box.rig;
    FrameRequest request = box.request;
    const std::vector<int>& classes = box.classes;
    constexpr std::size_t kDimmed = 0;
    const glm::dvec3 light_part =
        0.8 / std::numbers::pi *
        irradiance_coefficients(rig->sh.per_light[kDimmed], rig->window).evaluate({0, 1, 0});
    const std::vector<float> weights = {1.0f, 0.5f, 2.0f, 4.0f, 0.0f};
    std::vector<Frame> frames;
    for (const float weight : weights) {
        request.lights = {1.0f, 1.0f, 1.0f};
        request.lights[kDimmed] = weight;
        frames.push_back(render(request));
    }
    for (std::size_t step = 1; step < weights.size(); ++step) {
        const double change = double(weights[step]) - double(weights[step - 1]);
        int reached = 0, shadowed = 0;
        for (int y = 0; y < request.height; ++y) {
            for (int x = 0; x < request.width; ++x) {
                const int mask = classes[std::size_t(y * request.width + x)];
                if (mask < 0) {
                    continue;
                }
                const bool in_shadow = (mask & (1 << kDimmed)) != 0;
                const glm::dvec3 expected = in_shadow ? glm::dvec3(0.0) : change * light_part;
                const glm::dvec3 difference =
                    linear_rgb(frames[step], x, y) - linear_rgb(frames[step - 1], x, y);
                const double scale = glm::length(linear_rgb(frames[step - 1], x, y));
                ASSERT_NEAR(glm::length(difference - expected), 0.0, 1e-4 * scale + 1e-6)
                    << "pixel " << x << "," << y << (in_shadow ? " in" : " out of")
                    << " the light's shadow, weight " << weights[step - 1] << " -> "
                    << weights[step];
                ++(in_shadow ? shadowed : reached);
            }
        }
        EXPECT_GT(reached, 1000) << "step " << step;
        EXPECT_GT(shadowed, 100) << "step " << step;
    }
}

TEST_F(FrameRendererTest, AWeightOfZeroIsOffAndGetsNoShadowPass) {
    const auto rig = make_rig(three_light_map(), 3, 3);
    const glm::dvec3 low{-0.3, 0.0, -0.3}, high{0.3, 0.6, 0.3};
    Camera camera;
    camera.eye = {0.0f, 4.0f, 3.0f};
    camera.fov_y = 50.0f;
    FrameRequest request = box_on_ground_request(rig, low, high, camera, 64);
    request.shadows.resolution = 512;
    // Yaws no other test uses, so that every light's shadow map is a cache miss.
    request.environment_yaw = 17.0;
    request.lights = {1.0f, 0.0f, 1.0f};
    const Frame off = render(request);
    EXPECT_EQ(off.shadow_maps_rendered, 2);
    // The frame without light 1's shadow map is the frame with it: a light of weight 0 reads
    // no shadow layer, whatever the cache holds.
    request.lights = {1.0f, 1e-3f, 1.0f};
    EXPECT_EQ(render(request).shadow_maps_rendered, 1);
    request.lights = {1.0f, 0.0f, 1.0f};
    const Frame off_again = render(request);
    EXPECT_EQ(off_again.shadow_maps_rendered, 0);
    EXPECT_EQ(off_again.linear, off.linear);
    // And it does take the light away.
    request.lights = {1.0f, 1.0f, 1.0f};
    EXPECT_NE(render(request).linear, off.linear);
}

TEST_F(FrameRendererTest, ShadowEdgeLiesWhereGeometryPutsIt) {
    const auto rig = make_rig(oer::testing::disc_map(1024, 512, glm::vec3(0.05f),
                                                     {{{0.5, 1.0, 0.3}, 0.01, {5e4f, 5e4f, 5e4f}}}),
                              1, 3);
    ASSERT_EQ(rig->lights.size(), 1u);
    const glm::dvec3 low{-0.4, 0.0, -0.25}, high{0.4, 0.5, 0.25};
    Camera camera;
    camera.eye = {0.0f, 6.0f, 0.0f};
    camera.up = {0.0f, 0.0f, -1.0f};
    camera.fov_y = 30.0f;
    FrameRequest request = box_on_ground_request(rig, low, high, camera, 256);
    const Frame shadowed = render(request);
    request.shadows.enabled = false;
    const Frame unshadowed = render(request);
    const glm::dvec3 light_contribution =
        0.8 / std::numbers::pi *
        irradiance_coefficients(rig->sh.per_light[0], rig->window).evaluate({0, 1, 0});

    std::vector<int> predicted(256 * 256, -1), measured(256 * 256, -1);
    for (int y = 0; y < 256; ++y) {
        for (int x = 0; x < 256; ++x) {
            const glm::dvec3 ray = pixel_ray(camera, 256, 256, x, y);
            const glm::dvec3 eye(camera.eye);
            if (hits_box(eye, ray, low, high)) {
                continue;
            }
            const glm::dvec3 ground = eye + (-eye.y / ray.y) * ray;
            predicted[y * 256 + x] = hits_box(ground, rig->lights[0].direction, low, high);
            const double drop = (linear_rgb(unshadowed, x, y) - linear_rgb(shadowed, x, y)).g;
            measured[y * 256 + x] = drop > 0.5 * light_contribution.g;
        }
    }
    int shadow_pixels = 0, misplaced = 0;
    for (int y = 0; y < 256; ++y) {
        for (int x = 0; x < 256; ++x) {
            const int p = predicted[y * 256 + x];
            shadow_pixels += p == 1;
            if (p < 0 || p == measured[y * 256 + x]) {
                continue;
            }
            // A disagreement is allowed only within two pixels of a predicted edge.
            bool near_edge = false;
            for (int dy = -2; dy <= 2 && !near_edge; ++dy) {
                for (int dx = -2; dx <= 2 && !near_edge; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    near_edge = nx >= 0 && ny >= 0 && nx < 256 && ny < 256 &&
                                predicted[ny * 256 + nx] == 1 - p;
                }
            }
            misplaced += !near_edge;
        }
    }
    EXPECT_GT(shadow_pixels, 1000);
    EXPECT_EQ(misplaced, 0);
}

TEST_F(FrameRendererTest, EnvironmentBackgroundShowsTheMapInEachDirection) {
    // A smooth map, so that bilinear sampling equals the function to well under 1 %.
    HdrImage map(512, 256);
    const equirect::Grid grid(512, 256);
    const auto f = [](glm::dvec3 d) { return glm::dvec3(1.0 + d.x, 1.0 + d.y, 1.0 + d.z); };
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        map.set(i, glm::vec3(f(grid.direction(i))));
    }
    const auto rig = make_rig(map, 0, 3);
    for (const double yaw : {0.0, 60.0}) {
        FrameRequest request = sphere_request(rig, front_camera());
        request.objects.clear();
        request.environment_map = std::make_shared<const HdrImage>(map);
        request.background.kind = BackgroundKind::Environment;
        request.environment_yaw = yaw;
        const Frame frame = render(request);
        for (int y = 3; y < frame.height; y += 11) {
            for (int x = 5; x < frame.width; x += 13) {
                const glm::dvec3 ray = pixel_ray(*request.camera, frame.width, frame.height, x, y);
                const glm::dvec3 expected = f(equirect::rotate_yaw(ray, -yaw));
                const glm::dvec3 got = linear_rgb(frame, x, y);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(got[c], expected[c], 0.01 * expected[c] + 0.005) << x << "," << y;
                }
            }
        }
    }
}

TEST_F(FrameRendererTest, ThesisModelScalesByTheAttenuationFactor) {
    RigOptions options;
    options.light_count = 3;
    options.sh_order = 3;
    options.model = LightingModel::Thesis;
    const auto rig = std::make_shared<const Rig>(build_rig(three_light_map(), {}, options));
    FrameRequest request = sphere_request(rig, front_camera());
    request.shadows.enabled = false;
    request.lights = {1.0f, 0.0f, 1.0f};
    const Frame frame = render(request);
    const bool on[3] = {true, false, true};
    const ShRgb irradiance = irradiance_coefficients(subset_coefficients(rig->sh, on), rig->window);
    const double attenuation = 1.0 - rig->lights[1].luminance_share;
    int checked = 0;
    for (int y = 0; y < frame.height; y += 3) {
        for (int x = 0; x < frame.width; x += 3) {
            const auto normal =
                sphere_normal_in_frame(*request.camera, frame.width, frame.height, x, y);
            if (!normal) {
                continue;
            }
            const glm::dvec3 expected = irradiance.evaluate(*normal) * attenuation;  // albedo 1
            const glm::dvec3 got = linear_rgb(frame, x, y);
            EXPECT_NEAR(got.g, expected.g, 0.01 * std::abs(expected.g) + 1e-3) << x << "," << y;
            ++checked;
        }
    }
    EXPECT_GT(checked, 300);
}

TEST_F(FrameRendererTest, TransparentBackgroundGivesAlphaAndDisplayOutput) {
    const auto rig = make_rig(oer::testing::constant_map(64, 32, glm::vec3(0.18f)), 0, 3);
    FrameRequest request = sphere_request(rig, front_camera());
    request.linear = false;
    request.samples = 4;
    const Frame frame = render(request);
    ASSERT_EQ(frame.display.pixels.size(), std::size_t(128 * 128 * 4));
    EXPECT_EQ(frame.display.pixels[3], 0);  // a corner: background
    const std::size_t centre = (64 * 128 + 64) * 4;
    EXPECT_EQ(frame.display.pixels[centre + 3], 255);
    // Radiance 0.18 through the GPU tone mapper and sRGB equals the CPU implementation.
    const glm::vec3 mapped = tone_map(glm::vec3(0.18f), ToneMapper::Neutral);
    EXPECT_NEAR(frame.display.pixels[centre + 1], std::lround(255.0f * srgb_encode(mapped.g)), 1);
    // A solid color background composites exactly.
    request.background = {BackgroundKind::Color, {1.0f, 0.5f, 0.0f}};
    const Frame colored = render(request);
    EXPECT_EQ(colored.display.pixels[0], 255);
    EXPECT_NEAR(colored.display.pixels[1], 128, 1);
    EXPECT_EQ(colored.display.pixels[2], 0);
    EXPECT_EQ(colored.display.pixels[3], 255);
}

TEST_F(FrameRendererTest, AntiAliasingAveragesSupersamplesBeforeToneMapping) {
    const auto rig = make_rig(three_light_map(), 3, 3);
    FrameRequest request = sphere_request(rig, front_camera());
    request.ground = true;
    request.shadows.resolution = 1024;
    request.samples = 4;
    const Frame antialiased = render(request);
    // The same samples: a frame twice as wide and high, one sample per pixel.
    request.samples = 1;
    request.width = request.height = 256;
    const Frame fine = render(request);
    double largest_difference = 0.0;
    int partly_covered = 0;
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x < 128; ++x) {
            for (int c = 0; c < 4; ++c) {
                double mean = 0.0;
                for (int s = 0; s < 4; ++s) {
                    const int fx = 2 * x + (s & 1), fy = 2 * y + (s >> 1);
                    mean += 0.25 * fine.linear[(std::size_t(fy) * 256 + fx) * 4 + c];
                }
                const double value = antialiased.linear[(std::size_t(y) * 128 + x) * 4 + c];
                largest_difference =
                    std::max(largest_difference, std::abs(value - mean) / (std::abs(mean) + 1e-3));
            }
            const float alpha = linear_alpha(antialiased, x, y);
            partly_covered += alpha > 0.1f && alpha < 0.9f ? 1 : 0;
        }
    }
    EXPECT_LT(largest_difference, 1e-5);
    // The sphere's silhouette over the transparent background: coverage between 0 and 1.
    EXPECT_GT(partly_covered, 100);

    // Display output through ACES, curved at every radiance (Neutral is nearly linear below 0.76),
    // over a background color: each pixel must be the display transform of its samples' mean
    // radiance (`fine` holds them), not the mean of their display colors.
    request.samples = 4;
    request.width = request.height = 128;
    request.linear = false;
    request.tonemap = ToneMapper::Aces;
    request.exposure = 1.0;
    request.background = {BackgroundKind::Color, {0.2f, 0.3f, 0.4f}};
    const Frame displayed = render(request);
    ASSERT_EQ(displayed.display.pixels.size(), std::size_t(128 * 128 * 4));
    const auto sample = [&](int x, int y, int s) {
        const int fx = 2 * x + (s & 1), fy = 2 * y + (s >> 1);
        const float* p = &fine.linear[(std::size_t(fy) * 256 + fx) * 4];
        return glm::dvec4(p[0], p[1], p[2], p[3]);
    };
    double largest_error = 0.0;  // against averaging first, in 8-bit levels
    int edges = 0;               // pixels where the two orders differ by 3 levels or more
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x < 128; ++x) {
            glm::dvec4 mean_radiance{0.0};
            glm::dvec3 mean_display{0.0};
            for (int s = 0; s < 4; ++s) {
                mean_radiance += 0.25 * sample(x, y, s);
                mean_display += 0.25 * display_color(sample(x, y, s), request);
            }
            const glm::dvec3 averaged_first = 255.0 * display_color(mean_radiance, request);
            const glm::dvec3 mapped_first = 255.0 * mean_display;
            const std::uint8_t* got = &displayed.display.pixels[(std::size_t(y) * 128 + x) * 4];
            bool edge = false;
            for (int c = 0; c < 3; ++c) {
                largest_error = std::max(largest_error, std::abs(got[c] - averaged_first[c]));
                if (std::abs(averaged_first[c] - mapped_first[c]) >= 3.0) {
                    edge = true;
                    EXPECT_GE(std::abs(got[c] - mapped_first[c]), 2.0) << x << "," << y;
                }
            }
            EXPECT_EQ(got[3], 255);
            edges += edge ? 1 : 0;
        }
    }
    std::printf("display: largest difference from averaging first %.2f levels, %d edge pixels\n",
                largest_error, edges);
    // One level of rounding, and a little more where the floor fades into the background: there
    // the shaded target's half floats are divided by a partial coverage (1.05 on llvmpipe).
    EXPECT_LE(largest_error, 1.1);
    EXPECT_GT(edges, 50);  // 91 on llvmpipe
}

TEST_F(FrameRendererTest, GpuToneMapsMatchTheCpusOverARampOfRadiances) {
    // Frames of the environment alone, a constant map, so that every pixel's radiance is the
    // map's color times 2^exposure; exposures from -10 to +8 EV in quarter stops make the ramp.
    // The GPU's 8-bit sRGB output must be the CPU's tone map and encoding (renderer/lighting)
    // to within 1/255, at one sample per pixel (tone mapped in the shading pass) and at four
    // (in the resolve pass, from half-float radiance).
    double largest_error = 0.0;
    int compared = 0;
    for (const glm::vec3 color :
         {glm::vec3(1.0f), glm::vec3(1.0f, 0.45f, 0.1f), glm::vec3(0.05f, 0.2f, 1.0f)}) {
        const auto map = std::make_shared<const HdrImage>(oer::testing::constant_map(16, 8, color));
        FrameRequest request;
        request.rig = make_rig(*map, 0, 3);
        request.environment_map = map;
        request.ground = false;
        request.width = request.height = 4;
        for (const ToneMapper mapper : {ToneMapper::Aces, ToneMapper::Neutral}) {
            for (const int samples : {1, 4}) {
                for (int quarter_stops = -40; quarter_stops <= 32; ++quarter_stops) {
                    request.tonemap = mapper;
                    request.samples = samples;
                    request.exposure = 0.25 * quarter_stops;
                    const Frame frame = render(request);
                    const glm::vec3 mapped =
                        tone_map(color * float(std::exp2(request.exposure)), mapper);
                    for (std::size_t pixel = 0; pixel < 16; ++pixel) {
                        for (int c = 0; c < 3; ++c) {
                            const double expected = 255.0 * srgb_encode(mapped[c]);
                            const double error = std::abs(
                                frame.display.pixels[pixel * 4 + std::size_t(c)] - expected);
                            largest_error = std::max(largest_error, error);
                            ASSERT_LE(error, 1.0)
                                << to_string(mapper) << " samples " << samples << " exposure "
                                << request.exposure << " channel " << c;
                            ++compared;
                        }
                    }
                }
            }
        }
    }
    std::printf("%d values: largest difference from the CPU %.2f levels\n", compared,
                largest_error);
}

TEST_F(FrameRendererTest, ValidationKeepsTheRenderersOwnRules) {
    const auto rig = make_rig(three_light_map(), 3, 3);
    FrameRequest good = sphere_request(rig, front_camera());
    good.width = good.height = 32;
    const auto expect_error = [&](const FrameRequest& request, ErrorKind kind,
                                  const std::string& member) {
        try {
            render(request);
            ADD_FAILURE() << "accepted a request with a bad " << member;
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), kind) << error.what();
            EXPECT_NE(std::string(error.what()).find(member), std::string::npos) << error.what();
        }
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    FrameRequest request = good;
    request.samples = 0;
    expect_error(request, ErrorKind::InvalidInput, "samples");
    request = good;
    request.shadows.resolution = 0;
    expect_error(request, ErrorKind::LimitExceeded, "shadow_resolution");
    request = good;
    request.shadows.resolution = 1 << 20;
    expect_error(request, ErrorKind::LimitExceeded, "shadow_resolution");
    request = good;
    request.exposure = nan;
    expect_error(request, ErrorKind::InvalidInput, "exposure");
    request = good;
    request.background = {BackgroundKind::Color, {nan, 0.0f, 0.0f}};
    expect_error(request, ErrorKind::InvalidInput, "background");
    request = good;
    request.objects[0].base_color = glm::vec3(-0.1f);
    expect_error(request, ErrorKind::InvalidInput, "objects[0].base_color");
    request = good;
    request.objects[0].mesh = nullptr;
    expect_error(request, ErrorKind::InvalidInput, "objects[0].mesh");

    // What only the API rules out, the renderer draws: 3 samples (the API offers 1, 2, 4 and
    // 8), an 8-texel shadow map (the API asks for a power of two of at least 64), and a
    // background color outside [0, 1], which the 8-bit output clamps.
    request = good;
    request.samples = 3;
    request.shadows.resolution = 8;
    request.linear = false;
    request.background = {BackgroundKind::Color, {1.5f, 0.5f, -0.25f}};
    const Frame frame = render(request);
    ASSERT_EQ(frame.display.pixels.size(), std::size_t(32 * 32 * 4));
    EXPECT_EQ(frame.display.pixels[0], 255);  // a corner: the background
    EXPECT_NEAR(frame.display.pixels[1], 128, 1);
    EXPECT_EQ(frame.display.pixels[2], 0);
    EXPECT_EQ(frame.display.pixels[3], 255);
}

TEST_F(FrameRendererTest, SixteenShadowingLightsEachCastTheirShadow) {
    // 16 lights need 16 shadow maps: more than one texture unit each would exceed what GPUs
    // and llvmpipe offer.
    std::vector<oer::testing::DiscLight> discs;
    for (int i = 0; i < 16; ++i) {
        const double angle = 2.0 * std::numbers::pi * i / 16.0;
        discs.push_back({{std::cos(angle), 0.9, std::sin(angle)}, 0.06, {100.0f, 100.0f, 100.0f}});
    }
    RigOptions options;
    options.light_count = 16;
    options.sh_order = 3;
    options.location.cluster_count = 16;
    const auto rig = std::make_shared<const Rig>(
        build_rig(oer::testing::disc_map(1024, 512, glm::vec3(0.1f), discs), {}, options));
    ASSERT_EQ(rig->lights.size(), 16u);
    // A long, low box (a sphere would cast the same shadow map from every direction, so a
    // light reading another's map would go unnoticed), seen from above.
    const glm::dvec3 low{-1.2, 0.0, -0.3}, high{0.6, 0.5, 0.3};
    Camera above;
    above.eye = {0.0f, 6.0f, 0.01f};
    above.fov_y = 50.0f;
    FrameRequest request = box_on_ground_request(rig, low, high, above, 96);
    request.shadows.filter = ShadowFilter::Pcf;
    request.shadows.resolution = 1024;
    const Frame all_on = render(request);
    EXPECT_EQ(all_on.shadow_maps_rendered, 16);
    for (int k = 0; k < 16; k += 5) {
        request.lights.assign(16, 1.0f);
        request.lights[std::size_t(k)] = 0.0f;
        const Frame one_off = render(request);
        EXPECT_EQ(one_off.shadow_maps_rendered, 0) << "light " << k;
        // Over the ground, light k's part of the frame is zero in the box's shadow along light
        // k's direction (ray cast against a box shrunk or grown by a margin for the filter) and
        // whole elsewhere.
        const glm::dvec3 towards_light = rig->lights[std::size_t(k)].direction;
        const glm::dvec3 margin{0.05};
        double lit_part = 0.0;
        int shadowed = 0, lit = 0;
        std::vector<std::pair<double, bool>> ground;  // part, in shadow
        for (int y = 0; y < 96; ++y) {
            for (int x = 0; x < 96; ++x) {
                const glm::dvec3 eye(above.eye), ray = pixel_ray(above, 96, 96, x, y);
                if (hits_box(eye, ray, low - margin, high + margin) || ray.y >= 0.0) {
                    continue;
                }
                const glm::dvec3 point = eye + (-eye.y / ray.y) * ray;
                const double part = linear_rgb(all_on, x, y).g - linear_rgb(one_off, x, y).g;
                if (hits_box(point, towards_light, low + margin, high - margin)) {
                    ground.push_back({part, true});
                    ++shadowed;
                } else if (!hits_box(point, towards_light, low - margin, high + margin)) {
                    ground.push_back({part, false});
                    lit_part = std::max(lit_part, part);
                    ++lit;
                }
            }
        }
        ASSERT_GT(shadowed, 20) << "light " << k;
        ASSERT_GT(lit, 1000) << "light " << k;
        for (const auto& [part, in_shadow] : ground) {
            if (in_shadow) {
                EXPECT_LT(part, 0.02 * lit_part) << "light " << k;
            } else {
                EXPECT_GT(part, 0.98 * lit_part) << "light " << k;
            }
        }
    }
}

TEST_F(FrameRendererTest, ShadowMapsAreCachedAcrossCameraMoves) {
    const auto rig = make_rig(three_light_map(), 3, 3);
    FrameRequest request = sphere_request(rig, front_camera());
    request.ground = true;
    request.width = request.height = 64;
    request.shadows.resolution = 512;
    const Frame first = render(request);
    EXPECT_EQ(first.shadow_maps_rendered, 3);
    request.camera->eye = {2.0f, 1.0f, 3.0f};
    EXPECT_EQ(render(request).shadow_maps_rendered, 0);
    request.lights = {1.0f, 0.0f, 1.0f};
    EXPECT_EQ(render(request).shadow_maps_rendered, 0);
    request.environment_yaw = 45.0;  // the lights move
    EXPECT_EQ(render(request).shadow_maps_rendered, 2);
    EXPECT_GE(cached_shadow_maps(), 5u);
}

// Previews (512-texel maps, the lights turned) between full frames (2048) change nothing of the
// full frame: each layout keeps its own layers, and the full frame after them, drawn from the
// layers it left, equals the first one bit for bit; a third layout then replaces one of the two.
TEST_F(FrameRendererTest, FramesAlternatingShadowResolutionsKeepTheirOwnShadows) {
    const BoxShadowScene box = box_shadow_scene();
    FrameRequest full = box.request;
    full.shadows.resolution = 2048;
    FrameRequest preview = box.request;
    preview.shadows.resolution = 512;
    preview.environment_yaw = 60.0;
    // Linear or display, whichever the request asks for: the other is empty in both frames.
    const auto same = [](const Frame& a, const Frame& b) {
        return a.linear == b.linear && a.display.pixels == b.display.pixels;
    };
    const Frame first = render(full);
    const Frame turned = render(preview);
    EXPECT_EQ(turned.shadow_maps_rendered, 3);
    const Frame again = render(full);
    EXPECT_EQ(again.shadow_maps_rendered, 0);
    EXPECT_TRUE(same(again, first)) << "the full frame after a preview differs";
    EXPECT_FALSE(same(turned, first)) << "the preview's shadows are not the full frame's";
    FrameRequest third = box.request;
    third.shadows.resolution = 1024;
    render(third);
    EXPECT_TRUE(same(render(full), first)) << "after a third layout";
}

TEST_F(FrameRendererTest, MalformedRequestsAreRejectedNamingTheMember) {
    const auto rig = make_rig(three_light_map(), 3, 3);
    const auto expect_error = [&](FrameRequest request, ErrorKind kind, const std::string& member) {
        try {
            render(request);
            ADD_FAILURE() << "accepted a request with a bad " << member;
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), kind) << error.what();
            EXPECT_NE(std::string(error.what()).find(member), std::string::npos) << error.what();
        }
    };
    FrameRequest good = sphere_request(rig, front_camera());
    FrameRequest request = good;
    request.lights = {1.0f};
    expect_error(request, ErrorKind::InvalidInput, "lights");
    request = good;
    request.width = 0;
    expect_error(request, ErrorKind::InvalidInput, "width");
    request = good;
    request.width = 100000;
    expect_error(request, ErrorKind::LimitExceeded, "width");
    request = good;
    request.camera->target = request.camera->eye;
    expect_error(request, ErrorKind::InvalidInput, "camera");
    request = good;
    request.objects[0].transform = glm::mat4(0.0f);
    expect_error(request, ErrorKind::InvalidInput, "objects[0].transform");
    request = good;
    request.background.kind = BackgroundKind::Environment;
    expect_error(request, ErrorKind::InvalidInput, "background");
    request = good;
    request.width = request.height = 4096;
    request.samples = 16;
    expect_error(request, ErrorKind::LimitExceeded, "samples");
    // The renderer is still fine afterwards.
    EXPECT_EQ(render(good).width, 128);
}

TEST_F(FrameRendererTest, MemoryIsBoundedOverManyFrames) {
    const auto rig = make_rig(three_light_map(), 3, 3);
    FrameRequest request = sphere_request(rig, front_camera());
    request.ground = true;
    request.width = request.height = 96;
    request.shadows.resolution = 512;
    request.linear = false;
    for (int i = 0; i < 10; ++i) {
        request.camera->eye.x = 0.01f * float(i);
        render(request);
    }
    const std::size_t heap_after_ten = oer::testing::live_heap_bytes();
    const long resident_after_ten = oer::testing::resident_kib();
    for (int i = 10; i < 200; ++i) {
        request.camera->eye.x = 0.01f * float(i);
        render(request);
    }
    const long heap_growth_kib =
        (long(oer::testing::live_heap_bytes()) - long(heap_after_ten)) / 1024;
    const long resident_growth_kib = oer::testing::resident_kib() - resident_after_ten;
    std::printf(
        "over 190 frames after the first 10: live heap grew %ld KiB, resident memory %ld "
        "KiB\n",
        heap_growth_kib, resident_growth_kib);
    // Below a quarter of what leaking one readback (96x96 RGBA8, 36 KiB) per frame would add.
    const long leaked_readbacks_kib = 190L * 96 * 96 * 4 / 1024;
    EXPECT_LT(heap_growth_kib, leaked_readbacks_kib / 4);
    // The resident set also sees memory outside the heap (JIT code, mappings); under ASan it
    // would measure the quarantine of freed blocks instead.
    if (oer::testing::kResidentMemoryIsTheProgramsOwn) {
        EXPECT_LT(resident_growth_kib, 16 * 1024);
    }
}

TEST_F(FrameRendererTest, BrokenAssetsAreRejectedAndLeaveTheRendererClean) {
    const std::string root = "/usr/share/assimp/models/glTF2/";
    if (!std::filesystem::exists(root)) {
        GTEST_SKIP() << "assimp-testmodels is not installed: " << root << " is missing";
    }
    int rejected = 0;
    for (const char* sample :
         {"IndexOutOfRange/IndexOutOfRange.gltf",
          "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "MissingBin/BoxTextured.gltf",
          "RecursiveNodes/RecursiveNodes.gltf"}) {
        if (!std::filesystem::exists(root + std::string(sample))) {
            continue;
        }
        try {
            load_mesh_file(root + std::string(sample));
            ADD_FAILURE() << sample << " was accepted";
        } catch (const Error& error) {
            EXPECT_FALSE(std::string(error.what()).empty());
            ++rejected;
        }
    }
    EXPECT_EQ(rejected, 4);

    const auto rig = make_rig(three_light_map(), 3, 3);
    FrameRequest good = sphere_request(rig, front_camera());
    good.ground = true;
    // The glTF samples' materials are glossy: their frames read the residual map prefiltered,
    // near the sky's constant 0.3.
    good.specular =
        oer::testing::specular_of(oer::testing::constant_cube(glm::vec3(0.3f)), rig->lights.size());
    const Frame before = render(good);

    // Assets that load but are degenerate, each beside the sphere, through every pass: normals
    // the loader repaired, zero-area and collinear triangles (flat bounds), extents of 1e30 and
    // 1e-30, and a texture as wide as GL allows. One more texel of width passes the loaders,
    // which bound pixels, not sides, and GL would refuse its storage: the renderer refuses it
    // first.
    const int widest = thread_->info().max_texture_size;
    std::vector<std::pair<std::string, Mesh>> degenerate;
    degenerate.emplace_back("BoxBadNormals",
                            load_mesh_file(root + "BoxBadNormals-glTF-Binary/BoxBadNormals.glb"));
    for (const std::string obj :
         {"v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
          "v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n",
          "v 0 0 0\nv 1e-30 0 0\nv 0 1e-30 0\nf 1 2 3\n"}) {
        degenerate.emplace_back(obj, load_mesh_memory(std::as_bytes(std::span(obj)),
                                                      "degenerate.obj", MeshFormat::Obj));
    }
    for (const int width : {widest, widest + 1}) {
        degenerate.emplace_back("a " + std::to_string(width) + "x1 texture",
                                box_textured_with(root, width, 1));
    }
    std::vector<std::string> refused;
    for (const auto& [name, mesh] : degenerate) {
        FrameRequest request = good;
        request.objects.push_back(
            {std::make_shared<const Mesh>(mesh), glm::mat4(1.0f), std::nullopt});
        try {
            const Frame frame = render(request);
            EXPECT_EQ(frame.linear.size(), std::size_t(good.width * good.height * 4)) << name;
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded) << name << ": " << error.what();
            EXPECT_NE(std::string(error.what()).find("objects[1].mesh: texture 0"),
                      std::string::npos)
                << error.what();
            refused.push_back(name);
        }
    }
    EXPECT_EQ(refused, std::vector<std::string>{"a " + std::to_string(widest + 1) + "x1 texture"});
    // The next good frame is the one before, to the bit: render() ends with check_gl_errors,
    // which throws on any GL error left behind, and nothing of the degenerate frames remains.
    const Frame after = render(good);
    EXPECT_EQ(after.linear, before.linear);
}

// Hard cases: scale, grazing, polar and seam lights, and a sun beyond the half-float
// range, each against ray-cast geometry or plain finiteness.
namespace {

struct Box {
    glm::dvec3 low, high;
};

// The first box face the ray from origin along dir (t > 1e-6) meets, as its outward normal.
std::optional<glm::dvec3> box_face_hit(glm::dvec3 origin, glm::dvec3 dir, const Box& box) {
    double near_t = 1e-6, far_t = 1e30;
    int near_axis = -1;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-12) {
            if (origin[a] < box.low[a] || origin[a] > box.high[a]) {
                return std::nullopt;
            }
            continue;
        }
        double t0 = (box.low[a] - origin[a]) / dir[a], t1 = (box.high[a] - origin[a]) / dir[a];
        if (t0 > t1) {
            std::swap(t0, t1);
        }
        if (t0 > near_t) {
            near_t = t0;
            near_axis = a;
        }
        far_t = std::min(far_t, t1);
    }
    if (near_t > far_t || near_axis < 0) {
        return std::nullopt;
    }
    glm::dvec3 normal(0.0);
    normal[near_axis] = dir[near_axis] > 0.0 ? -1.0 : 1.0;
    return normal;
}

// One light's shadows in a frame of boxes on the ground, against ray casting: each ground pixel
// is predicted in shadow when the ray from its ground point towards the light meets a box, and
// measured in shadow when the shadowed frame is darker than the unshadowed one by more than half
// the light's contribution there. Ground pixels whose prediction and measurement disagree
// further than two pixels from a predicted edge are misplaced: acne on the ground, a shadow
// detached from its caster (peter-panning) or one in the wrong place. Box faces that face the
// light and are not in another box's shadow are acne when any of the light is lost there.
struct ShadowCheck {
    int shadow_pixels = 0;  // ground pixels predicted in shadow
    int lit_pixels = 0;     // ground pixels predicted lit
    int misplaced = 0;
    int lit_faces = 0;  // box-face pixels facing the light
    int acne = 0;       // ... of which lose more than 2 % of the light
};

// unit: the scene's scale; the ray casting runs in multiples of it (hits_box's 1e-6 is absolute).
ShadowCheck check_shadows(const Frame& shadowed, const Frame& unshadowed, const Rig& rig,
                          std::vector<Box> boxes, const Camera& camera, float box_albedo,
                          double unit = 1.0) {
    const int width = shadowed.width, height = shadowed.height;
    for (Box& box : boxes) {
        box = {box.low / unit, box.high / unit};
    }
    const glm::dvec3 towards_light = rig.lights[0].direction;
    const ShRgb light_irradiance = irradiance_coefficients(rig.sh.per_light[0], rig.window);
    const double ground_part = 0.8 / std::numbers::pi * light_irradiance.evaluate({0, 1, 0}).g;
    const double ground_y = boxes[0].low.y;
    const auto shadowed_point = [&](glm::dvec3 point) {
        return std::any_of(boxes.begin(), boxes.end(), [&](const Box& b) {
            return hits_box(point, towards_light, b.low, b.high);
        });
    };
    ShadowCheck check;
    std::vector<int> predicted(std::size_t(width * height), -1), measured = predicted;
    const glm::dvec3 eye = glm::dvec3(camera.eye) / unit;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 ray = pixel_ray(camera, width, height, x, y);
            const double drop = (linear_rgb(unshadowed, x, y) - linear_rgb(shadowed, x, y)).g;
            // The nearest box the camera sees, if any.
            double nearest = HUGE_VAL;
            std::optional<glm::dvec3> face;
            glm::dvec3 face_point{0.0};
            for (const Box& b : boxes) {
                const auto normal = box_face_hit(eye, ray, b);
                if (!normal) {
                    continue;
                }
                // The hit's distance along the ray, from the face's plane.
                const int axis = std::abs(normal->x) > 0.5 ? 0 : std::abs(normal->y) > 0.5 ? 1 : 2;
                const double plane = (*normal)[axis] > 0.0 ? b.high[axis] : b.low[axis];
                const double t = (plane - eye[axis]) / ray[axis];
                if (t < nearest) {
                    nearest = t;
                    face = normal;
                    face_point = eye + t * ray;
                }
            }
            if (face) {
                const double facing = glm::dot(*face, towards_light);
                if (facing > 0.0 && !shadowed_point(face_point + 1e-9 * *face)) {
                    const double part =
                        box_albedo / std::numbers::pi * light_irradiance.evaluate(*face).g;
                    ++check.lit_faces;
                    check.acne += part > 0.0 && drop > 0.02 * part;
                }
                continue;
            }
            if (ray.y >= 0.0 || linear_alpha(unshadowed, x, y) < 1.0f) {
                continue;  // the sky, or beyond the ground's edge
            }
            const glm::dvec3 ground = eye + ((ground_y - eye.y) / ray.y) * ray;
            const int in_shadow = shadowed_point(ground);
            predicted[std::size_t(y * width + x)] = in_shadow;
            measured[std::size_t(y * width + x)] = drop > 0.5 * ground_part;
            ++(in_shadow ? check.shadow_pixels : check.lit_pixels);
        }
    }
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const int p = predicted[std::size_t(y * width + x)];
            if (p < 0 || p == measured[std::size_t(y * width + x)]) {
                continue;
            }
            bool near_edge = false;
            for (int dy = -2; dy <= 2 && !near_edge; ++dy) {
                for (int dx = -2; dx <= 2 && !near_edge; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    near_edge = nx >= 0 && ny >= 0 && nx < width && ny < height &&
                                predicted[std::size_t(ny * width + nx)] == 1 - p;
                }
            }
            check.misplaced += !near_edge;
        }
    }
    return check;
}

// Boxes of albedo 0.5 on the ground under a one-light rig, hard 4096-texel shadows, linear
// output; the shadowed and unshadowed frames.
std::pair<Frame, Frame> render_boxes(const std::function<Frame(const FrameRequest&)>& render,
                                     std::shared_ptr<const Rig> rig, const std::vector<Box>& boxes,
                                     const Camera& camera, int size) {
    FrameRequest request = box_on_ground_request(rig, boxes[0].low, boxes[0].high, camera, size);
    for (std::size_t i = 1; i < boxes.size(); ++i) {
        request.objects.push_back(
            {std::make_shared<const Mesh>(oer::testing::box(
                 glm::vec3(boxes[i].low), glm::vec3(boxes[i].high), glm::vec3(0.5f))),
             glm::mat4(1.0f), std::nullopt});
    }
    const Frame shadowed = render(request);
    request.shadows.enabled = false;
    return {shadowed, render(request)};
}

// A one-light rig from a small bright disc towards direction.
std::shared_ptr<const Rig> one_light_rig(glm::dvec3 direction) {
    return make_rig(oer::testing::disc_map(1024, 512, glm::vec3(0.05f),
                                           {{direction, 0.01, {5e4f, 5e4f, 5e4f}}}),
                    1, 3);
}

// The frames that isolate a one-light request's light: as asked, without shadows, and with the
// light's weight at 0 (its contribution is the difference with the last).
struct LightContributionFrames {
    Frame shadowed, unshadowed, off;
};
LightContributionFrames light_contribution_frames(
    const std::function<Frame(const FrameRequest&)>& render, FrameRequest request) {
    LightContributionFrames frames;
    frames.shadowed = render(request);
    request.shadows.enabled = false;
    frames.unshadowed = render(request);
    request.shadows.enabled = true;
    request.lights = {0.0f};
    frames.off = render(request);
    return frames;
}

// Renders the boxes under rig's light with and without shadows (box albedo 0.5, 256 pixels) and
// expects no ground pixel misplaced and no acne, over at least the given numbers of shadowed
// ground pixels and lit box pixels (so that a frame without the shadow or the box fails);
// `label` names the case in the printed figures and in failures, unit is check_shadows's.
void expect_shadows_in_place(const std::function<Frame(const FrameRequest&)>& render,
                             std::shared_ptr<const Rig> rig, const std::vector<Box>& boxes,
                             const Camera& camera, const std::string& label,
                             int least_shadow_pixels, int least_lit_faces, double unit = 1.0) {
    const auto [shadowed, unshadowed] = render_boxes(render, rig, boxes, camera, 256);
    const ShadowCheck check = check_shadows(shadowed, unshadowed, *rig, boxes, camera, 0.5f, unit);
    std::printf(
        "[ measured ] %s: %d shadow, %d lit ground pixels, %d misplaced; %d lit box pixels, %d "
        "with acne\n",
        label.c_str(), check.shadow_pixels, check.lit_pixels, check.misplaced, check.lit_faces,
        check.acne);
    EXPECT_GT(check.shadow_pixels, least_shadow_pixels) << label;
    EXPECT_GT(check.lit_faces, least_lit_faces) << label;
    EXPECT_EQ(check.misplaced, 0) << label;
    EXPECT_EQ(check.acne, 0) << label;
}

}  // namespace

TEST_F(FrameRendererTest, ShadowsLandWhereGeometryPutsThemAtEveryScale) {
    // The scene of ShadowEdgeLiesWhereGeometryPutsIt scaled by 1e-6, 1e-4 and 1e4: the shadow
    // maps, their bias and normal offset and the camera's planes all follow the scene's size,
    // so the same pixels are in shadow (at 1e-6, before the scene's radius lost its 1e-4 floor,
    // 288 ground pixels were misplaced). Stated bounds: no ground pixel misplaced further than
    // two image pixels from a predicted edge (2 x 6 s x 2 tan 15 deg / 256 = 0.025 s, 3 % of the
    // box's width: the peter-panning allowed), and no light lost on the box's top (acne: a drop
    // above 2 % of the light's part).
    const auto rig = one_light_rig({0.5, 1.0, 0.3});
    ASSERT_EQ(rig->lights.size(), 1u);
    for (const double scale : {1e-6, 1e-4, 1.0, 1e4}) {
        const std::vector<Box> boxes = {
            {glm::dvec3{-0.4, 0.0, -0.25} * scale, glm::dvec3{0.4, 0.5, 0.25} * scale}};
        Camera camera;
        camera.eye = {0.0f, float(6.0 * scale), 0.0f};
        camera.target = {0.0f, 0.0f, 0.0f};
        camera.up = {0.0f, 0.0f, -1.0f};
        camera.fov_y = 30.0f;
        char label[32];
        std::snprintf(label, sizeof label, "scale %g", scale);
        expect_shadows_in_place(render, rig, boxes, camera, label, 1000, 1000, scale);
    }
}

TEST_F(FrameRendererTest, GrazingLightsCastLongShadowsWithoutAcne) {
    // Lights 2 and 6 degrees above the horizon: shadows 14 and 4.8 times the box's height,
    // the box's top lit at n . l = 0.035 and 0.1, where a depth bias too small shows acne and
    // one too large detaches the shadow. Same bounds as at every scale.
    const std::vector<Box> boxes = {{{-0.3, 0.0, -0.3}, {0.3, 0.5, 0.3}}};
    Camera above;
    above.eye = {0.0f, 24.0f, 0.0f};
    above.target = {0.0f, 0.0f, 0.0f};
    above.up = {0.0f, 0.0f, -1.0f};
    above.fov_y = 50.0f;
    for (const double elevation : {2.0, 6.0}) {
        const double e = glm::radians(elevation), azimuth = glm::radians(30.0);
        const auto rig = one_light_rig(
            {std::cos(e) * std::cos(azimuth), std::sin(e), std::cos(e) * std::sin(azimuth)});
        ASSERT_EQ(rig->lights.size(), 1u);
        char label[40];
        std::snprintf(label, sizeof label, "light %.0f degrees up", elevation);
        expect_shadows_in_place(render, rig, boxes, above, label, 200, 20);
    }
}

TEST_F(FrameRendererTest, LightsAtThePoleAndOnTheSeamCastTheirShadows) {
    // A slab on a pedestal, seen from low in front so that the ground under the slab shows: a
    // light straight overhead (+Y, where the light's view needs another up vector) shadows the
    // slab's footprint, and a light on the seam (phi = pi, direction -X) shadows towards +X.
    const std::vector<Box> boxes = {{{-0.15, 0.0, -0.15}, {0.15, 0.4, 0.15}},
                                    {{-0.5, 0.4, -0.35}, {0.5, 0.5, 0.35}}};
    Camera low_front;
    low_front.eye = {0.6f, 0.9f, 3.0f};
    low_front.target = {0.0f, 0.2f, 0.0f};
    low_front.fov_y = 45.0f;
    for (const glm::dvec3 direction : {glm::dvec3{0.0, 1.0, 0.0}, glm::dvec3{-1.0, 1.0, 0.0}}) {
        const auto found = one_light_rig(direction);
        ASSERT_EQ(found->lights.size(), 1u);
        EXPECT_LT(std::acos(glm::dot(found->lights[0].direction, glm::normalize(direction))),
                  std::numbers::pi / 512)
            << "light found off its disc";
        // Exactly on the pole and the seam: the mean of the disc's pixel directions leaves about
        // 1e-17 of the other axes, which would hide a light view whose up vector is parallel to
        // it (a mutation tried: with +Y as the up vector for every light, the exact pole fails).
        Rig exact = *found;
        exact.lights[0].direction = glm::normalize(direction);
        const auto rig = std::make_shared<const Rig>(std::move(exact));
        char label[48];
        std::snprintf(label, sizeof label, "light towards %.1f,%.1f,%.1f", direction.x, direction.y,
                      direction.z);
        expect_shadows_in_place(render, rig, boxes, low_front, label, 500, 500);
    }
}

TEST_F(FrameRendererTest, ATinySunAtExtremeRadianceStaysFiniteAndWhite) {
    // A sun of a few map pixels 1e6 times a sky of 0.1 (1e5: above the largest half float,
    // 65504, the format anti-aliased display frames keep their samples in), and one at the
    // largest float (what a repaired +Inf becomes), in view beside a white sphere (18 degrees
    // off the view axis, clear of the sphere's 16.6): with and without anti-aliasing, linear and
    // display output. Linear radiance stays finite (a plain sum of four samples of the largest
    // float was +Inf: 18 values, before the resolve averaged by fractions); on display, two stops
    // up, the sun is white and no pixel is black where the linear frame is not (a NaN that the
    // 8-bit conversion turned to 0: 6 pixels before the display transform capped its input).
    const glm::dvec3 sun_direction = glm::normalize(glm::dvec3(0.25, 0.2, -1.0));
    for (const float sun : {1e5f, std::numeric_limits<float>::max()}) {
        const auto map = std::make_shared<const HdrImage>(oer::testing::disc_map(
            1024, 512, glm::vec3(0.1f), {{sun_direction, 0.006, glm::vec3(sun)}}));
        // The automatic window: without one, the order-3 irradiance of a sun 30 times the sky's
        // rings below zero on the sphere's far side, a true black.
        RigOptions options;
        options.light_count = 1;
        options.sh_order = 3;
        options.window = WindowChoice::Auto;
        const auto rig = std::make_shared<const Rig>(build_rig(*map, {}, options));
        ASSERT_EQ(rig->lights.size(), 1u);
        FrameRequest request = sphere_request(rig, front_camera());
        request.environment_map = map;
        request.background.kind = BackgroundKind::Environment;
        const Camera& camera = *request.camera;
        // The sun's pixel: the camera ray through it is the sun's direction (pixel_ray inverted).
        const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target - camera.eye));
        const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
        const glm::dvec3 up = glm::cross(right, forward);
        const double t = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
        const double along = glm::dot(sun_direction, forward);
        const int sun_x = int(
            std::floor((glm::dot(sun_direction, right) / along / t + 1.0) / 2.0 * request.width));
        const int sun_y =
            int(std::floor((1.0 - glm::dot(sun_direction, up) / along / t) / 2.0 * request.height));
        ASSERT_TRUE(sun_x > 0 && sun_x < request.width - 1 && sun_y > 0 &&
                    sun_y < request.height - 1);
        for (const int samples : {1, 4}) {
            request.samples = samples;
            request.linear = true;
            const Frame linear = render(request);
            const std::size_t non_finite =
                std::size_t(std::count_if(linear.linear.begin(), linear.linear.end(),
                                          [](float v) { return !std::isfinite(v); }));
            EXPECT_EQ(non_finite, 0u) << "sun " << sun << ", " << samples << " samples";
            // Two stops up: the largest float becomes +Inf before the tone map.
            request.linear = false;
            request.exposure = 2.0;
            const Frame display = render(request);
            // Against a sun at the largest float the sky's light on the sphere is 1e-35 of the
            // sun's, below float rounding: there only the background is checked.
            int black = 0;
            for (int y = 0; y < display.height; ++y) {
                for (int x = 0; x < display.width; ++x) {
                    if (sun > 1e30f &&
                        hit_sphere(glm::dvec3(camera.eye),
                                   pixel_ray(camera, display.width, display.height, x, y),
                                   {0, 0, 0}, 1.0)) {
                        continue;
                    }
                    const std::uint8_t* p =
                        &display.display.pixels[(std::size_t(y) * display.width + x) * 4];
                    // Black on display though the linear frame's display transform is not: a
                    // NaN of the display path. (A pixel that the CPU's transform also puts
                    // below one display step is no NaN: the order-3 sun's truncated lobe,
                    // subtracted where the shadow test says the sun is hidden, can leave the
                    // sphere's terminator near 1e-3, which Khronos PBR Neutral's black offset
                    // maps to 6.25 x^2.)
                    const float* q = &linear.linear[(std::size_t(y) * linear.width + x) * 4];
                    const glm::dvec3 expected =
                        display_color(glm::dvec4(q[0], q[1], q[2], q[3]), request);
                    const bool lit = std::max({expected.r, expected.g, expected.b}) * 255.0 > 1.5;
                    black += lit && p[0] == 0 && p[1] == 0 && p[2] == 0;
                }
            }
            EXPECT_EQ(black, 0) << "sun " << sun << ", " << samples << " samples";
            // The brightest display pixel around the sun's is white.
            int brightest = 0;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::uint8_t* p =
                        &display.display
                             .pixels[(std::size_t(sun_y + dy) * display.width + (sun_x + dx)) * 4];
                    brightest = std::max(brightest, std::min({int(p[0]), int(p[1]), int(p[2])}));
                }
            }
            EXPECT_EQ(brightest, 255) << "sun " << sun << ", " << samples << " samples";
        }
    }
}

TEST_F(FrameRendererTest, ALightBelowTheHorizonLightsTheBoxButNotTheGround) {
    // A light 5 degrees below the horizon (azimuth 30 degrees), a box on the ground: the ground's
    // top faces away from it (cos = -0.087), so its irradiance from the light is 0 and the light
    // can cast no shadow on it; the order-3 SH of the light still has a lobe there (the clamped
    // cosine's truncation, about 5 % of its facing irradiance), which the ground, whose own
    // plane hides the light, must not show. The box's faces towards the light are lit (the
    // ground is a shadow catcher, not in the shadow maps) and keep all of the light (no
    // self-shadowing). Checked on the light's own contribution: the frame with the light on
    // less the frame with its weight 0, with and without shadows; no NaN or Inf anywhere.
    const std::vector<Box> boxes = {{{-0.3, 0.0, -0.3}, {0.3, 0.5, 0.3}}};
    const double e = glm::radians(-5.0), azimuth = glm::radians(30.0);
    const glm::dvec3 direction{std::cos(e) * std::cos(azimuth), std::sin(e),
                               std::cos(e) * std::sin(azimuth)};
    const auto rig = one_light_rig(direction);
    ASSERT_EQ(rig->lights.size(), 1u);
    ASSERT_LT(rig->lights[0].direction.y, -0.08);
    Camera camera;
    camera.eye = {2.5f, 1.8f, 1.5f};
    camera.target = {0.0f, 0.2f, 0.0f};
    camera.fov_y = 45.0f;
    FrameRequest request = box_on_ground_request(rig, boxes[0].low, boxes[0].high, camera, 256);
    const auto [shadowed, unshadowed, off] = light_contribution_frames(render, request);
    for (const Frame* frame : {&shadowed, &unshadowed, &off}) {
        EXPECT_TRUE(std::all_of(frame->linear.begin(), frame->linear.end(),
                                [](float v) { return std::isfinite(v); }));
    }
    const ShRgb light_irradiance = irradiance_coefficients(rig->sh.per_light[0], rig->window);
    // What the ground would show of the light's SH lobe (0.8 / pi E_k(+Y)), against which the
    // ground's measured change is judged.
    const double lobe = 0.8 / std::numbers::pi * light_irradiance.evaluate({0, 1, 0}).g;
    const glm::dvec3 eye(camera.eye);
    int ground_pixels = 0, face_pixels = 0;
    double ground_change = 0.0, face_loss = 0.0, least_face_part = HUGE_VAL;
    for (int y = 0; y < request.height; ++y) {
        for (int x = 0; x < request.width; ++x) {
            const glm::dvec3 ray = pixel_ray(camera, request.width, request.height, x, y);
            const glm::dvec3 light_on = linear_rgb(shadowed, x, y),
                             light_off = linear_rgb(off, x, y);
            if (const auto face = box_face_hit(eye, ray, boxes[0])) {
                const double facing = glm::dot(*face, rig->lights[0].direction);
                if (facing < 0.3) {
                    continue;
                }
                // A face towards the light: the light's SH irradiance there, all of it, with
                // shadows as without.
                const double part = 0.5 / std::numbers::pi * light_irradiance.evaluate(*face).g;
                least_face_part = std::min(least_face_part, part);
                face_loss = std::max(face_loss, std::abs((light_on - light_off).g - part) / part);
                face_loss = std::max(face_loss,
                                     std::abs((linear_rgb(unshadowed, x, y) - light_on).g) / part);
                ++face_pixels;
                continue;
            }
            if (ray.y >= 0.0 || linear_alpha(off, x, y) < 1.0f) {
                continue;  // the sky, or beyond the ground's edge
            }
            // Green, as the lobe (the light is white).
            ground_change =
                std::max({ground_change, std::abs((light_on - light_off).g) / lobe,
                          std::abs((linear_rgb(unshadowed, x, y) - light_off).g) / lobe});
            ++ground_pixels;
        }
    }
    std::printf(
        "[ measured ] light 5 degrees below the horizon: SH lobe on the ground %.4g (%.1f %% of "
        "a face's %.4g); over %d ground pixels the light changes the ground by at most %.3g of "
        "the lobe; over %d box pixels facing it the faces keep its part within %.3g\n",
        lobe, 100.0 * lobe / least_face_part, least_face_part, ground_pixels, ground_change,
        face_pixels, face_loss);
    EXPECT_GT(lobe, 0.02 * least_face_part);  // so that a ground lit by the lobe fails below
    EXPECT_GT(ground_pixels, 20000);
    EXPECT_LT(ground_change, 1e-3);
    EXPECT_GT(face_pixels, 2000);
    EXPECT_LT(face_loss, 0.02);
}

TEST_F(FrameRendererTest, SoftShadowsAreSharpAtTheCasterAndSpreadAwayFromIt) {
    // A pole 0.1 wide and 1 tall on the ground under one disc light of 8 degrees' radius at 45
    // degrees from +X: its shadow runs along -X to x = -1. Near the pole's foot the ground sees
    // the pole across far more than the light's disc, an umbra; near the tip (0.8 from the
    // foot, 1.13 along the ray from the pole) the pole hides a strip 0.088 rad wide of the
    // 0.28 rad disc, 0.38 of it: no umbra, the shadow only dims to about 0.62 (percentage-closer
    // soft shadows, the penumbra growing with the blocker's distance). A fixed filter cannot do
    // both: a hard test, or the fixed kernel this replaced (a quarter of the light's tangent,
    // 0.035 here), gives an umbra at the tip too; a kernel the width of the tip's penumbra
    // leaves none at the foot. PCSS averages the blockers' depths, and the pole's lower texels
    // in its search disc are nearer the ground: its penumbra comes out narrower than the
    // geometry's (measured 0.34 at the tip), hence the bound. The light's visibility on the ground
    // is measured as its own contribution there, (shadowed - off) / (unshadowed - off).
    const glm::dvec3 direction = glm::normalize(glm::dvec3(1.0, 1.0, 0.0));
    const auto rig = make_rig(oer::testing::disc_map(1024, 512, glm::vec3(0.05f),
                                                     {{direction, 0.14, {50.0f, 50.0f, 50.0f}}}),
                              1, 3);
    ASSERT_EQ(rig->lights.size(), 1u);
    Camera camera;
    camera.eye = {-0.45f, 3.0f, 0.0f};
    camera.target = {-0.45f, 0.0f, 0.0f};
    camera.up = {-1.0f, 0.0f, 0.0f};
    camera.fov_y = 30.0f;
    FrameRequest request =
        box_on_ground_request(rig, {-0.05, 0.0, -0.05}, {0.05, 1.0, 0.05}, camera, 256);
    request.shadows.filter = ShadowFilter::Pcf;
    request.shadows.resolution = 2048;
    const auto [shadowed, unshadowed, off] = light_contribution_frames(render, request);
    // The least visibility across the shadow (over z) at two distances from the foot.
    const glm::dvec3 eye(camera.eye);
    double foot = 1.0, tip = 1.0;
    int foot_pixels = 0, tip_pixels = 0;
    for (int y = 0; y < request.height; ++y) {
        for (int x = 0; x < request.width; ++x) {
            const glm::dvec3 ray = pixel_ray(camera, request.width, request.height, x, y);
            const glm::dvec3 ground = eye + ray * (-eye.y / ray.y);
            if (std::abs(ground.z) > 0.3) {
                continue;
            }
            const double lit = (linear_rgb(unshadowed, x, y) - linear_rgb(off, x, y)).g;
            const double visibility = (linear_rgb(shadowed, x, y) - linear_rgb(off, x, y)).g / lit;
            if (ground.x > -0.2 && ground.x < -0.12) {
                foot = std::min(foot, visibility);
                ++foot_pixels;
            } else if (ground.x > -0.82 && ground.x < -0.76) {
                tip = std::min(tip, visibility);
                ++tip_pixels;
            }
        }
    }
    std::printf(
        "[ measured ] pole under an 8-degree light: least visibility %.3f near the foot "
        "(%d pixels), %.3f near the tip (%d pixels)\n",
        foot, foot_pixels, tip, tip_pixels);
    EXPECT_GT(foot_pixels, 100);
    EXPECT_GT(tip_pixels, 100);
    EXPECT_LT(foot, 0.1);  // an umbra by the caster
    EXPECT_GT(tip, 0.25);  // none far from it (geometry: 0.62; hard or fixed kernel: 0)
    EXPECT_LT(tip, 0.9);   // but a shadow still
}
