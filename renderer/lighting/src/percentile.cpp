#include "percentile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "large_buffer.hpp"
#include "oer/core/error.hpp"

namespace oer::detail {

namespace {

// Below this many values the sample is not worth it.
constexpr std::size_t min_sampled_size = std::size_t(1) << 16;
constexpr std::size_t sample_size = 8192;
// Margin, in sample ranks, on each side of the sampled quantiles: the rank of a quantile in an
// 8192-value sample has a standard deviation of sqrt(8192 p (1 - p)), at most 45, 18 for the
// default percentiles.
constexpr std::size_t sample_margin = 160;

// Both ranks, then the low one among the values below the high one (they are all <= it).
void select_two(float* values, std::size_t n, std::size_t high_rank, std::size_t low_rank,
                PercentilePair& result) {
    float* high_it = values + high_rank;
    std::nth_element(values, high_it, values + n);
    result.high = *high_it;
    if (low_rank == high_rank) {
        result.low = result.high;
    } else {
        float* low_it = values + low_rank;
        std::nth_element(values, low_it, high_it);
        result.low = *low_it;
    }
}

PercentilePair select_all(const float* values, std::size_t n, std::size_t high_rank,
                          std::size_t low_rank) {
    LargeBuffer<float> copy(values, values + n);
    PercentilePair result;
    select_two(copy.data(), n, high_rank, low_rank, result);
    // Everything after low_rank is >= the value there: the minimum is at or before it.
    result.minimum = *std::min_element(copy.data(), copy.data() + low_rank + 1);
    return result;
}

struct Tally {
    std::size_t below = 0;   // values < lower
    std::size_t inside = 0;  // values in [lower, upper]
    std::size_t equal = 0;   // values == lower
    float minimum = 0.0f;
};

// Branch-free over 8 lanes, so that it vectorises; lane counters are flushed into the totals
// before they could overflow.
Tally tally(const float* values, std::size_t n, float lower, float upper) {
    constexpr std::size_t lanes = 8;
    constexpr std::size_t flush_every = std::size_t(1) << 24;
    Tally result;
    float minimum[lanes];
    std::fill(minimum, minimum + lanes, values[0]);
    std::size_t i = 0;
    while (i + lanes <= n) {
        std::uint32_t below[lanes] = {}, inside[lanes] = {}, equal[lanes] = {};
        const std::size_t end = std::min(n - (n - i) % lanes, i + flush_every);
        for (; i < end; i += lanes) {
            for (std::size_t j = 0; j < lanes; ++j) {
                const float v = values[i + j];
                minimum[j] = v < minimum[j] ? v : minimum[j];
                below[j] += std::uint32_t(v < lower);
                inside[j] += std::uint32_t((v >= lower) & (v <= upper));
                equal[j] += std::uint32_t(v == lower);
            }
        }
        for (std::size_t j = 0; j < lanes; ++j) {
            result.below += below[j];
            result.inside += inside[j];
            result.equal += equal[j];
        }
    }
    result.minimum = *std::min_element(minimum, minimum + lanes);
    for (; i < n; ++i) {
        const float v = values[i];
        result.minimum = std::min(result.minimum, v);
        result.below += std::size_t(v < lower);
        result.inside += std::size_t((v >= lower) & (v <= upper));
        result.equal += std::size_t(v == lower);
    }
    return result;
}

}  // namespace

std::size_t quantile_rank(std::size_t n, double p) {
    const double rank = std::floor(std::clamp(p, 0.0, 1.0) * double(n - 1));
    return std::min(n - 1, std::size_t(rank));
}

PercentilePair select_percentiles(const float* values, std::size_t n, double high_p, double low_p) {
    if (n == 0 || !(low_p <= high_p)) {
        throw Error(ErrorKind::Internal, "select_percentiles: empty set or low_p > high_p");
    }
    const std::size_t high_rank = quantile_rank(n, high_p);
    const std::size_t low_rank = quantile_rank(n, low_p);
    if (n < min_sampled_size) {
        return select_all(values, n, high_rank, low_rank);
    }

    // A deterministic sample: one value from each of sample_size equal strides, at an offset
    // within the stride given by a multiplicative hash (in memory order, for the prefetcher).
    std::vector<float> sample(sample_size);
    const std::size_t stride = n / sample_size;
    for (std::size_t j = 0; j < sample_size; ++j) {
        const std::uint64_t hashed = std::uint64_t(j + 1) * 0x9E3779B97F4A7C15ull;
        sample[j] = values[j * stride + std::size_t((hashed >> 32) % stride)];
    }
    const std::size_t sample_low = quantile_rank(sample_size, low_p);
    const std::size_t sample_high = quantile_rank(sample_size, high_p);
    const std::size_t bracket_low = sample_low > sample_margin ? sample_low - sample_margin : 0;
    const std::size_t bracket_high = std::min(sample_size - 1, sample_high + sample_margin);
    std::nth_element(sample.begin(), sample.begin() + std::ptrdiff_t(bracket_high), sample.end());
    const float upper = sample[bracket_high];
    std::nth_element(sample.begin(), sample.begin() + std::ptrdiff_t(bracket_low),
                     sample.begin() + std::ptrdiff_t(bracket_high));
    const float lower = sample[bracket_low];

    // One pass for the minimum and the counts below and inside the bracket, one to copy the
    // values inside it.
    const Tally counts = tally(values, n, lower, upper);
    const std::size_t below = counts.below;
    if (below > low_rank || below + counts.inside <= high_rank) {
        return select_all(values, n, high_rank, low_rank);  // the bracket missed a rank
    }
    // Ranks [below, ties_end) hold values equal to lower (a uniform background often fills
    // the bracket's bottom): those need no selection, the rest are selected among the values
    // in (lower, upper].
    PercentilePair result;
    result.minimum = counts.minimum;
    const std::size_t ties_end = below + counts.equal;
    if (high_rank < ties_end) {
        result.high = result.low = lower;
        return result;
    }
    LargeBuffer<float> inside(counts.inside - counts.equal + 1);  // + 1: see below
    std::size_t copied = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const float v = values[i];
        inside[copied] = v;  // written every time, kept only when in the bracket
        copied += std::size_t((v > lower) & (v <= upper));
    }
    if (low_rank < ties_end) {
        float* high_it = inside.data() + (high_rank - ties_end);
        std::nth_element(inside.data(), high_it, inside.data() + copied);
        result.high = *high_it;
        result.low = lower;
    } else {
        select_two(inside.data(), copied, high_rank - ties_end, low_rank - ties_end, result);
    }
    return result;
}

}  // namespace oer::detail
