// The shared sampling primitives (oer/lighting/sampling.hpp) against what they must be: the
// radical inverse's exact values and stratification, GGX half vectors distributed as D(h) (n.h)
// with D integrating to 1, and cosine-weighted directions with the moments of density cos / pi.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "oer/lighting/sampling.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

// integral over the hemisphere of D(h) (n.h) with (n.h) in [cos_low, 1], by the midpoint rule in
// mu = n.h (dOmega = 2 pi dmu after the azimuth): the probability that a GGX half vector of
// alpha^2 = alpha2 has n.h >= cos_low.
double ggx_mass_above(double alpha2, double cos_low) {
    constexpr int kCells = 1000000;
    const double width = (1.0 - cos_low) / kCells;
    double sum = 0.0;
    for (int k = 0; k < kCells; ++k) {
        const double mu = cos_low + (k + 0.5) * width;
        sum += sampling::ggx_distribution(alpha2, mu * mu) * mu;
    }
    return 2.0 * pi * sum * width;
}

}  // namespace

TEST(Sampling, RadicalInverseMirrorsTheBinaryDigits) {
    EXPECT_EQ(sampling::radical_inverse(0), 0.0);
    EXPECT_EQ(sampling::radical_inverse(1), 0.5);
    EXPECT_EQ(sampling::radical_inverse(2), 0.25);
    EXPECT_EQ(sampling::radical_inverse(3), 0.75);
    EXPECT_EQ(sampling::radical_inverse(4), 0.125);
    EXPECT_EQ(sampling::radical_inverse(5), 0.625);
    EXPECT_EQ(sampling::radical_inverse(6), 0.375);
    EXPECT_EQ(sampling::radical_inverse(11), 0.8125);  // 1011 -> 0.1101
    EXPECT_EQ(sampling::radical_inverse(0x80000000u), 0x1p-32);
    EXPECT_EQ(sampling::radical_inverse(0xFFFFFFFFu), 1.0 - 0x1p-32);
}

TEST(Sampling, RadicalInverseFillsEveryStratumOfAPowerOfTwoPrefix) {
    // The first 2^m values are exactly the multiples of 2^-m: one point per stratum.
    for (int m : {1, 4, 10}) {
        const std::uint32_t count = 1u << m;
        std::vector<double> values;
        for (std::uint32_t i = 0; i < count; ++i) {
            values.push_back(sampling::radical_inverse(i));
        }
        std::sort(values.begin(), values.end());
        for (std::uint32_t i = 0; i < count; ++i) {
            EXPECT_EQ(values[i], double(i) / count) << "m " << m << ", i " << i;
        }
    }
}

TEST(Sampling, HammersleyPointsPairTheIndexWithItsRadicalInverse) {
    const glm::dvec2 point = sampling::hammersley(3, 8);
    EXPECT_EQ(point.x, 3.0 / 8.0);
    EXPECT_EQ(point.y, 0.75);
    EXPECT_EQ(sampling::hammersley(0, 5), glm::dvec2(0.0, 0.0));
}

TEST(SamplingGgx, TheDistributionTimesCosineIntegratesToOne) {
    for (double alpha : {0.05, 0.2, 0.5, 0.8, 1.0}) {
        EXPECT_NEAR(ggx_mass_above(alpha * alpha, 0.0), 1.0, 1e-6) << "alpha " << alpha;
    }
    // alpha = 1: D = 1 / pi everywhere.
    EXPECT_DOUBLE_EQ(sampling::ggx_distribution(1.0, 0.3), 1.0 / pi);
}

TEST(SamplingGgx, HalfVectorsFollowTheDistribution) {
    // u is the probability mass at smaller polar angles: the mass of D (n.h) above the drawn
    // n.h must be u, whatever alpha.
    for (double alpha : {0.1, 0.4, 0.9}) {
        const double alpha2 = alpha * alpha;
        for (double u : {0.1, 0.25, 0.5, 0.75, 0.95}) {
            const sampling::GgxHalfVector h = sampling::ggx_half_vector(alpha2, u, 1.0);
            EXPECT_NEAR(ggx_mass_above(alpha2, h.direction.z), u, 1e-6)
                << "alpha " << alpha << ", u " << u;
        }
    }
}

TEST(SamplingGgx, HalfVectorsAreUnitWithTheGivenAzimuth) {
    for (double phi : {0.0, 1.0, 2.5, 4.0, 6.0}) {
        const sampling::GgxHalfVector h = sampling::ggx_half_vector(0.09, 0.6, phi);
        EXPECT_NEAR(glm::length(h.direction), 1.0, 1e-15);
        EXPECT_DOUBLE_EQ(h.direction.z * h.direction.z, h.cos2_theta);
        const double azimuth = std::atan2(h.direction.y, h.direction.x);
        EXPECT_NEAR(std::remainder(azimuth - phi, 2.0 * pi), 0.0, 1e-12) << phi;
    }
    // u = 0 is the normal itself.
    EXPECT_EQ(sampling::ggx_half_vector(0.25, 0.0, 1.0).direction, glm::dvec3(0.0, 0.0, 1.0));
}

TEST(SamplingCosine, DirectionsHaveTheMomentsOfTheCosineLobe) {
    // Over a stratified grid of (u1, u2), density cos / pi: E[cos] = 2/3 (a uniform hemisphere
    // gives 1/2), E[cos^2] = 1/2, the mean direction (2/3) n, P(cos > 1/2) = 3/4. The concentric
    // map takes the grid's square rings to rings of the disc, so that last share moves in steps
    // of about 2 / kSide.
    constexpr int kSide = 512;
    for (const glm::dvec3 n : {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0),
                               glm::normalize(glm::dvec3(0.3, -0.8, 0.5))}) {
        double cosine = 0.0, cosine2 = 0.0, above_half = 0.0;
        glm::dvec3 mean(0.0);
        for (int row = 0; row < kSide; ++row) {
            for (int column = 0; column < kSide; ++column) {
                const glm::dvec3 d =
                    sampling::cosine_direction(n, (column + 0.5) / kSide, (row + 0.5) / kSide);
                ASSERT_NEAR(glm::length(d), 1.0, 1e-12);
                const double c = glm::dot(d, n);
                ASSERT_GE(c, -1e-12);
                cosine += c;
                cosine2 += c * c;
                above_half += c > 0.5 ? 1.0 : 0.0;
                mean += d;
            }
        }
        const double count = double(kSide) * kSide;
        EXPECT_NEAR(cosine / count, 2.0 / 3.0, 1e-3) << n.x << " " << n.y << " " << n.z;
        EXPECT_NEAR(cosine2 / count, 0.5, 1e-3);
        EXPECT_NEAR(above_half / count, 0.75, 5e-3);
        EXPECT_NEAR(glm::length(mean / count - (2.0 / 3.0) * n), 0.0, 1e-3);
    }
}
