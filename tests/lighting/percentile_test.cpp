// Percentile selection, a private helper of light location (renderer/lighting/src/percentile).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "percentile.hpp"

using namespace oer::detail;

namespace {

// Reference: the lower p-quantile by a full sort, its rank floor(p (n - 1)) computed here (not
// by quantile_rank, which the test RankIsTheLowerQuantile checks by hand).
float sorted_quantile(std::vector<float> values, double p) {
    std::sort(values.begin(), values.end());
    return values[std::size_t(std::floor(p * double(values.size() - 1)))];
}

void expect_exact_percentiles(const std::vector<float>& values, double high_p, double low_p) {
    const PercentilePair got = select_percentiles(values.data(), values.size(), high_p, low_p);
    EXPECT_EQ(got.high, sorted_quantile(values, high_p));
    EXPECT_EQ(got.low, sorted_quantile(values, low_p));
    float minimum = values[0];
    for (const float value : values) {
        minimum = value < minimum ? value : minimum;
    }
    EXPECT_EQ(got.minimum, minimum);
}

}  // namespace

TEST(Percentile, RankIsTheLowerQuantile) {
    EXPECT_EQ(quantile_rank(1, 0.99), 0u);
    EXPECT_EQ(quantile_rank(100, 0.99), 98u);  // floor(0.99 * 99)
    EXPECT_EQ(quantile_rank(101, 0.99), 99u);
    EXPECT_EQ(quantile_rank(101, 1.0), 100u);
    EXPECT_EQ(quantile_rank(101, 0.0), 0u);
}

TEST(Percentile, HandComputedCase) {
    // 0..99 shuffled: floor(0.99 * 99) = 98 and floor(0.96 * 99) = 95 are the ranks, and the
    // values at them in sorted order are 98 and 95.
    std::vector<float> values(100);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = float((i * 37) % 100);  // 37 is prime to 100: a permutation
    }
    const PercentilePair got = select_percentiles(values.data(), values.size(), 0.99, 0.96);
    EXPECT_EQ(got.high, 98.0f);
    EXPECT_EQ(got.low, 95.0f);
    EXPECT_EQ(got.minimum, 0.0f);
    // The same on 300000 values, which take the sampled path: 0 .. 299999 permuted (7919 is
    // prime to 300000); floor(0.99 * 299999) = 296999, floor(0.96 * 299999) = 287999.
    std::vector<float> large(300000);
    for (std::size_t i = 0; i < large.size(); ++i) {
        large[i] = float((i * 7919) % large.size());
    }
    const PercentilePair large_got = select_percentiles(large.data(), large.size(), 0.99, 0.96);
    EXPECT_EQ(large_got.high, 296999.0f);
    EXPECT_EQ(large_got.low, 287999.0f);
    EXPECT_EQ(large_got.minimum, 0.0f);
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
