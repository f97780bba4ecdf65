#pragma once
// Private: percentiles by selection (std::nth_element), not by sorting.
#include <cstddef>

namespace oer::detail {

// Rank (0-based, ascending) of the p-quantile of n values: floor(p (n - 1)), the "lower"
// quantile, so that the value returned is always one of the values. n > 0, p in [0, 1].
std::size_t quantile_rank(std::size_t n, double p);

struct PercentilePair {
    float high = 0.0f;     // value at quantile_rank(n, high_p)
    float low = 0.0f;      // value at quantile_rank(n, low_p)
    float minimum = 0.0f;  // the smallest value
};

// The values at two quantiles, low_p <= high_p, and the minimum of n > 0 values (no NaN), exact.
// Large sets are first narrowed by a deterministic sample (Floyd-Rivest style): the sample's
// quantiles, widened by a safe margin, bracket both ranks; one pass counts the values below the
// bracket and copies those inside it, and std::nth_element runs on that copy only (a few
// percent of the values). Should the bracket miss (it cannot for any realistic map, but
// adversarial inputs could), it falls back to std::nth_element on a copy of everything.
PercentilePair select_percentiles(const float* values, std::size_t n, double high_p, double low_p);

}  // namespace oer::detail
