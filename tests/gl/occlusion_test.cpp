// The renderer's side of the occlusion of the residual map: a frame lit through a transfer
// (FrameRequest::occlusion) against frames lit the old way, with hand-made transfers whose
// answer is known. An unoccluded transfer, A_l Y_i(n) at every receiver, must give back the
// frame without occlusion; a zero transfer must take exactly the residual map's irradiance off;
// a light below the ground's horizon must reach no object. The bake itself is tested in
// tests/transfer, and baked frames against the reference renderer in occlusion_reference_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include "frame_test_support.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "oer/transfer/transfer_lighting.hpp"
#include "synthetic_maps.hpp"
#include "test_meshes.hpp"

namespace oer {
namespace {

using oer::testing::linear_alpha;
using oer::testing::linear_rgb;

// Three disc lights over a background that varies with direction, so that the residual map is
// not symmetric about +Y and the yaw's rotation of it shows. Lights above the horizon unless
// below_horizon.
HdrImage lit_map(bool below_horizon) {
    std::vector<oer::testing::DiscLight> discs{{{1.0, 1.2, 0.0}, 0.06, {400.0f, 380.0f, 350.0f}},
                                               {{-0.6, 1.2, 0.8}, 0.06, {200.0f, 260.0f, 400.0f}}};
    discs.push_back(below_horizon
                        ? oer::testing::DiscLight{{0.3, -1.0, 0.6}, 0.06, {300, 250, 200}}
                        : oer::testing::DiscLight{{-0.5, 1.0, -0.9}, 0.06, {300, 250, 200}});
    HdrImage map = oer::testing::disc_map(256, 128, glm::vec3(0.0f), discs);
    const equirect::Grid grid(map.width, map.height);
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        const glm::dvec3 d = grid.direction(i);
        const glm::vec3 background(float(0.3 + 0.2 * d.x), float(0.25 + 0.15 * d.z),
                                   float(0.2 + 0.1 * d.y));
        map.set(i, map.rgb(i) + background);
    }
    return map;
}

std::shared_ptr<const Rig> lit_rig(bool below_horizon) {
    RigOptions options;
    options.light_count = 3;
    options.sh_order = 5;
    options.window = WindowChoice::None;
    return std::make_shared<const Rig>(build_rig(lit_map(below_horizon), {}, options));
}

// The transfer of a scene where nothing occludes and nothing reflects: A_l Y_i(n) at every
// receiver, so that T . R is plain SH irradiance. `scale` multiplies it (0: no residual light).
std::vector<float> cosine_transfer(const glm::dvec3& normal, float scale) {
    std::array<double, kTransferBakeOrder * kTransferBakeOrder> basis{};
    sh_evaluate(kTransferBakeOrder, normal, basis);
    std::vector<float> vector(basis.size());
    for (int l = 0; l < kTransferBakeOrder; ++l) {
        for (int m = -l; m <= l; ++m) {
            const int i = sh_index(l, m);
            vector[std::size_t(i)] =
                scale * float(lambertian_band_factor(l) * basis[std::size_t(i)]);
        }
    }
    return vector;
}

std::shared_ptr<const SceneTransfer> cosine_scene_transfer(const FrameRequest& request,
                                                           float object_scale, float ground_scale,
                                                           Bounce bounce = Bounce::None) {
    auto transfer = std::make_shared<SceneTransfer>();
    transfer->bounce = bounce;
    if (bounce == Bounce::One) {
        transfer->reflectors = reflector_slots(request);
    }
    // Under Bounce::One, nothing reflected: zero bounce vectors.
    const auto reflect_nothing = [&](TransferPoints& points) {
        points.bounce.assign(points.count * bounce_vectors(transfer->reflectors) *
                                 kTransferBakeOrder * kTransferBakeOrder,
                             0.0f);
    };
    for (const SceneObject& object : request.objects) {
        const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(object.transform));
        std::vector<TransferPoints>& primitives = transfer->objects.emplace_back();
        for (const Primitive& primitive : object.mesh->primitives) {
            TransferPoints& points = primitives.emplace_back();
            points.count = primitive.positions.size();
            for (const glm::vec3& n : primitive.normals) {
                const std::vector<float> vector =
                    cosine_transfer(glm::normalize(glm::dvec3(normal_matrix * n)), object_scale);
                points.direct.insert(points.direct.end(), vector.begin(), vector.end());
            }
            reflect_nothing(points);
        }
    }
    if (request.ground) {
        const SceneBounds bounds = scene_bounds(request.objects);
        GroundTransfer ground;
        ground.centre = {bounds.centre.x, bounds.centre.z};
        ground.half_size = bounds.ground_half_size();
        ground.height = bounds.box.min.y;
        ground.resolution = 8;
        ground.points.count = 64;
        const std::vector<float> up = cosine_transfer({0.0, 1.0, 0.0}, ground_scale);
        for (int t = 0; t < 64; ++t) {
            ground.points.direct.insert(ground.points.direct.end(), up.begin(), up.end());
        }
        reflect_nothing(ground.points);
        transfer->ground = std::move(ground);
    }
    return transfer;
}

