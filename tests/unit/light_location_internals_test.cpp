// Tests of the private helpers of light location (renderer/src), included by relative path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "../../renderer/src/kmeans.hpp"
#include "../../renderer/src/percentile.hpp"

using namespace oer::detail;

namespace {

// Reference: the value at a rank by a full sort.
float sorted_at(std::vector<float> values, std::size_t rank) {
    std::sort(values.begin(), values.end());
    return values[rank];
}

void expect_exact_percentiles(const std::vector<float>& values, double high_p, double low_p) {
    const PercentilePair got = select_percentiles(values.data(), values.size(), high_p, low_p);
    EXPECT_EQ(got.high, sorted_at(values, quantile_rank(values.size(), high_p)));
    EXPECT_EQ(got.low, sorted_at(values, quantile_rank(values.size(), low_p)));
    EXPECT_EQ(got.minimum, *std::min_element(values.begin(), values.end()));
}

}  // namespace

TEST(Percentile, RankIsTheLowerQuantile) {
    EXPECT_EQ(quantile_rank(1, 0.99), 0u);
    EXPECT_EQ(quantile_rank(100, 0.99), 98u);  // floor(0.99 * 99)
    EXPECT_EQ(quantile_rank(101, 0.99), 99u);
    EXPECT_EQ(quantile_rank(101, 1.0), 100u);
    EXPECT_EQ(quantile_rank(101, 0.0), 0u);
}

TEST(Percentile, SelectionMatchesAFullSort) {
    std::mt19937_64 rng(7);
    for (std::size_t n : {std::size_t(1), std::size_t(2), std::size_t(1000), std::size_t(70000),
                          std::size_t(300000)}) {
        std::vector<float> noise(n), ties(n), smooth(n);
        for (std::size_t i = 0; i < n; ++i) {
            noise[i] = float(rng() >> 40) * 1e-3f;
            ties[i] = float((rng() >> 60) % 3);                            // three values only
            smooth[i] = float(i % 1000) + (i > n - n / 50 ? 1e6f : 0.0f);  // sorted runs, a tail
        }
        expect_exact_percentiles(noise, 0.99, 0.96);
        expect_exact_percentiles(ties, 0.99, 0.96);
        expect_exact_percentiles(smooth, 0.99, 0.96);
        expect_exact_percentiles(noise, 0.5, 0.5);
    }
}

TEST(Percentile, TiesAtTheBracketsBottom) {
    // A uniform background with a few brighter values: the low rank, or both, fall among the
    // ties with the bracket's lower bound.
    const std::size_t n = 100000;
    for (std::size_t bright : {std::size_t(0), std::size_t(10), std::size_t(500), std::size_t(2000),
                               std::size_t(5000)}) {
        std::vector<float> values(n, 5.0f);
        for (std::size_t i = 0; i < bright; ++i) {
            values[(i * 7919) % n] = 6.0f + float(i);
        }
        values[n / 2] = 1.0f;  // and one darker pixel
        expect_exact_percentiles(values, 0.99, 0.96);
    }
}

TEST(Percentile, SelectionIsExactWhenTheSampleIsMisleading) {
    // Zeros exactly where percentile.cpp samples (one value per stride, at a hashed offset),
    // ones everywhere else: the sample's bracket [0, 0] misses both ranks, and the exact
    // fallback must answer.
    const std::size_t n = std::size_t(1) << 17, sample_size = 8192, stride = n / sample_size;
    std::vector<float> values(n, 1.0f);
    for (std::size_t j = 0; j < sample_size; ++j) {
        const std::uint64_t hashed = std::uint64_t(j + 1) * 0x9E3779B97F4A7C15ull;
        values[j * stride + std::size_t((hashed >> 32) % stride)] = 0.0f;
    }
    const PercentilePair got = select_percentiles(values.data(), n, 0.99, 0.96);
    EXPECT_EQ(got.high, 1.0f);
    EXPECT_EQ(got.low, 1.0f);
    EXPECT_EQ(got.minimum, 0.0f);
    // Other structured layouts.
    std::vector<float> alternating(n, 1.0f);
    for (std::size_t i = 0; i < n; i += 2) {
        alternating[i] = float(i);
    }
    expect_exact_percentiles(alternating, 0.99, 0.96);
    std::vector<float> descending(n);
    for (std::size_t i = 0; i < n; ++i) {
        descending[i] = float(n - i);
    }
    expect_exact_percentiles(descending, 0.999, 0.001);
}

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
