// k-means, a private helper of light location (renderer/lighting/src/kmeans).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "kmeans.hpp"

using namespace oer::detail;

namespace {

// Brute force: the index of the centre at the least squared distance, ties to the lowest.
std::uint32_t nearest_by_brute_force(const double* point, const std::vector<double>& centres,
                                     int dimension) {
    std::uint32_t best = 0;
    double best_distance = INFINITY;
    for (std::size_t c = 0; c * std::size_t(dimension) < centres.size(); ++c) {
        double distance = 0.0;
        for (int d = 0; d < dimension; ++d) {
            const double difference = point[d] - centres[c * std::size_t(dimension) + d];
            distance += difference * difference;
        }
        if (distance < best_distance) {
            best_distance = distance;
            best = std::uint32_t(c);
        }
    }
    return best;
}

}  // namespace

TEST(KMeans, UniformFromRawBitsIsDeterministicAndInRange) {
    std::mt19937_64 a(42), b(42), reference(42);
    for (int i = 0; i < 1000; ++i) {
        const double u = uniform01(a);
        EXPECT_EQ(u, uniform01(b));
        EXPECT_GE(u, 0.0);
        EXPECT_LT(u, 1.0);
        EXPECT_EQ(u, std::ldexp(double(reference() >> 11), -53));
    }
}

TEST(KMeans, FindsSeparatedBlobsDeterministically) {
    // Three square blobs of 2-D points, 100 apart.
    std::vector<double> points;
    const double centres[3][2] = {{0.0, 0.0}, {100.0, 0.0}, {50.0, 100.0}};
    for (const auto& c : centres) {
        for (int i = 0; i < 20; ++i) {
            for (int j = 0; j < 20; ++j) {
                points.push_back(c[0] + i * 0.5);
                points.push_back(c[1] + j * 0.5);
            }
        }
    }
    const KMeansResult r = kmeans(points, 2, 3, CentreKind::Mean, 1234);
    EXPECT_EQ(r.k, 3);
    EXPECT_TRUE(r.converged);
    // Every blob is one cluster, with its centre at the blob's mean.
    for (int blob = 0; blob < 3; ++blob) {
        const std::uint32_t c = r.assignment[std::size_t(blob) * 400];
        for (int i = 0; i < 400; ++i) {
            ASSERT_EQ(r.assignment[std::size_t(blob) * 400 + i], c);
        }
        EXPECT_NEAR(r.centres[c * 2], centres[blob][0] + 4.75, 1e-9);
        EXPECT_NEAR(r.centres[c * 2 + 1], centres[blob][1] + 4.75, 1e-9);
    }
    const KMeansResult again = kmeans(points, 2, 3, CentreKind::Mean, 1234);
    EXPECT_EQ(again.assignment, r.assignment);
    EXPECT_EQ(again.centres, r.centres);
    EXPECT_EQ(again.iterations, r.iterations);
}

TEST(KMeans, MatchesPlainLloydOnOverlappingData) {
    // Hamerly's bounds must not change what Lloyd converges to: at the fixed point every
    // point is with its nearest centre and every centre is the mean of its points.
    std::mt19937_64 rng(99);
    std::vector<double> points;
    for (int i = 0; i < 3000; ++i) {
        points.push_back(uniform01(rng) * 10.0 + (i % 3) * 3.0);
        points.push_back(uniform01(rng) * 10.0);
    }
    const KMeansResult r = kmeans(points, 2, 6, CentreKind::Mean, 5);
    ASSERT_TRUE(r.converged);
    std::vector<double> sums(std::size_t(r.k) * 2, 0.0);
    std::vector<int> counts(std::size_t(r.k), 0);
    for (std::size_t i = 0; i < points.size() / 2; ++i) {
        EXPECT_EQ(nearest_by_brute_force(&points[i * 2], r.centres, 2), r.assignment[i]);
        EXPECT_EQ(nearest_centre(&points[i * 2], r.centres, 2), r.assignment[i]);
        sums[r.assignment[i] * 2] += points[i * 2];
        sums[r.assignment[i] * 2 + 1] += points[i * 2 + 1];
        ++counts[r.assignment[i]];
    }
    for (int c = 0; c < r.k; ++c) {
        ASSERT_GT(counts[c], 0);
        EXPECT_NEAR(r.centres[c * 2], sums[c * 2] / counts[c], 1e-9);
        EXPECT_NEAR(r.centres[c * 2 + 1], sums[c * 2 + 1] / counts[c], 1e-9);
    }
}

