#include "oer/mesh/mesh_lod.hpp"

#include <algorithm>
#include <cmath>

#include <meshoptimizer.h>
#include <glm/geometric.hpp>

namespace oer {

namespace {
// Levels stop below this many triangles, or when a halving keeps more than 80 % of them.
constexpr std::size_t kSmallestLevelTriangles = 256;
constexpr double kLeastReduction = 0.8;
// The coarsest error allowed, relative to the primitive's extent: beyond it a level would
// only serve frames where the whole primitive is a few pixels tall.
constexpr float kLargestRelativeError = 0.05f;
// meshoptimizer's error is the distance to the planes of the triangles a vertex gathered, not
// to the surface: on a finely tessellated sphere the true deviation measured up to 4.2 times
// more (tests/mesh/mesh_lod_test.cpp), so levels claim five times it.
constexpr float kErrorSafetyFactor = 5.0f;
float longest_edge(const Primitive& primitive, const std::uint32_t* indices, std::size_t count) {
    float longest = 0.0f;
    for (std::size_t t = 0; t + 2 < count; t += 3) {
        for (int e = 0; e < 3; ++e) {
            const glm::vec3 d = primitive.positions[indices[t + std::size_t(e)]] -
                                primitive.positions[indices[t + std::size_t((e + 1) % 3)]];
            longest = std::max(longest, glm::dot(d, d));
        }
    }
    return std::sqrt(longest);
}

}  // namespace

LodIndices build_lods(const Primitive& primitive) {
    const std::size_t vertex_count = primitive.positions.size();
    const float* positions = &primitive.positions[0].x;
    constexpr std::size_t stride = sizeof(primitive.positions[0]);
    LodIndices lods;
    std::vector<std::uint32_t> full(primitive.indices.size());
    meshopt_optimizeVertexCache(full.data(), primitive.indices.data(), full.size(), vertex_count);
    lods.indices = full;
    lods.levels.push_back(
        {0, std::uint32_t(full.size()), 0.0f, longest_edge(primitive, full.data(), full.size())});
    if (full.size() < 3 * kSmallestLevelTriangles) {
        return lods;
    }
    const float scale = meshopt_simplifyScale(positions, vertex_count, stride);
    std::vector<std::uint32_t> level(full.size());
    std::size_t previous = full.size();
    while (previous / 3 >= 2 * kSmallestLevelTriangles) {
        float relative_error = 0.0f;
        // Each level simplifies the full primitive, so errors do not compound.
        const std::size_t count = meshopt_simplify(
            level.data(), full.data(), full.size(), positions, vertex_count, stride, previous / 2,
            kLargestRelativeError, meshopt_SimplifyLockBorder, &relative_error);
        if (double(count) > kLeastReduction * double(previous) || count == 0) {
            break;
        }
        meshopt_optimizeVertexCache(level.data(), level.data(), count, vertex_count);
        lods.levels.push_back({std::uint32_t(lods.indices.size()), std::uint32_t(count),
                               kErrorSafetyFactor * relative_error * scale,
                               longest_edge(primitive, level.data(), count)});
        lods.indices.insert(lods.indices.end(), level.begin(), level.begin() + long(count));
        previous = count;
    }
    return lods;
}

const LodLevel& choose_lod(const std::vector<LodLevel>& levels, float max_error, float max_edge) {
    const LodLevel* chosen = &levels.front();
    for (const LodLevel& level : levels) {
        if (level.error <= max_error && level.longest_edge <= max_edge) {
            chosen = &level;
        }
    }
    return *chosen;
}

}  // namespace oer
