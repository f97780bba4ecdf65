#include "kmeans.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "oer/core/error.hpp"

namespace oer::detail {

namespace {

template <int D>
double squared_distance(const double* a, const double* b) {
    double sum = 0.0;
    for (int i = 0; i < D; ++i) {
        const double d = a[i] - b[i];
        sum += d * d;
    }
    return sum;
}

template <int D>
std::uint32_t nearest(const double* point, const double* centres, int k) {
    std::uint32_t best = 0;
    double best_distance = squared_distance<D>(point, centres);
    for (int c = 1; c < k; ++c) {
        const double d = squared_distance<D>(point, centres + std::size_t(c) * D);
        if (d < best_distance) {
            best_distance = d;
            best = std::uint32_t(c);
        }
    }
    return best;
}

// k-means++ (Arthur and Vassilvitskii 2007): the first centre uniformly, each next one with
// probability proportional to the squared distance to the nearest centre chosen so far.
template <int D>
std::vector<double> seed_centres(const std::vector<double>& points, std::size_t n, int k,
                                 std::mt19937_64& rng) {
    std::vector<double> centres;
    centres.reserve(std::size_t(k) * D);
    const std::size_t first = std::min(n - 1, std::size_t(uniform01(rng) * double(n)));
    centres.insert(centres.end(), points.begin() + std::ptrdiff_t(first * D),
                   points.begin() + std::ptrdiff_t(first * D + D));
    std::vector<double> nearest_squared(n);
    for (std::size_t i = 0; i < n; ++i) {
        nearest_squared[i] = squared_distance<D>(&points[i * D], centres.data());
    }
    for (int c = 1; c < k; ++c) {
        double total = 0.0;
        for (double d : nearest_squared) {
            total += d;
        }
        if (!(total > 0.0)) {
            break;  // every point coincides with a centre: no more distinct centres
        }
        const double target = uniform01(rng) * total;
        std::size_t chosen = n;
        double cumulative = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            if (nearest_squared[i] > 0.0) {
                chosen = i;  // last candidate, in case rounding leaves cumulative <= target
                cumulative += nearest_squared[i];
                if (cumulative > target) {
                    break;
                }
            }
        }
        const double* centre = &points[chosen * D];
        centres.insert(centres.end(), centre, centre + D);
        for (std::size_t i = 0; i < n; ++i) {
            nearest_squared[i] =
                std::min(nearest_squared[i], squared_distance<D>(&points[i * D], centre));
        }
    }
    return centres;
}

// Lloyd's algorithm (Lloyd 1982: assign each point to its nearest centre, move each centre to
// its points' mean, repeat) with Hamerly's bounds (G. Hamerly, "Making k-means even faster", SDM
// 2010): per point an upper bound on the distance to its centre and a lower bound on the
// distance to every other centre, kept valid as the centres move, so that most points skip the
// scan over all centres once the clustering settles. Same assignments as plain Lloyd (up to
// exact ties).
template <int D>
KMeansResult run(const std::vector<double>& points, int k, CentreKind kind, std::uint64_t seed,
                 int max_iterations) {
    constexpr double infinity = std::numeric_limits<double>::infinity();
    const std::size_t n = points.size() / D;
    k = int(std::clamp<std::size_t>(std::size_t(std::max(k, 1)), 1, n));
    std::mt19937_64 rng(seed);
    KMeansResult result;
    result.dimension = D;
    result.centres = seed_centres<D>(points, n, k, rng);
    result.k = int(result.centres.size() / D);
    k = result.k;
    const std::size_t kk = std::size_t(k);
    std::vector<double>& centres = result.centres;
    std::vector<std::uint32_t>& assignment = result.assignment;
    assignment.assign(n, 0);
    std::vector<double> upper(n), lower(n);

    // Exact nearest and second-nearest distances of point i.
    auto scan = [&](std::size_t i) {
        const double* p = &points[i * D];
        double best = infinity, second = infinity;
        std::uint32_t best_index = 0;
        for (std::size_t c = 0; c < kk; ++c) {
            const double d = squared_distance<D>(p, &centres[c * D]);
            if (d < best) {
                second = best;
                best = d;
                best_index = std::uint32_t(c);
            } else if (d < second) {
                second = d;
            }
        }
        assignment[i] = best_index;
        upper[i] = std::sqrt(best);
        lower[i] = std::sqrt(second);  // infinity when k == 1
    };
    for (std::size_t i = 0; i < n; ++i) {
        scan(i);
    }

    // Member sums and counts, kept up to date as points change cluster (an O(changes) update
    // rather than a pass over every point per iteration).
    std::vector<double> sums(kk * D, 0.0), previous(kk * D), moved(kk), half_gap(kk);
    std::vector<std::size_t> counts(kk, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t c = assignment[i];
        ++counts[c];
        for (std::size_t j = 0; j < D; ++j) {
            sums[c * D + j] += points[i * D + j];
        }
    }
    while (result.iterations < max_iterations) {
        ++result.iterations;
        // Centres: their members' mean (renormalised for UnitMean); empty clusters stay.
        previous = centres;
        for (std::size_t c = 0; c < kk; ++c) {
            if (counts[c] == 0) {
                continue;
            }
            double* centre = &centres[c * D];
            const double* sum = &sums[c * D];
            double scale = 1.0 / double(counts[c]);
            if (kind == CentreKind::UnitMean) {
                double squared_length = 0.0;
                for (std::size_t j = 0; j < D; ++j) {
                    squared_length += sum[j] * sum[j];
                }
                if (!(squared_length > 0.0)) {
                    continue;
                }
                scale = 1.0 / std::sqrt(squared_length);
            }
            for (std::size_t j = 0; j < D; ++j) {
                centre[j] = sum[j] * scale;
            }
        }

        // How far each centre moved, and half the distance to its nearest other centre.
        double largest = 0.0, second_largest = 0.0;
        std::size_t largest_index = 0;
        for (std::size_t c = 0; c < kk; ++c) {
            moved[c] = std::sqrt(squared_distance<D>(&centres[c * D], &previous[c * D]));
            if (moved[c] > largest) {
                second_largest = largest;
                largest = moved[c];
                largest_index = c;
            } else if (moved[c] > second_largest) {
                second_largest = moved[c];
            }
            half_gap[c] = infinity;
        }
        for (std::size_t a = 0; a < kk; ++a) {
            for (std::size_t b = a + 1; b < kk; ++b) {
                const double gap =
                    0.5 * std::sqrt(squared_distance<D>(&centres[a * D], &centres[b * D]));
                half_gap[a] = std::min(half_gap[a], gap);
                half_gap[b] = std::min(half_gap[b], gap);
            }
        }

        std::size_t changed = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t a = assignment[i];
            upper[i] += moved[a];
            lower[i] -= a == largest_index ? second_largest : largest;
            const double bound = std::max(half_gap[a], lower[i]);
            if (upper[i] <= bound) {
                continue;
            }
            upper[i] = std::sqrt(squared_distance<D>(&points[i * D], &centres[a * D]));
            if (upper[i] <= bound) {
                continue;
            }
            scan(i);
            const std::size_t b = assignment[i];
            if (b != a) {
                ++changed;
                --counts[a];
                ++counts[b];
                for (std::size_t j = 0; j < D; ++j) {
                    sums[a * D + j] -= points[i * D + j];
                    sums[b * D + j] += points[i * D + j];
                }
            }
        }
        if (changed == 0) {
            result.converged = true;
            break;
        }
    }
    return result;
}

}  // namespace

KMeansResult kmeans(const std::vector<double>& points, int dimension, int k, CentreKind kind,
                    std::uint64_t seed, int max_iterations) {
    if (dimension == 2 && points.size() >= 2 && points.size() % 2 == 0) {
        return run<2>(points, k, kind, seed, max_iterations);
    }
    if (dimension == 3 && points.size() >= 3 && points.size() % 3 == 0) {
        return run<3>(points, k, kind, seed, max_iterations);
    }
    throw Error(ErrorKind::Internal, "kmeans: dimension must be 2 or 3, with at least one point");
}

std::uint32_t nearest_centre(const double* point, const std::vector<double>& centres,
                             int dimension) {
    const int k = int(centres.size()) / dimension;
    return dimension == 2 ? nearest<2>(point, centres.data(), k)
                          : nearest<3>(point, centres.data(), k);
}

}  // namespace oer::detail
