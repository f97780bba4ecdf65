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
// exact ties). Works on the centres and assignment of a KMeansResult.
template <int D>
class HamerlyIterations {
  public:
    // Assigns every point to its nearest seed centre and sums each cluster's members.
    HamerlyIterations(const std::vector<double>& points, KMeansResult& result)
        : points_(points),
          n_(points.size() / D),
          k_(result.centres.size() / D),
          centres_(result.centres),
          assignment_(result.assignment),
          upper_(n_),
          lower_(n_),
          sums_(k_ * D, 0.0),
          previous_(k_ * D),
          moved_(k_),
          half_gap_(k_),
          counts_(k_, 0) {
        assignment_.assign(n_, 0);
        for (std::size_t i = 0; i < n_; ++i) {
            scan(i);
        }
        sum_members();
    }

    // One iteration: the centres moved to their members' means, then the points reassigned.
    // Returns how many points changed cluster.
    std::size_t iterate(CentreKind kind) {
        move_centres(kind);
        measure_centre_motion();
        return reassign();
    }

  private:
    static constexpr double infinity = std::numeric_limits<double>::infinity();

    // Exact nearest and second-nearest distances of point i.
    void scan(std::size_t i) {
        const double* p = &points_[i * D];
        double best = infinity, second = infinity;
        std::uint32_t best_index = 0;
        for (std::size_t c = 0; c < k_; ++c) {
            const double d = squared_distance<D>(p, &centres_[c * D]);
            if (d < best) {
                second = best;
                best = d;
                best_index = std::uint32_t(c);
            } else if (d < second) {
                second = d;
            }
        }
        assignment_[i] = best_index;
        upper_[i] = std::sqrt(best);
        lower_[i] = std::sqrt(second);  // infinity when k == 1
    }

    // Member sums and counts, then kept up to date as points change cluster (an O(changes)
    // update rather than a pass over every point per iteration).
    void sum_members() {
        for (std::size_t i = 0; i < n_; ++i) {
            const std::size_t c = assignment_[i];
            ++counts_[c];
            for (std::size_t j = 0; j < D; ++j) {
                sums_[c * D + j] += points_[i * D + j];
            }
        }
    }

    // Centres: their members' mean (renormalised for UnitMean); empty clusters stay.
    void move_centres(CentreKind kind) {
        previous_ = centres_;
        for (std::size_t c = 0; c < k_; ++c) {
            if (counts_[c] == 0) {
                continue;
            }
            double* centre = &centres_[c * D];
            const double* sum = &sums_[c * D];
            double scale = 1.0 / double(counts_[c]);
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
    }

    // How far each centre moved (the largest two moves kept), and half the distance to its
    // nearest other centre.
    void measure_centre_motion() {
        largest_ = 0.0;
        second_largest_ = 0.0;
        largest_index_ = 0;
        for (std::size_t c = 0; c < k_; ++c) {
            moved_[c] = std::sqrt(squared_distance<D>(&centres_[c * D], &previous_[c * D]));
            if (moved_[c] > largest_) {
                second_largest_ = largest_;
                largest_ = moved_[c];
                largest_index_ = c;
            } else if (moved_[c] > second_largest_) {
                second_largest_ = moved_[c];
            }
            half_gap_[c] = infinity;
        }
        for (std::size_t a = 0; a < k_; ++a) {
            for (std::size_t b = a + 1; b < k_; ++b) {
                const double gap =
                    0.5 * std::sqrt(squared_distance<D>(&centres_[a * D], &centres_[b * D]));
                half_gap_[a] = std::min(half_gap_[a], gap);
                half_gap_[b] = std::min(half_gap_[b], gap);
            }
        }
    }

    // The bounds moved with the centres; a point whose bounds no longer prove its centre the
    // nearest is scanned again, and the member sums follow it if it changes cluster.
    std::size_t reassign() {
        std::size_t changed = 0;
        for (std::size_t i = 0; i < n_; ++i) {
            const std::size_t a = assignment_[i];
            upper_[i] += moved_[a];
            lower_[i] -= a == largest_index_ ? second_largest_ : largest_;
            const double bound = std::max(half_gap_[a], lower_[i]);
            if (upper_[i] <= bound) {
                continue;
            }
            upper_[i] = std::sqrt(squared_distance<D>(&points_[i * D], &centres_[a * D]));
            if (upper_[i] <= bound) {
                continue;
            }
            scan(i);
            const std::size_t b = assignment_[i];
            if (b != a) {
                ++changed;
                --counts_[a];
                ++counts_[b];
                for (std::size_t j = 0; j < D; ++j) {
                    sums_[a * D + j] -= points_[i * D + j];
                    sums_[b * D + j] += points_[i * D + j];
                }
            }
        }
        return changed;
    }

    const std::vector<double>& points_;
    const std::size_t n_, k_;
    std::vector<double>& centres_;
    std::vector<std::uint32_t>& assignment_;
    std::vector<double> upper_, lower_;
    std::vector<double> sums_, previous_, moved_, half_gap_;
    std::vector<std::size_t> counts_;
    double largest_ = 0.0, second_largest_ = 0.0;
    std::size_t largest_index_ = 0;
};

template <int D>
KMeansResult run(const std::vector<double>& points, int k, CentreKind kind, std::uint64_t seed,
                 int max_iterations) {
    const std::size_t n = points.size() / D;
    k = int(std::clamp<std::size_t>(std::size_t(std::max(k, 1)), 1, n));
    std::mt19937_64 rng(seed);
    KMeansResult result;
    result.dimension = D;
    result.centres = seed_centres<D>(points, n, k, rng);
    result.k = int(result.centres.size() / D);
    HamerlyIterations<D> iterations(points, result);
    while (result.iterations < max_iterations) {
        ++result.iterations;
        if (iterations.iterate(kind) == 0) {
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
