// The per-frame side of the transfer (transfer_lighting.hpp): the residual map and the whole
// lighting a frame applies it to, turned by the yaw, and the dot products per receiver.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "oer/transfer/transfer_lighting.hpp"
#include "synthetic_maps.hpp"

namespace oer {
namespace {

Rig two_light_rig() {
    HdrImage map = oer::testing::disc_map(256, 128, glm::vec3(0.0f),
                                          {{{1.0, 1.0, 0.2}, 0.08, {300.0f, 200.0f, 100.0f}},
                                           {{-0.7, 0.4, 0.9}, 0.08, {50.0f, 150.0f, 250.0f}}});
    const equirect::Grid grid(map.width, map.height);
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        const glm::dvec3 d = grid.direction(i);
        map.set(i, map.rgb(i) + glm::vec3(float(0.4 + 0.3 * d.x), 0.3f, float(0.2 + 0.1 * d.z)));
    }
    RigOptions options;
    options.light_count = 2;
    options.sh_order = 5;
    return build_rig(map, {}, options);
}

double largest_difference(const ShRgb& a, const ShRgb& b) {
    double largest = 0.0;
    for (std::size_t i = 0; i < a.coefficients.size(); ++i) {
        largest = std::max(largest, glm::length(a.coefficients[i] - b.coefficients[i]));
    }
    return largest;
}

TEST(TransferLighting, TheResidualAndTheWholeLightingSplitTheRigByItsLights) {
    const Rig rig = two_light_rig();
    ASSERT_EQ(rig.lights.size(), 2u);
    EXPECT_EQ(transfer_order(rig), 5);
    const TransferLighting as_captured =
        transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 5, false, Bounce::None);
    EXPECT_LT(largest_difference(as_captured.whole, rig.sh.all), 1e-12);
    ShRgb sum = as_captured.residual;
    sum += rig.sh.per_light[0];
    sum += rig.sh.per_light[1];
    EXPECT_LT(largest_difference(sum, rig.sh.all), 1e-12);
    // A weight scales its light's pixels in the whole lighting, never the residual.
    const TransferLighting dimmed =
        transfer_lighting(rig, std::vector<float>{0.0f, 3.0f}, 0.0, 5, false, Bounce::None);
    EXPECT_LT(largest_difference(dimmed.residual, as_captured.residual), 1e-12);
    ShRgb expected = as_captured.residual;
    ShRgb tripled = rig.sh.per_light[1];
    tripled *= 3.0;
    expected += tripled;
    EXPECT_LT(largest_difference(dimmed.whole, expected), 1e-12);
    // Lower orders are the first coefficients.
    const TransferLighting order3 =
        transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 3, false, Bounce::None);
    EXPECT_LT(largest_difference(order3.residual, as_captured.residual.truncated(3)), 1e-12);
}

TEST(TransferLighting, TheYawTurnsTheLightingIntoTheWorld) {
    const Rig rig = two_light_rig();
    const TransferLighting still =
        transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 5, false, Bounce::None);
    const TransferLighting turned =
        transfer_lighting(rig, std::vector<float>{1, 0.5f}, 73.0, 5, false, Bounce::None);
    const TransferLighting still_dimmed =
        transfer_lighting(rig, std::vector<float>{1, 0.5f}, 0.0, 5, false, Bounce::None);
    for (const glm::dvec3& d : {glm::dvec3(1, 0, 0), glm::normalize(glm::dvec3(0.3, 0.8, -0.5)),
                                glm::normalize(glm::dvec3(-0.6, -0.2, 0.7))}) {
        const glm::dvec3 world = equirect::rotate_yaw(d, 73.0);
        EXPECT_LT(glm::length(turned.residual.evaluate(world) - still.residual.evaluate(d)), 1e-9);
        EXPECT_LT(glm::length(turned.whole.evaluate(world) - still_dimmed.whole.evaluate(d)), 1e-9);
    }
    // And it does turn: the residual is not symmetric about +Y.
    EXPECT_GT(glm::length(turned.residual.evaluate({1, 0, 0}) - still.residual.evaluate({1, 0, 0})),
              0.05);
}