// `request` lit through cosine_scene_transfer's transfer, in `bounce` mode.
FrameRequest with_cosine_transfer(FrameRequest request, float object_scale, float ground_scale,
                                  Bounce bounce = Bounce::None) {
    request.occlusion = true;
    request.bounce = bounce;
    request.transfer = cosine_scene_transfer(request, object_scale, ground_scale, bounce);
    return request;
}

class OcclusionTest : public oer::testing::RendererSuite {
  protected:
    // A white sphere resting on the ground, seen from above the horizon, linear output.
    static FrameRequest sphere_on_ground(std::shared_ptr<const Rig> rig) {
        FrameRequest request;
        request.rig = std::move(rig);
        request.objects.push_back({std::make_shared<const Mesh>(oer::testing::uv_sphere(
                                       {0, 0, 0}, 1.0f, 128, 64, glm::vec3(1.0f))),
                                   glm::mat4(1.0f), std::nullopt});
        Camera camera;
        camera.eye = {0.0f, 1.5f, 4.0f};
        camera.target = {0.0f, -0.3f, 0.0f};
        camera.fov_y = 50.0f;
        request.camera = camera;
        request.width = request.height = 128;
        request.ground = true;
        request.background.kind = BackgroundKind::Transparent;
        request.samples = 1;
        request.linear = true;
        return request;
    }

    // The largest difference between two frames' covered pixels, relative to the brightest.
    static double largest_relative_difference(const Frame& a, const Frame& b) {
        double brightest = 0.0, largest = 0.0;
        for (int y = 0; y < a.height; ++y) {
            for (int x = 0; x < a.width; ++x) {
                if (linear_alpha(a, x, y) == 0.0f) {
                    continue;
                }
                brightest = std::max(brightest, glm::length(linear_rgb(a, x, y)));
                largest = std::max(largest, glm::length(linear_rgb(a, x, y) - linear_rgb(b, x, y)));
            }
        }
        return largest / brightest;
    }
};

// Without the ground (which, as lighting, changes what the object sees below its horizon).
TEST_F(OcclusionTest, AnUnoccludedTransferGivesTheFrameWithoutOcclusion) {
    const auto rig = lit_rig(false);
    ASSERT_EQ(rig->lights.size(), 3u);
    FrameRequest plain = sphere_on_ground(rig);
    plain.ground = false;
    plain.environment_yaw = 30.0;
    plain.lights = {1.0f, 0.5f, 2.0f};
    const Frame expected = render(plain);
    FrameRequest occluded = with_cosine_transfer(plain, 1.0f, 1.0f);
    const Frame frame = render(occluded);
    // Half floats carry the transferred irradiance (2^-11 relative) and it is interpolated
    // between the sphere's vertices: a tenth of a per cent of the brightest pixel.
    EXPECT_LT(largest_relative_difference(expected, frame), 1e-3);
    // The same transfer without the yaw is another frame: the residual's rotation shows.
    occluded.environment_yaw = 0.0;
    EXPECT_GT(largest_relative_difference(expected, render(occluded)), 1e-2);
}

// The ground's (albedo 0.8) radiance from the residual map's irradiance facing up, which a zero
// transfer takes off it (the three lights at weight 1).
glm::dvec3 ground_radiance_of_residual(const Rig& rig) {
    const TransferLighting lighting = transfer_lighting(rig, std::vector<float>(3, 1.0f), 0.0,
                                                        transfer_order(rig), true, Bounce::None);
    return irradiance_coefficients(lighting.residual).evaluate({0.0, 1.0, 0.0}) *
           (0.8 / std::numbers::pi);
}

