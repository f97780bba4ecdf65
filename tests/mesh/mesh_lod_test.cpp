// Levels of detail (renderer/mesh, oer/mesh/mesh_lod.hpp): each level
// is a real simplification whose stated error bounds its distance from the surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "oer/mesh/mesh_lod.hpp"
#include "test_meshes.hpp"

namespace {

using oer::LodIndices;
using oer::LodLevel;

TEST(MeshLod, LevelsHalveTheTrianglesAndTheirErrorBoundsTheirDistanceFromTheSphere) {
    const oer::Mesh sphere = oer::testing::uv_sphere({0, 0, 0}, 1.0f, 256, 128, glm::vec3(1.0f));
    const oer::Primitive& primitive = sphere.primitives.at(0);
    const LodIndices lods = oer::build_lods(primitive);
    ASSERT_GE(lods.levels.size(), 4u);
    EXPECT_EQ(lods.levels[0].index_count, primitive.indices.size());
    EXPECT_EQ(lods.levels[0].error, 0.0f);
    for (std::size_t l = 1; l < lods.levels.size(); ++l) {
        const LodLevel& level = lods.levels[l];
        const LodLevel& finer = lods.levels[l - 1];
        EXPECT_LT(double(level.index_count), 0.8 * finer.index_count) << "level " << l;
        EXPECT_GE(level.error, finer.error) << "level " << l;
        EXPECT_EQ(level.first_index, finer.first_index + finer.index_count) << "level " << l;
        // Every triangle's centroid lies within the stated error of the unit sphere (its
        // vertices are vertices of the full mesh, on the sphere).
        double worst = 0.0;
        for (std::uint32_t i = level.first_index; i < level.first_index + level.index_count;
             i += 3) {
            glm::dvec3 centroid{0.0};
            for (int corner = 0; corner < 3; ++corner) {
                const std::uint32_t vertex = lods.indices.at(i + std::uint32_t(corner));
                ASSERT_LT(vertex, primitive.positions.size());
                centroid += glm::dvec3(primitive.positions[vertex]) / 3.0;
            }
            worst = std::max(worst, 1.0 - glm::length(centroid));
        }
        EXPECT_LE(worst, level.error) << "level " << l;
        EXPECT_GT(worst, 0.1 * level.error) << "level " << l << ": the error is not tight";
    }
}

TEST(MeshLod, SmallPrimitivesKeepOneLevel) {
    const oer::Mesh box = oer::testing::box({0, 0, 0}, {1, 1, 1}, glm::vec3(1.0f));
    const LodIndices lods = oer::build_lods(box.primitives.at(0));
    ASSERT_EQ(lods.levels.size(), 1u);
    EXPECT_EQ(lods.levels[0].index_count, box.primitives[0].indices.size());
}

TEST(MeshLod, ChoiceIsTheCoarsestLevelWithinTheError) {
    const std::vector<LodLevel> levels{{0, 300, 0.0f}, {300, 150, 0.01f}, {450, 75, 0.04f}};
    EXPECT_EQ(oer::choose_lod(levels, 0.0f).index_count, 300u);
    EXPECT_EQ(oer::choose_lod(levels, 0.02f).index_count, 150u);
    EXPECT_EQ(oer::choose_lod(levels, 0.04f).index_count, 75u);
    EXPECT_EQ(oer::choose_lod(levels, -1.0f).index_count, 300u);
}

}  // namespace
