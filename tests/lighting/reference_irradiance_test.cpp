#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/reference_irradiance.hpp"
#include "sh_test_support.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

// A dim sky with a few bright gaussian blobs (lights of different sizes and colors).
HdrImage blob_map(int width, int height) {
    struct Blob {
        glm::dvec3 centre;
        double radius;
        glm::dvec3 radiance;
    };
    const Blob blobs[] = {
        {glm::normalize(glm::dvec3(0.3, 0.8, -0.5)), 0.03, {4000.0, 3800.0, 3000.0}},
        {glm::normalize(glm::dvec3(-0.7, 0.2, 0.4)), 0.10, {50.0, 60.0, 90.0}},
        {glm::normalize(glm::dvec3(0.1, -0.3, 0.9)), 0.05, {200.0, 40.0, 10.0}},
    };
    HdrImage image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d = equirect::pixel_direction(x, y, width, height);
            glm::dvec3 value(0.3 + 0.2 * d.y, 0.35 + 0.2 * d.y, 0.5 + 0.3 * d.y);
            for (const Blob& blob : blobs) {
                const double angle = std::acos(std::min(1.0, glm::dot(d, blob.centre)));
                value +=
                    blob.radiance * std::exp(-0.5 * angle * angle / (blob.radius * blob.radius));
            }
            image.set(std::size_t(y) * width + x, glm::vec3(value));
        }
    }
    return image;
}

double max_relative_to_pi_l(const std::vector<glm::dvec3>& e, const glm::dvec3& radiance) {
    double worst = 0.0;
    for (const glm::dvec3& value : e) {
        for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, std::abs(value[c] / (pi * radiance[c]) - 1.0));
        }
    }
    return worst;
}

}  // namespace

TEST(ReferenceIrradianceFibonacciSphere, UnitPointsSpreadEvenly) {
    EXPECT_TRUE(fibonacci_sphere(0).empty());
    EXPECT_THROW(fibonacci_sphere(-1), Error);
    const int n = 1000;
    const std::vector<glm::dvec3> points = fibonacci_sphere(n);
    ASSERT_EQ(points.size(), std::size_t(n));
    glm::dvec3 mean(0.0);
    double closest = 2.0;
    for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(glm::length(points[i]), 1.0, 1e-14);
        mean += points[i] / double(n);
        for (int j = 0; j < i; ++j) {
            closest = std::min(closest, glm::length(points[i] - points[j]));
        }
    }
    EXPECT_LT(glm::length(mean), 1e-3);
    // Each point has an area of 4 pi / n; an even spread keeps neighbours a good fraction of
    // the corresponding spacing sqrt(4 pi / n) apart (random points would come far closer).
    EXPECT_GT(closest, 0.5 * std::sqrt(4.0 * pi / n));
    // Equal-area bands: as many points above y = 0.5 as the cap's share of the sphere (1/4).
    int above = 0;
    for (const glm::dvec3& p : points) {
        above += p.y > 0.5 ? 1 : 0;
    }
    EXPECT_NEAR(above, n / 4, 2);
}

TEST(ReferenceIrradiance, ConstantMapGivesPiL) {
    // Pixel-centre directions make the brute force a second-order quadrature of the clamped
    // cosine: measured worst relative error 3.1e-5 at 256x128 and 1.6e-6 at 1024x512 over these
    // normals (it cannot be exact: the clamped cosine is not linear over pixels that straddle the
    // horizon).
    const glm::dvec3 radiance(0.5, 1.0, 3.0);
    const std::vector<glm::dvec3> normals = fibonacci_sphere(64);
    const double coarse = max_relative_to_pi_l(
        ReferenceIrradiance(test::constant_map(256, 128, glm::vec3(radiance))).at(normals),
        radiance);
    const double fine = max_relative_to_pi_l(
        ReferenceIrradiance(test::constant_map(1024, 512, glm::vec3(radiance))).at(normals),
        radiance);
    std::printf("constant map: worst relative error 256x128 %.2e, 1024x512 %.2e\n", coarse, fine);
    EXPECT_LT(fine, 3e-6);
    EXPECT_LT(fine, coarse / 10.0);  // second order: 16x finer pixels area-wise
}

TEST(ReferenceIrradiance, SingleSampleEqualsBruteForceFormula) {
    HdrImage image(16, 8);
    image.set(3 * 16 + 5, {2.0f, 4.0f, 8.0f});
    image.set(6 * 16 + 12, {1.0f, 0.0f, 0.5f});
    const ReferenceIrradiance reference(image);
    EXPECT_EQ(reference.sample_count(), image.pixel_count());
    for (const glm::dvec3& n : fibonacci_sphere(50)) {
        glm::dvec3 expected(0.0);
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 16; ++x) {
                const glm::dvec3 d = equirect::pixel_direction(x, y, 16, 8);
                expected += glm::dvec3(image.rgb(std::size_t(y) * 16 + x)) *
                            std::max(0.0, glm::dot(n, d)) * equirect::pixel_solid_angle(y, 16, 8);
            }
        }
        const glm::dvec3 e = reference.at(n);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(e[c], expected[c], 1e-14);
        }
    }
}