TEST_F(OcclusionTest, AZeroTransferTakesTheResidualMapsIrradianceOffTheGround) {
    const auto rig = lit_rig(false);
    FrameRequest plain = sphere_on_ground(rig);
    plain.objects[0].base_color = glm::vec3(0.5f);
    const Frame expected = render(plain);
    FrameRequest occluded = with_cosine_transfer(plain, 1.0f, 0.0f);
    const Frame frame = render(occluded);
    // The ground (albedo 0.8) loses albedo / pi E_R(+Y), the residual's irradiance facing up,
    // wherever it is.
    const glm::dvec3 residual_up = ground_radiance_of_residual(*rig);
    ASSERT_GT(residual_up.g, 0.05);
    const SceneBounds bounds = scene_bounds(plain.objects);
    int ground_pixels = 0;
    for (int y = 0; y < frame.height; ++y) {
        for (int x = 0; x < frame.width; ++x) {
            const glm::dvec3 eye(plain.camera->eye);
            const glm::dvec3 ray = oer::testing::pixel_ray(*plain.camera, 128, 128, x, y);
            const double t = (bounds.box.min.y - eye.y) / ray.y;
            // The floor drawn whole (farther out it fades into the background).
            const glm::dvec3 point = eye + t * ray;
            if (ray.y >= 0.0 || oer::testing::hit_sphere(eye, ray, {0, 0, 0}, 1.05) ||
                glm::length(glm::dvec2(point.x - bounds.centre.x, point.z - bounds.centre.z)) >
                    bounds.ground_fade_start()) {
                continue;
            }
            const glm::dvec3 lost = linear_rgb(expected, x, y) - linear_rgb(frame, x, y);
            for (int c = 0; c < 3; ++c) {
                ASSERT_NEAR(lost[c], residual_up[c], 2e-3 * residual_up[c] + 1e-5)
                    << x << "," << y << " channel " << c;
            }
            ++ground_pixels;
        }
    }
    EXPECT_GT(ground_pixels, 3000);
}

TEST_F(OcclusionTest, BeyondTheGroundsGridTheObjectsEffectFallsOffWithTheCubeOfTheDistance) {
    // A zero transfer over a grid of 2 scene radii each side: inside, the ground loses the
    // residual's irradiance whole; outside, at `outside` times the grid's half side (its
    // Chebyshev distance), a 1 / outside^3 share of it, towards the open ground's.
    const auto rig = lit_rig(false);
    FrameRequest plain = sphere_on_ground(rig);
    plain.camera->eye = {0.0f, 9.0f, 0.5f};
    plain.camera->target = {0.0f, 0.0f, 0.0f};
    plain.camera->fov_y = 60.0f;
    const Frame expected = render(plain);
    FrameRequest occluded = with_cosine_transfer(plain, 1.0f, 0.0f);
    auto transfer = std::make_shared<SceneTransfer>(*occluded.transfer);
    const SceneBounds bounds = scene_bounds(plain.objects);
    transfer->ground->half_size = 2.0f * bounds.radius;
    occluded.transfer = transfer;
    const Frame frame = render(occluded);
    const glm::dvec3 residual_up = ground_radiance_of_residual(*rig);
    int inside = 0, outside = 0;
    const glm::dvec3 eye(plain.camera->eye);
    for (int y = 0; y < frame.height; ++y) {
        for (int x = 0; x < frame.width; ++x) {
            const glm::dvec3 ray = oer::testing::pixel_ray(*plain.camera, 128, 128, x, y);
            const glm::dvec3 point = eye + (bounds.box.min.y - eye.y) / ray.y * ray;
            if (ray.y >= 0.0 || oer::testing::hit_sphere(eye, ray, {0, 0, 0}, 1.05) ||
                glm::length(glm::dvec2(point.x - bounds.centre.x, point.z - bounds.centre.z)) >
                    bounds.ground_fade_start()) {
                continue;
            }
            const double chebyshev =
                std::max(std::abs(point.x - bounds.centre.x), std::abs(point.z - bounds.centre.z)) /
                transfer->ground->half_size;
            // A pixel's centre against the texel-filtered edge: away from the grid's border.
            if (std::abs(chebyshev - 1.0) < 0.05) {
                continue;
            }
            const double share = chebyshev < 1.0 ? 1.0 : 1.0 / (chebyshev * chebyshev * chebyshev);
            const glm::dvec3 lost = linear_rgb(expected, x, y) - linear_rgb(frame, x, y);
            ASSERT_NEAR(lost.g, share * residual_up.g, 2e-3 * residual_up.g + 1e-5)
                << x << "," << y << " at " << chebyshev << " half sides";
            ++(chebyshev < 1.0 ? inside : outside);
        }
    }
    EXPECT_GT(inside, 500);
    EXPECT_GT(outside, 2000);
}

