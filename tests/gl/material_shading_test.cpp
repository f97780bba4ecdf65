// glTF metallic-roughness materials in the GL renderer (issue 12), on this machine's EGL
// (llvmpipe here and in CI), against numbers known without it: a white furnace, where the
// split sum with Fdez-Aguera's multiple scattering gives back the map's radiance exactly; a
// mirror, which shows the light where reflection puts it and as bright as it is, and loses it
// with the light's weight or in the light's shadow; highlights that widen and dim with
// roughness; the Lambertian path unchanged; alpha masks, blending and normal maps against the
// geometry they stand for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "frame_test_support.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/split_sum.hpp"
#include "oer/lighting/tonemap.hpp"
#include "prefiltered_cubes.hpp"
#include "synthetic_maps.hpp"
#include "test_meshes.hpp"

using namespace oer;
using oer::testing::hit_sphere;
using oer::testing::hits_box;
using oer::testing::linear_alpha;
using oer::testing::linear_rgb;
using oer::testing::make_rig;
using oer::testing::pixel_ray;

namespace {

constexpr double kPi = std::numbers::pi;

class MaterialShadingTest : public oer::testing::RendererSuite {};

Camera front_camera() {
    Camera camera;
    camera.eye = {0.0f, 0.0f, 3.5f};
    camera.fov_y = 40.0f;
    return camera;
}

std::shared_ptr<const Mesh> shared(Mesh mesh) {
    return std::make_shared<const Mesh>(std::move(mesh));
}

// A unit sphere at the origin with one material.
std::shared_ptr<const Mesh> sphere_of(const Material& material) {
    Mesh mesh = oer::testing::uv_sphere({0, 0, 0}, 1.0f, 256, 128, glm::vec3(1.0f));
    mesh.materials[0] = material;
    return shared(std::move(mesh));
}

FrameRequest linear_request(std::shared_ptr<const Rig> rig, const Camera& camera, int size) {
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

// The unit sphere's normal seen through pixel (x, y), or nothing for pixels that miss it or
// lie within about a pixel of its silhouette.
std::optional<glm::dvec3> sphere_normal(const Camera& camera, int size, int x, int y,
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

// One small bright disc light over a dim constant sky: the map of the specular tests.
struct SmallLight {
    glm::dvec3 direction;
    double radius = 0.1;       // radians
    float radiance = 100.0f;   // the disc's
    float background = 0.05f;  // the sky's
};

HdrImage small_light_map(const SmallLight& light) {
    return oer::testing::disc_map(1024, 512, glm::vec3(light.background),
                                  {{light.direction, light.radius, glm::vec3(light.radiance)}});
}

}  // namespace

// Under a constant map every direction brings the same radiance L: a white material keeps it
// all, by the split sum's construction (FssEss + Fms Ems = Ess + (1 - Ess) = 1 for a white
// metal; FssEss + Fms Ems + c_diff (1 - FssEss - Fms Ems) = 1 for a white dielectric), so the
// bound is float rounding and the half-float cube (L in halves is exact here), not the DFG
// table's interpolation: 3 % is the bound, the measurement is far inside it.
TEST_F(MaterialShadingTest, AWhiteFurnaceKeepsItsEnergyAtEveryRoughness) {
    const glm::vec3 radiance{0.5f, 1.0f, 2.0f};
    const auto rig = make_rig(oer::testing::constant_map(256, 128, radiance), 0, 3);
    ASSERT_TRUE(rig->lights.empty());
    const Camera camera = front_camera();
    for (const float metallic : {0.0f, 1.0f}) {
        for (const float roughness : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
            FrameRequest request = linear_request(rig, camera, 96);
            request.objects.push_back(
                {sphere_of(oer::testing::metallic_roughness(glm::vec3(1.0f), metallic, roughness)),
                 glm::mat4(1.0f), std::nullopt});
            request.specular = oer::testing::constant_cube(radiance);
            const Frame frame = render(request);
            glm::dvec3 sum(0.0);
            double worst = 0.0;
            int pixels = 0;
            for (int y = 0; y < 96; ++y) {
                for (int x = 0; x < 96; ++x) {
                    if (!sphere_normal(camera, 96, x, y)) {
                        continue;
                    }
                    const glm::dvec3 got = linear_rgb(frame, x, y);
                    sum += got;
                    worst = std::max(worst, std::abs(got.g / radiance.g - 1.0));
                    ++pixels;
                }
            }
            ASSERT_GT(pixels, 2000);
            const glm::dvec3 mean = sum / double(pixels);
            std::printf(
                "[ measured ] furnace, metallic %.0f roughness %.2f: mean / L %.5f %.5f "
                "%.5f, worst pixel %.5f off\n",
                metallic, roughness, mean.r / radiance.r, mean.g / radiance.g, mean.b / radiance.b,
                worst);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(mean[c], radiance[c], 0.03 * radiance[c])
                    << "metallic " << metallic << " roughness " << roughness;
            }
        }
    }
}

namespace {

// The frames of a white metal mirror sphere (roughness 0) under one small light: as asked,
// without shadows, and with the light's weight at 0.
struct MirrorFrames {
    Frame lit, unshadowed, off;
};

struct Pixel {
    int x = -1, y = -1;
};

// The sphere pixel whose reflected view ray points nearest to direction.
Pixel reflection_towards(const Camera& camera, int size, glm::dvec3 direction) {
    Pixel best;
    double best_cosine = -2.0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const auto n = sphere_normal(camera, size, x, y);
            if (!n) {
                continue;
            }
            const glm::dvec3 ray = pixel_ray(camera, size, size, x, y);
            const double cosine = glm::dot(glm::reflect(ray, *n), direction);
            if (cosine > best_cosine) {
                best_cosine = cosine;
                best = {x, y};
            }
        }
    }
    return best;
}