TEST(ReferenceIrradiance, BatchEqualsOneAtATime) {
    const HdrImage image = test::random_map(300, 150, 3);
    const ReferenceIrradiance reference(image);
    for (const int count : {1, 7, 8, 9, 203}) {  // 203 normals: two threads, a partial block
        const std::vector<glm::dvec3> normals = fibonacci_sphere(count);
        const std::vector<glm::dvec3> batch = reference.at(normals);
        ASSERT_EQ(batch.size(), normals.size());
        for (int i = 0; i < count; ++i) {
            EXPECT_EQ(batch[i], reference.at(normals[i])) << count << " normals, " << i;
        }
    }
}

TEST(ReferenceIrradiance, ReductionPreservesEnergyAndBoundsSamples) {
    const HdrImage image = test::random_map(37, 19, 5);  // sizes that do not divide evenly
    double total = 0.0;                                  // sum of L dOmega, channel 0
    for (int y = 0; y < 19; ++y) {
        for (int x = 0; x < 37; ++x) {
            total += image.at(x, y)[0] * equirect::pixel_solid_angle(y, 37, 19);
        }
    }
    // Mean of E over the sphere = sum (L dOmega) * (mean of max(0, n.d) over n = 1/4).
    const std::vector<glm::dvec3> normals = fibonacci_sphere(20000);
    for (const std::size_t max_samples :
         {std::size_t(1), std::size_t(20), std::size_t(100), std::size_t(500), std::size_t(0)}) {
        const ReferenceIrradiance reference(image, max_samples);
        if (max_samples > 0) {
            EXPECT_LE(reference.sample_count(), max_samples);
        } else {
            EXPECT_EQ(reference.sample_count(), image.pixel_count());
        }
        double mean = 0.0;
        for (const glm::dvec3& e : reference.at(normals)) {
            mean += e.x / double(normals.size());
        }
        EXPECT_NEAR(mean, total / 4.0, 1e-3 * total) << max_samples << " samples";
    }
}

TEST(ReferenceIrradiance, ReducedMatchesFullOnBrightBlobs) {
    // 2048x1024 with a small bright sun and two softer lights, reduced to at most 65536 samples
    // (blocks of 6x6 pixels, 58482 samples): measured relative RMS difference 5.1e-5 over 512
    // normals.
    const HdrImage image = blob_map(2048, 1024);
    const std::vector<glm::dvec3> normals = fibonacci_sphere(512);
    const ReferenceIrradiance full(image);
    const ReferenceIrradiance reduced(image, 65536);
    EXPECT_LE(reduced.sample_count(), 65536u);
    const double error = relative_rms_error(reduced.at(normals), full.at(normals));
    std::printf("reduced (%zu samples) vs full (%zu): relative RMS %.3e\n", reduced.sample_count(),
                full.sample_count(), error);
    EXPECT_LT(error, 2e-4);
    EXPECT_GT(error, 0.0);
}

TEST(ReferenceIrradiance, RelativeRmsError) {
    const std::vector<glm::dvec3> reference = {{1, 2, 3}, {4, 5, 6}};
    const std::vector<glm::dvec3> scaled = {{1.1, 2.2, 3.3}, {4.4, 5.5, 6.6}};
    EXPECT_NEAR(relative_rms_error(scaled, reference), 0.1, 1e-14);
    EXPECT_EQ(relative_rms_error(reference, reference), 0.0);
    const std::vector<glm::dvec3> offset = {{1, 2, 3}, {4, 5, 7}};
    EXPECT_NEAR(relative_rms_error(offset, reference), 1.0 / std::sqrt(91.0), 1e-14);
    const std::vector<glm::dvec3> one = {{1, 2, 3}};
    EXPECT_THROW(relative_rms_error(one, reference), Error);
    const std::vector<glm::dvec3> zero = {{0, 0, 0}};
    EXPECT_EQ(relative_rms_error(zero, zero), 0.0);
    EXPECT_TRUE(std::isinf(relative_rms_error(one, zero)));
}

TEST(ReferenceIrradiance, RejectsInvalidImage) {
    HdrImage broken(4, 2);
    broken.pixels.resize(5);
    EXPECT_THROW(ReferenceIrradiance{broken}, Error);
    EXPECT_THROW(ReferenceIrradiance{HdrImage()}, Error);
}