TEST_F(OcclusionTest, ALightBelowTheGroundsHorizonReachesNoObject) {
    const auto rig = lit_rig(true);
    ASSERT_EQ(rig->lights.size(), 3u);
    const auto below = std::find_if(rig->lights.begin(), rig->lights.end(),
                                    [](const Light& light) { return light.direction.y < 0.0; });
    ASSERT_NE(below, rig->lights.end());
    const std::size_t k = std::size_t(below - rig->lights.begin());
    FrameRequest plain = sphere_on_ground(rig);
    plain.camera->eye = {0.0f, -0.2f, 4.0f};
    plain.camera->target = {0.0f, -0.2f, 0.0f};
    std::vector<float> without_it(3, 1.0f);
    without_it[k] = 0.0f;
    // Without occlusion the light below lights the sphere's underside through the ground.
    FrameRequest plain_off = plain;
    plain_off.lights = without_it;
    ASSERT_GT(largest_relative_difference(render(plain), render(plain_off)), 0.05);
    // With occlusion and the ground, switching it off changes nothing, in either mode.
    for (const Bounce bounce : {Bounce::None, Bounce::One}) {
        FrameRequest occluded = with_cosine_transfer(plain, 1.0f, 1.0f, bounce);
        FrameRequest occluded_off = occluded;
        occluded_off.lights = without_it;
        EXPECT_LT(largest_relative_difference(render(occluded), render(occluded_off)), 1e-4);
    }
}

// The transferred irradiance does not depend on the camera: an orbit reuses the previous frame's,
// and gets the frame a renderer that never saw the first one draws. Anything the transfer's
// lighting reads (a colour, a light's weight, the yaw) computes it again.
TEST_F(OcclusionTest, AnOrbitReusesTheTransferredIrradianceAndNothingElseDoes) {
    const auto rig = lit_rig(false);
    FrameRequest request = with_cosine_transfer(sphere_on_ground(rig), 0.7f, 0.9f, Bounce::One);
    render(request);
    const std::size_t reuses = transferred_irradiance_reuses();
    request.camera->eye = {1.5f, 1.2f, 3.5f};
    const Frame orbited = render(request);
    EXPECT_EQ(transferred_irradiance_reuses(), reuses + 1);
    const Frame expected = thread_
                               ->submit([&request] {
                                   FrameRenderer fresh;
                                   return fresh.render(request);
                               })
                               .get();
    EXPECT_EQ(orbited.linear, expected.linear);

    FrameRequest changed = request;
    changed.objects[0].base_color = glm::vec3(0.2f, 0.9f, 0.4f);
    render(changed);
    changed = request;
    changed.lights = {1.0f, 0.5f, 1.0f};
    render(changed);
    changed = request;
    changed.environment_yaw = 30.0;
    render(changed);
    EXPECT_EQ(transferred_irradiance_reuses(), reuses + 1);
}

TEST_F(OcclusionTest, ATransferThatDoesNotFitTheSceneIsRefused) {
    const auto rig = lit_rig(false);
    FrameRequest request = sphere_on_ground(rig);
    request.occlusion = true;
    request.bounce = Bounce::None;
    EXPECT_THROW(render(request), Error);  // no transfer
    request.transfer = cosine_scene_transfer(request, 1.0f, 1.0f);
    request.bounce = Bounce::One;
    EXPECT_THROW(render(request), Error);  // baked without the bounce
    request.bounce = Bounce::None;
    FrameRequest other_mesh = request;
    other_mesh.objects[0].mesh = std::make_shared<const Mesh>(
        oer::testing::uv_sphere({0, 0, 0}, 1.0f, 64, 32, glm::vec3(1.0f)));
    EXPECT_THROW(render(other_mesh), Error);
    FrameRequest no_ground = request;
    no_ground.ground = false;
    EXPECT_THROW(render(no_ground), Error);
    // Reflector slots must name the frame's own surfaces.
    FrameRequest bounce = with_cosine_transfer(request, 1.0f, 1.0f, Bounce::One);
    EXPECT_NO_THROW(render(bounce));
    auto other_material = std::make_shared<SceneTransfer>(*bounce.transfer);
    other_material->reflectors.back().material = 1;
    bounce.transfer = other_material;
    EXPECT_THROW(render(bounce), Error);
    FrameRequest no_occlusion = request;
    no_occlusion.occlusion = false;
    EXPECT_THROW(render(no_occlusion), Error);  // a transfer it would not use
    EXPECT_NO_THROW(render(request));
}

}  // namespace
}  // namespace oer
