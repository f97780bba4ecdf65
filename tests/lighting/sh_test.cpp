#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/lighting/sh.hpp"
#include "sh_test_support.hpp"

using namespace oer;
using std::sqrt;
using std::numbers::pi;

namespace {

// Closed forms of bands 0..3 with exact constants (no Condon-Shortley phase), index l(l+1)+m.
std::array<double, 16> closed_forms(const glm::dvec3& d) {
    const double x = d.x, y = d.y, z = d.z;
    return {
        0.5 / sqrt(pi),
        sqrt(3.0 / (4.0 * pi)) * y,
        sqrt(3.0 / (4.0 * pi)) * z,
        sqrt(3.0 / (4.0 * pi)) * x,
        0.5 * sqrt(15.0 / pi) * x * y,
        0.5 * sqrt(15.0 / pi) * y * z,
        0.25 * sqrt(5.0 / pi) * (3.0 * z * z - 1.0),
        0.5 * sqrt(15.0 / pi) * x * z,
        0.25 * sqrt(15.0 / pi) * (x * x - y * y),
        0.25 * sqrt(35.0 / (2.0 * pi)) * y * (3.0 * x * x - y * y),
        0.5 * sqrt(105.0 / pi) * x * y * z,
        0.25 * sqrt(21.0 / (2.0 * pi)) * y * (5.0 * z * z - 1.0),
        0.25 * sqrt(7.0 / pi) * z * (5.0 * z * z - 3.0),
        0.25 * sqrt(21.0 / (2.0 * pi)) * x * (5.0 * z * z - 1.0),
        0.25 * sqrt(105.0 / pi) * z * (x * x - y * y),
        0.25 * sqrt(35.0 / (2.0 * pi)) * x * (x * x - 3.0 * y * y),
    };
}

std::vector<glm::dvec3> test_directions(int random_count) {
    std::vector<glm::dvec3> directions = {
        {0, 0, 1},
        {0, 0, -1},
        {1, 0, 0},
        {-1, 0, 0},
        {0, 1, 0},
        {0, -1, 0},
        glm::normalize(glm::dvec3(1e-9, -2e-9, 1.0)),
        glm::normalize(glm::dvec3(-3e-12, 1e-12, -1.0)),
    };
    std::mt19937 rng(7);
    std::normal_distribution<double> normal;
    for (int i = 0; i < random_count; ++i) {
        directions.push_back(glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng))));
    }
    return directions;
}

}  // namespace

TEST(Sh, RecurrenceMatchesClosedFormsToBand3) {
    std::array<double, 16> values{};
    for (const glm::dvec3& d : test_directions(2000)) {
        sh_evaluate(4, d, values);
        const std::array<double, 16> expected = closed_forms(d);
        for (int i = 0; i < 16; ++i) {
            ASSERT_NEAR(values[i], expected[i], 1e-12)
                << "index " << i << " at " << d.x << ", " << d.y << ", " << d.z;
        }
    }
}

TEST(Sh, ThesisConstantsAndSigns) {
    // The rounded constants of the thesis's appendix A (docs/design.md section 3), all positive.
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, 0.5, 0.7));
    std::array<double, 9> v{};
    sh_evaluate(3, d, v);
    const double x = d.x, y = d.y, z = d.z;
    EXPECT_NEAR(v[0], 0.282095, 1e-6);
    EXPECT_NEAR(v[1], 0.488603 * y, 1e-6);
    EXPECT_NEAR(v[2], 0.488603 * z, 1e-6);
    EXPECT_NEAR(v[3], 0.488603 * x, 1e-6);
    EXPECT_NEAR(v[4], 1.092548 * x * y, 1e-6);
    EXPECT_NEAR(v[5], 1.092548 * y * z, 1e-6);
    EXPECT_NEAR(v[6], 0.315392 * (3 * z * z - 1), 1e-6);
    EXPECT_NEAR(v[7], 1.092548 * x * z, 1e-6);
    EXPECT_NEAR(v[8], 0.546274 * (x * x - y * y), 1e-6);
}

TEST(Sh, OrthonormalUpToMaxOrderByExactQuadrature) {
    // Products of two band <= 15 functions have degree <= 30: Gauss-Legendre in z with 17 points
    // times 40 uniform azimuths integrates them exactly.
    const int order = kMaxShOrder;
    const int count = sh_count(order);
    const test::GaussLegendre rule(17);
    const int n_phi = 40;
    std::vector<double> gram(std::size_t(count) * count, 0.0);
    std::vector<double> y(count);
    for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
        const double z = rule.nodes[i];
        const double s = sqrt(1.0 - z * z);
        for (int j = 0; j < n_phi; ++j) {
            const double phi = 2.0 * pi * (j + 0.25) / n_phi;
            sh_evaluate(order, {s * std::cos(phi), s * std::sin(phi), z}, y);
            const double w = rule.weights[i] * 2.0 * pi / n_phi;
            for (int a = 0; a < count; ++a) {
                for (int b = 0; b <= a; ++b) {
                    gram[std::size_t(a) * count + b] += w * y[a] * y[b];
                }
            }
        }
    }
    double worst = 0.0;
    for (int a = 0; a < count; ++a) {
        for (int b = 0; b <= a; ++b) {
            const double expected = a == b ? 1.0 : 0.0;
            worst = std::max(worst, std::abs(gram[std::size_t(a) * count + b] - expected));
            // Orders up to 8 as the design requires; the rest holds as tightly.
            ASSERT_NEAR(gram[std::size_t(a) * count + b], expected, a < 64 ? 1e-6 : 1e-9)
                << "basis " << a << " x " << b;
        }
    }
    std::printf("orthonormality to order %d: largest deviation %.2e\n", order, worst);
}

