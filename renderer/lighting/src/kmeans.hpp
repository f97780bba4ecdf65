#pragma once
// Private: k-means over points of dimension 2 (pixel coordinates) or 3 (unit direction vectors),
// Euclidean distance: k-means++ seeding from a fixed seed (D. Arthur and S. Vassilvitskii,
// "k-means++: The Advantages of Careful Seeding", SODA 2007), then Lloyd's iterations (S. P.
// Lloyd, "Least Squares Quantization in PCM", IEEE Transactions on Information Theory, 1982).
#include <cstdint>
#include <random>
#include <vector>

namespace oer::detail {

enum class CentreKind {
    Mean,      // centres are their members' mean
    UnitMean,  // ... renormalised to unit length (points on the unit sphere; chord distance)
};

struct KMeansResult {
    int dimension = 0;
    int k = 0;                              // clusters actually formed (<= asked, <= points)
    std::vector<double> centres;            // k * dimension
    std::vector<std::uint32_t> assignment;  // per point, index of its nearest centre
    int iterations = 0;                     // Lloyd iterations (centre update + reassignment)
    bool converged = false;                 // the last iteration changed no assignment
};

// A uniform double in [0, 1) from the top 53 bits of one raw output: the same on every
// platform, unlike std::uniform_real_distribution whose algorithm is implementation-defined.
inline double uniform01(std::mt19937_64& rng) {
    return double(rng() >> 11) * 0x1.0p-53;
}

// points holds n * dimension coordinates. k is clamped to [1, n]; seeding also stops early
// when every remaining point coincides with a chosen centre (duplicates). Empty clusters keep
// their previous centre. Ties go to the lowest centre index. Throws oer::Error(Internal) for
// a dimension other than 2 or 3 or an empty point set.
KMeansResult kmeans(const std::vector<double>& points, int dimension, int k, CentreKind kind,
                    std::uint64_t seed, int max_iterations = 100);

// Index of the centre nearest to point (dimension coordinates), ties to the lowest index.
std::uint32_t nearest_centre(const double* point, const std::vector<double>& centres,
                             int dimension);

}  // namespace oer::detail
