#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "oer/lighting/equirect.hpp"

using namespace oer;
using std::numbers::pi;

TEST(Equirect, SolidAnglesSumToFourPi) {
    for (auto [w, h] : {std::pair{1, 1}, {2, 1}, {1, 4096}, {7, 3}, {2048, 1024}, {8192, 4096}}) {
        double total = 0.0;
        for (int y = 0; y < h; ++y) {
            total += equirect::pixel_solid_angle(y, w, h) * w;
        }
        EXPECT_NEAR(total / (4.0 * pi), 1.0, 1e-12) << w << "x" << h;
    }
}

TEST(Equirect, ImageCentreLooksAlongPlusXAndQuarterAlongMinusZ) {
    const int w = 400, h = 200;
    const glm::dvec3 centre = equirect::direction_at(w / 2.0, h / 2.0, w, h);
    EXPECT_NEAR(centre.x, 1.0, 1e-12);
    const glm::dvec3 quarter = equirect::direction_at(w / 4.0, h / 2.0, w, h);
    EXPECT_NEAR(quarter.z, -1.0, 1e-12);
    const glm::dvec3 top = equirect::direction_at(0.0, 0.0, w, h);
    EXPECT_NEAR(top.y, 1.0, 1e-12);
    const glm::dvec3 edge = equirect::direction_at(0.0, h / 2.0, w, h);
    EXPECT_NEAR(edge.x, -1.0, 1e-12);
}

TEST(Equirect, PositionInvertsDirection) {
    const int w = 64, h = 32;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::dvec2 p = equirect::position_of(equirect::pixel_direction(x, y, w, h), w, h);
            EXPECT_NEAR(p.x, x + 0.5, 1e-9);
            EXPECT_NEAR(p.y, y + 0.5, 1e-9);
        }
    }
}

TEST(Equirect, GridMatchesPixelDirection) {
    const equirect::Grid grid(33, 17);
    for (int y = 0; y < 17; ++y) {
        for (int x = 0; x < 33; ++x) {
            const glm::dvec3 a = grid.direction(x, y);
            const glm::dvec3 b = equirect::pixel_direction(x, y, 33, 17);
            EXPECT_NEAR(glm::length(a - b), 0.0, 1e-14);
        }
    }
}

TEST(Equirect, YawTurnsPlusXTowardsMinusZ) {
    const glm::dvec3 d = equirect::rotate_yaw({1.0, 0.0, 0.0}, 90.0);
    EXPECT_NEAR(d.x, 0.0, 1e-12);
    EXPECT_NEAR(d.z, -1.0, 1e-12);
}