TEST(Sh, AdditionTheoremAtHighOrders) {
    // sum_m Y_lm(a) Y_lm(b) = (2l + 1) / (4 pi) P_l(a . b): checks normalisation and rotation
    // invariance of every band, including at and near the poles.
    const std::vector<glm::dvec3> directions = test_directions(60);
    std::vector<double> ya(sh_count(kMaxShOrder)), yb(sh_count(kMaxShOrder));
    for (std::size_t i = 0; i < directions.size(); ++i) {
        const glm::dvec3& a = directions[i];
        const glm::dvec3& b = directions[(i * 7 + 3) % directions.size()];
        sh_evaluate(kMaxShOrder, a, ya);
        sh_evaluate(kMaxShOrder, b, yb);
        for (int l = 0; l < kMaxShOrder; ++l) {
            double sum = 0.0;
            for (int m = -l; m <= l; ++m) {
                sum += ya[sh_index(l, m)] * yb[sh_index(l, m)];
            }
            const double expected =
                (2.0 * l + 1.0) / (4.0 * pi) * test::legendre_p(l, glm::dot(a, b));
            ASSERT_NEAR(sum, expected, 1e-11) << "band " << l << ", pair " << i;
        }
    }
}

TEST(Sh, ZonalAtThePoles) {
    std::vector<double> y(sh_count(kMaxShOrder));
    for (const double z : {1.0, -1.0}) {
        sh_evaluate(kMaxShOrder, {0.0, 0.0, z}, y);
        for (int l = 0; l < kMaxShOrder; ++l) {
            for (int m = -l; m <= l; ++m) {
                const double expected =
                    m == 0 ? std::pow(z, l) * sqrt((2.0 * l + 1.0) / (4.0 * pi)) : 0.0;
                ASSERT_NEAR(y[sh_index(l, m)], expected, 1e-13) << l << ", " << m << " at z " << z;
            }
        }
    }
}

TEST(Sh, RejectsBadArguments) {
    std::vector<double> y(sh_count(kMaxShOrder + 1));
    EXPECT_THROW(sh_evaluate(0, {0, 0, 1}, y), Error);
    EXPECT_THROW(sh_evaluate(kMaxShOrder + 1, {0, 0, 1}, y), Error);
    std::vector<double> short_span(8);
    EXPECT_THROW(sh_evaluate(3, {0, 0, 1}, short_span), Error);
}

TEST(ShRgb, EvaluateIsTheBasisExpansion) {
    ShRgb sh(4);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (glm::dvec3& c : sh.coefficients) {
        c = {uniform(rng), uniform(rng), uniform(rng)};
    }
    for (const glm::dvec3& d : test_directions(50)) {
        const std::array<double, 16> y = closed_forms(d);
        glm::dvec3 expected(0.0);
        for (int i = 0; i < 16; ++i) {
            expected += sh.coefficients[i] * y[i];
        }
        const glm::dvec3 value = sh.evaluate(d);
        EXPECT_NEAR(value.x, expected.x, 1e-12);
        EXPECT_NEAR(value.y, expected.y, 1e-12);
        EXPECT_NEAR(value.z, expected.z, 1e-12);
    }
}

TEST(ShRgb, TruncatedKeepsTheLowBands) {
    ShRgb sh(5);
    for (int i = 0; i < sh_count(5); ++i) {
        sh.coefficients[i] = glm::dvec3(i, 2 * i, -i);
    }
    const ShRgb low = sh.truncated(3);
    ASSERT_EQ(low.order, 3);
    ASSERT_EQ(low.coefficients.size(), 9u);
    for (int i = 0; i < 9; ++i) {
        EXPECT_EQ(low.coefficients[i], glm::dvec3(i, 2 * i, -i));
    }
    EXPECT_THROW(sh.truncated(6), Error);
    EXPECT_THROW(sh.truncated(0), Error);
}

TEST(ShRgb, Arithmetic) {
    ShRgb a(2), b(2);
    for (int i = 0; i < 4; ++i) {
        a.coefficients[i] = glm::dvec3(i + 1.0, 0.5, -2.0);
        b.coefficients[i] = glm::dvec3(0.25, i, 3.0);
    }
    ShRgb sum = a;
    sum += b;
    ShRgb difference = a;
    difference -= b;
    ShRgb scaled = a;
    scaled *= -1.5;
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(sum.coefficients[i], a.coefficients[i] + b.coefficients[i]);
        EXPECT_EQ(difference.coefficients[i], a.coefficients[i] - b.coefficients[i]);
        EXPECT_EQ(scaled.coefficients[i], a.coefficients[i] * -1.5);
    }
    ShRgb other(3);
    EXPECT_THROW(sum += other, Error);
    EXPECT_THROW(sum -= other, Error);
}