TEST(KMeans, UnitCentresOnTheSphere) {
    std::vector<double> points;
    for (int i = 0; i < 50; ++i) {
        const double a = 0.01 * i;
        points.insert(points.end(), {std::cos(a), std::sin(a), 0.0});
        points.insert(points.end(), {0.0, std::cos(a), std::sin(a)});
    }
    const KMeansResult r = kmeans(points, 3, 2, CentreKind::UnitMean, 3);
    ASSERT_EQ(r.k, 2);
    for (int c = 0; c < 2; ++c) {
        const double* v = &r.centres[c * 3];
        EXPECT_NEAR(v[0] * v[0] + v[1] * v[1] + v[2] * v[2], 1.0, 1e-12);
    }
    EXPECT_NE(r.assignment[0], r.assignment[1]);
    // Each arc is one cluster, whose unit mean is the normalised sum of its points: by hand,
    // sum over i of (cos 0.01 i, sin 0.01 i) points at angle 0.245 (the arc's middle), so the
    // centres are (cos 0.245, sin 0.245, 0) and (0, cos 0.245, sin 0.245).
    const double middle = 0.01 * 49 / 2.0;
    const double* first = &r.centres[r.assignment[0] * 3];
    const double* second = &r.centres[r.assignment[1] * 3];
    EXPECT_NEAR(first[0], std::cos(middle), 1e-12);
    EXPECT_NEAR(first[1], std::sin(middle), 1e-12);
    EXPECT_NEAR(first[2], 0.0, 1e-12);
    EXPECT_NEAR(second[0], 0.0, 1e-12);
    EXPECT_NEAR(second[1], std::cos(middle), 1e-12);
    EXPECT_NEAR(second[2], std::sin(middle), 1e-12);
    for (int i = 0; i < 50; ++i) {
        EXPECT_EQ(r.assignment[2 * i], r.assignment[0]) << i;
        EXPECT_EQ(r.assignment[2 * i + 1], r.assignment[1]) << i;
    }
}

TEST(KMeans, HandComputedOneDimensionalPairs) {
    // Two pairs far apart, (0, 0) (1, 0) and (10, 0) (12, 0): whatever the seeding, Lloyd ends
    // with the centres at the pairs' means, (0.5, 0) and (11, 0).
    const std::vector<double> points = {0.0, 0.0, 1.0, 0.0, 10.0, 0.0, 12.0, 0.0};
    const KMeansResult r = kmeans(points, 2, 2, CentreKind::Mean, 17);
    ASSERT_EQ(r.k, 2);
    ASSERT_TRUE(r.converged);
    EXPECT_EQ(r.assignment[0], r.assignment[1]);
    EXPECT_EQ(r.assignment[2], r.assignment[3]);
    EXPECT_NE(r.assignment[0], r.assignment[2]);
    EXPECT_DOUBLE_EQ(r.centres[r.assignment[0] * 2], 0.5);
    EXPECT_DOUBLE_EQ(r.centres[r.assignment[2] * 2], 11.0);
    EXPECT_DOUBLE_EQ(r.centres[r.assignment[0] * 2 + 1], 0.0);
}

TEST(KMeans, KIsClampedToPointsAndDistinctValues) {
    const std::vector<double> two = {0.0, 0.0, 1.0, 1.0};
    EXPECT_EQ(kmeans(two, 2, 10, CentreKind::Mean, 1).k, 2);
    const std::vector<double> same = {3.0, 3.0, 3.0, 3.0, 3.0, 3.0};
    const KMeansResult r = kmeans(same, 2, 3, CentreKind::Mean, 1);
    EXPECT_EQ(r.k, 1);  // duplicates: one distinct centre
    EXPECT_EQ(r.assignment, (std::vector<std::uint32_t>{0, 0, 0}));
    EXPECT_THROW(kmeans({}, 2, 1, CentreKind::Mean, 1), std::exception);
    EXPECT_THROW(kmeans({1.0, 2.0, 3.0, 4.0}, 4, 1, CentreKind::Mean, 1), std::exception);
}