Pixel brightest(const Frame& frame) {
    Pixel best;
    double peak = -1.0;
    for (int y = 0; y < frame.height; ++y) {
        for (int x = 0; x < frame.width; ++x) {
            if (linear_rgb(frame, x, y).g > peak) {
                peak = linear_rgb(frame, x, y).g;
                best = {x, y};
            }
        }
    }
    return best;
}

}  // namespace

// A mirror shows the light where reflection puts it, as bright as the light (its radiance times
// F0 = 1, the split sum's A + B being 1 for a mirror); the light's weight at 0 takes exactly
// that highlight away and nothing else (a metal has no diffuse), and a blocker between the
// light and part of the highlight takes it away where the shadow map hides the light.
TEST_F(MaterialShadingTest, AMirrorReflectsTheLightWhereItIsAndLosesItWithTheLight) {
    const SmallLight light{glm::normalize(glm::dvec3(0.35, 0.6, 1.0))};
    const auto rig = make_rig(small_light_map(light), 1, 3);
    ASSERT_EQ(rig->lights.size(), 1u);
    const glm::dvec3 l = rig->lights[0].direction;
    const Camera camera = front_camera();
    const int size = 256;
    const Pixel predicted = reflection_towards(camera, size, l);
    const glm::dvec3 eye(camera.eye);
    const glm::dvec3 predicted_ray = pixel_ray(camera, size, size, predicted.x, predicted.y);
    const glm::dvec3 highlight_point =
        eye + *hit_sphere(eye, predicted_ray, {0, 0, 0}, 1.0) * predicted_ray;
    // A thin plate above the sphere, across half of the highlight's rays towards the light: its
    // edge, at x = q.x, splits them.
    const glm::dvec3 q = highlight_point + 1.2 * l + glm::dvec3(0.01, 0.0, 0.0);
    const glm::dvec3 plate_low(q.x, q.y - 0.02, q.z - 0.6),
        plate_high(q.x + 0.8, q.y + 0.02, q.z + 0.6);

    FrameRequest request = linear_request(rig, camera, size);
    request.objects.push_back(
        {sphere_of(oer::testing::metallic_roughness(glm::vec3(1.0f), 1.0f, 0.0f)), glm::mat4(1.0f),
         std::nullopt});
    // The residual map: the sky, where the light's pixels are not.
    request.specular = oer::testing::constant_cube(glm::vec3(light.background));
    request.shadows.filter = ShadowFilter::Hard;
    request.shadows.resolution = 4096;
    const Frame lit = render(request);
    request.lights = {0.0f};
    const Frame off = render(request);
    request.lights = {};
    request.objects.push_back(
        {shared(oer::testing::box(glm::vec3(plate_low), glm::vec3(plate_high), glm::vec3(0.5f))),
         glm::mat4(1.0f), std::nullopt});
    const Frame blocked = render(request);
    request.shadows.enabled = false;
    const Frame unblocked = render(request);

    // Where and how bright.
    const Pixel peak = brightest(lit);
    const double peak_radiance = linear_rgb(lit, peak.x, peak.y).g;
    std::printf(
        "[ measured ] mirror: highlight at (%d, %d), reflection predicts (%d, %d); peak "
        "%.2f for a light of radiance %.0f\n",
        peak.x, peak.y, predicted.x, predicted.y, peak_radiance, light.radiance);
    EXPECT_LE(std::hypot(peak.x - predicted.x, peak.y - predicted.y), 2.0);
    EXPECT_NEAR(peak_radiance, light.radiance, 0.1 * light.radiance);

    // The light switched off: its highlight gone, the rest of the sphere unchanged.
    const Pixel off_peak = brightest(off);
    EXPECT_LT(linear_rgb(off, off_peak.x, off_peak.y).g, 0.01 * peak_radiance);
    int rest = 0;
    double worst_rest = 0.0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const auto n = sphere_normal(camera, size, x, y);
            if (!n) {
                continue;
            }
            const glm::dvec3 ray = pixel_ray(camera, size, size, x, y);
            if (glm::dot(glm::reflect(ray, *n), l) > std::cos(0.5)) {
                continue;
            }
            const double on_value = linear_rgb(lit, x, y).g, off_value = linear_rgb(off, x, y).g;
            worst_rest = std::max(worst_rest, std::abs(on_value / off_value - 1.0));
            ++rest;
        }
    }
    std::printf(
        "[ measured ] light off: peak %.4f; %d pixels away from the highlight differ by "
        "at most %.5f\n",
        linear_rgb(off, off_peak.x, off_peak.y).g, rest, worst_rest);
    EXPECT_GT(rest, 20000);
    EXPECT_LT(worst_rest, 0.01);

    // The plate's shadow: each highlight pixel predicted in it by ray casting (away from the
    // predicted edge) loses its highlight, each predicted lit keeps it.
    std::vector<int> shadowed(std::size_t(size * size), -1);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const auto n = sphere_normal(camera, size, x, y);
            const double highlight = linear_rgb(unblocked, x, y).g - linear_rgb(off, x, y).g;
            if (n && highlight > 0.1 * (peak_radiance - light.background)) {
                shadowed[std::size_t(y * size + x)] =
                    hits_box(*n + 1e-6 * *n, l, plate_low, plate_high);
            }
        }
    }
    int in_shadow = 0, in_light = 0, wrong = 0;
    for (int y = 2; y < size - 2; ++y) {
        for (int x = 2; x < size - 2; ++x) {
            const int s = shadowed[std::size_t(y * size + x)];
            if (s < 0) {
                continue;
            }
            bool near_edge = false;
            for (int dy = -2; dy <= 2; ++dy) {
                for (int dx = -2; dx <= 2; ++dx) {
                    near_edge =
                        near_edge || shadowed[std::size_t((y + dy) * size + x + dx)] == 1 - s;
                }
            }
            if (near_edge) {
                continue;
            }
            const double before = linear_rgb(unblocked, x, y).g - linear_rgb(off, x, y).g;
            const double after = linear_rgb(blocked, x, y).g - linear_rgb(off, x, y).g;
            if (s == 1) {
                ++in_shadow;
                wrong += after > 0.02 * before;
            } else {
                ++in_light;
                wrong += after < 0.98 * before;
            }
        }
    }
    std::printf(
        "[ measured ] blocker: %d highlight pixels in its shadow, %d in the light, %d "
        "not as predicted\n",
        in_shadow, in_light, wrong);
    EXPECT_GT(in_shadow, 20);
    EXPECT_GT(in_light, 20);
    EXPECT_EQ(wrong, 0);
}