TEST(TransferLighting,
     DirectVectorsTakeTheResidualAndEachReflectorSlotTheWholeLightingByItsAlbedo) {
    const Rig rig = two_light_rig();
    const TransferLighting lighting =
        transfer_lighting(rig, std::vector<float>{1, 2}, 0.0, 3, false, Bounce::None);
    TransferPoints points;
    points.count = 2;
    points.direct.assign(2 * 25, 0.0f);
    points.bounce.assign(2 * 3 * 25, 0.0f);       // three slots
    points.direct[0] = 1.0f;                      // point 0: the residual's coefficient 0
    points.direct[25 + 3] = 2.0f;                 // point 1: twice the residual's coefficient 3
    points.bounce[(1 * 3 + 1) * 25 + 2] = 0.5f;   // point 1, slot 1: half L's coefficient 2
    points.bounce[(1 * 3 + 2) * 25 + 0] = 7.0f;   // point 1, slot 2: of albedo 0, not read
    points.bounce[(0 * 3 + 0) * 25 + 24] = 9.0f;  // beyond order 3: not read
    const std::vector<glm::vec3> albedos{glm::vec3(0.3f), glm::vec3(0.2f, 0.6f, 1.0f),
                                         glm::vec3(0.0f)};
    const std::vector<glm::vec3> e = transferred_irradiance(points, 5, lighting, albedos);
    ASSERT_EQ(e.size(), 2u);
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(e[0][c], float(lighting.residual.coefficients[0][c]));
        const double bounce = albedos[1][c] * 0.5 * lighting.whole.coefficients[2][c];
        EXPECT_NEAR(e[1][c], 2.0 * lighting.residual.coefficients[3][c] + bounce, 1e-5);
    }
}

TEST(TransferLighting, TheIndicatorBelowTheHorizonIsTheProjectionOfAHalfBrightMap) {
    HdrImage half(512, 256);
    const equirect::Grid grid(half.width, half.height);
    for (std::size_t i = 0; i < half.pixel_count(); ++i) {
        half.set(i, glm::vec3(grid.direction(i).y < 0.0 ? 1.0f : 0.0f));
    }
    const ShRgb projected = project_environment(half, {}, 5).all;
    const ShRgb indicator = below_horizon_indicator(5);
    // The projection's rows are point samples in theta: O(1 / height^2) from the integral.
    EXPECT_LT(largest_difference(projected, indicator), 2e-4);
    EXPECT_NEAR(indicator.coefficients[0].r, std::sqrt(std::numbers::pi), 1e-12);
}

// With the ground, a point above it sees the map above the horizon and the ground below: the
// ground reflects the light from above under Bounce::One, nothing under Bounce::None.
TEST(TransferLighting, WithTheGroundTheMapBelowTheHorizonIsTheGroundsRadiance) {
    const Rig rig = two_light_rig();
    ASSERT_GT(rig.lights[0].direction.y, 0.0);
    ASSERT_GT(rig.lights[1].direction.y, 0.0);
    const std::vector<float> weights{1.0f, 0.5f};
    const TransferLighting dark = transfer_lighting(rig, weights, 0.0, 5, true, Bounce::None);
    EXPECT_LT(largest_difference(dark.residual, residual_above_horizon(rig.sh, 5)), 1e-12);
    ShRgb above = residual_above_horizon(rig.sh, 5);
    ShRgb half_light = rig.sh.per_light[1];
    half_light *= 0.5;
    above += rig.sh.per_light[0];
    above += half_light;
    EXPECT_LT(largest_difference(dark.whole, above), 1e-12);
    const TransferLighting lit = transfer_lighting(rig, weights, 0.0, 5, true, Bounce::One);
    const glm::dvec3 ground_radiance =
        irradiance_coefficients(above).evaluate({0, 1, 0}) * (0.8 / std::numbers::pi);
    ASSERT_GT(ground_radiance.g, 0.1);
    // Below the horizon the lighting gains the ground's radiance, as far as order 5 can say it.
    ShRgb expected = below_horizon_indicator(5);
    for (glm::dvec3& c : expected.coefficients) {
        c *= ground_radiance;
    }
    ShRgb gained = lit.residual;
    gained -= dark.residual;
    EXPECT_LT(largest_difference(gained, expected), 1e-6);
    gained = lit.whole;
    gained -= dark.whole;
    EXPECT_LT(largest_difference(gained, expected), 1e-6);
}

TEST(TransferLighting, MismatchedInputsAreRefused) {
    const Rig rig = two_light_rig();
    EXPECT_THROW(transfer_lighting(rig, std::vector<float>{1}, 0.0, 5, false, Bounce::None), Error);
    EXPECT_THROW(transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 6, false, Bounce::None),
                 Error);
    EXPECT_THROW(transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 0, false, Bounce::None),
                 Error);
    const TransferLighting lighting =
        transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 5, false, Bounce::None);
    TransferPoints points;
    points.count = 1;
    points.direct.assign(9, 0.0f);  // order 3 vectors for order 5 lighting
    EXPECT_THROW(transferred_irradiance(points, 3, lighting, {}), Error);
    points.direct.assign(24, 0.0f);  // one short
    EXPECT_THROW(transferred_irradiance(points, 5, lighting, {}), Error);
    points.direct.assign(25, 0.0f);
    points.bounce.assign(2 * 25, 0.0f);  // two slots' vectors for three albedos
    EXPECT_THROW(transferred_irradiance(points, 5, lighting, std::vector<glm::vec3>(3)), Error);
    EXPECT_NO_THROW(transferred_irradiance(points, 5, lighting, std::vector<glm::vec3>(2)));
}

}  // namespace
}  // namespace oer
