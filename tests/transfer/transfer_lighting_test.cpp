// The per-frame side of the transfer (transfer_lighting.hpp): the residual map and the whole
// lighting a frame applies it to, turned by the yaw, and the dot products per receiver.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/rig.hpp"
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
    const TransferLighting as_captured = transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 5);
    EXPECT_LT(largest_difference(as_captured.whole, rig.sh.all), 1e-12);
    ShRgb sum = as_captured.residual;
    sum += rig.sh.per_light[0];
    sum += rig.sh.per_light[1];
    EXPECT_LT(largest_difference(sum, rig.sh.all), 1e-12);
    // A weight scales its light's pixels in the whole lighting, never the residual.
    const TransferLighting dimmed = transfer_lighting(rig, std::vector<float>{0.0f, 3.0f}, 0.0, 5);
    EXPECT_LT(largest_difference(dimmed.residual, as_captured.residual), 1e-12);
    ShRgb expected = as_captured.residual;
    ShRgb tripled = rig.sh.per_light[1];
    tripled *= 3.0;
    expected += tripled;
    EXPECT_LT(largest_difference(dimmed.whole, expected), 1e-12);
    // Lower orders are the first coefficients.
    const TransferLighting order3 = transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 3);
    EXPECT_LT(largest_difference(order3.residual, as_captured.residual.truncated(3)), 1e-12);
}

TEST(TransferLighting, TheYawTurnsTheLightingIntoTheWorld) {
    const Rig rig = two_light_rig();
    const TransferLighting still = transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 5);
    const TransferLighting turned = transfer_lighting(rig, std::vector<float>{1, 0.5f}, 73.0, 5);
    const TransferLighting still_dimmed =
        transfer_lighting(rig, std::vector<float>{1, 0.5f}, 0.0, 5);
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

TEST(TransferLighting, DirectVectorsTakeTheResidualAndBounceVectorsTheWholeLightingPerChannel) {
    const Rig rig = two_light_rig();
    const TransferLighting lighting = transfer_lighting(rig, std::vector<float>{1, 2}, 0.0, 3);
    TransferPoints points;
    points.count = 2;
    points.direct.assign(2 * 25, 0.0f);
    points.bounce.assign(2 * 3 * 25, 0.0f);
    points.direct[0] = 1.0f;                      // point 0: the residual's coefficient 0
    points.direct[25 + 3] = 2.0f;                 // point 1: twice the residual's coefficient 3
    points.bounce[(1 * 3 + 1) * 25 + 2] = 0.5f;   // point 1, green: half L's coefficient 2
    points.bounce[(0 * 3 + 2) * 25 + 24] = 9.0f;  // beyond order 3: not read
    const std::vector<glm::vec3> e = transferred_irradiance(points, 5, lighting);
    ASSERT_EQ(e.size(), 2u);
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(e[0][c], float(lighting.residual.coefficients[0][c]));
        const double green_bounce = c == 1 ? 0.5 * lighting.whole.coefficients[2][c] : 0.0;
        EXPECT_NEAR(e[1][c], 2.0 * lighting.residual.coefficients[3][c] + green_bounce, 1e-5);
    }
}

TEST(TransferLighting, MismatchedInputsAreRefused) {
    const Rig rig = two_light_rig();
    EXPECT_THROW(transfer_lighting(rig, std::vector<float>{1}, 0.0, 5), Error);
    EXPECT_THROW(transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 6), Error);
    EXPECT_THROW(transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 0), Error);
    const TransferLighting lighting = transfer_lighting(rig, std::vector<float>{1, 1}, 0.0, 5);
    TransferPoints points;
    points.count = 1;
    points.direct.assign(9, 0.0f);  // order 3 vectors for order 5 lighting
    EXPECT_THROW(transferred_irradiance(points, 3, lighting), Error);
    points.direct.assign(24, 0.0f);  // one short
    EXPECT_THROW(transferred_irradiance(points, 5, lighting), Error);
}

}  // namespace
}  // namespace oer
