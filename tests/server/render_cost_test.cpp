// The estimate of a render's cost before it runs (server/src/render_cost.hpp), part by part
// against the rules it states, and the refusal that names the budget it is over.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "http_errors.hpp"
#include "oer/scene/scene_transfer.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "render_cost.hpp"

using namespace oer;
using namespace oer::server;

namespace {

api::RenderSpec spec_of(int objects) {
    api::RenderSpec spec;
    spec.objects.resize(std::size_t(objects));
    spec.width = 100;
    spec.height = 50;
    spec.samples = 2;
    spec.shadows.resolution = 1024;
    return spec;
}

constexpr MeshSummary kTexturedMesh{1000, 600, 3 << 20, 5 << 20, 4};
constexpr MeshSummary kPlainMesh{20000, 10000, 0, 1 << 20, 1};

}  // namespace

TEST(RenderCost, EachPartFollowsItsRule) {
    api::RenderSpec spec = spec_of(3);
    spec.occlusion = true;
    spec.bounce = Bounce::One;
    // Two copies of the textured mesh and one plain one, under a rig of 3 lights.
    const RenderCost cost = estimate_render_cost(spec, {kTexturedMesh, kTexturedMesh, kPlainMesh},
                                                 {"a", "a", "b"}, 3, 1e6);
    // Distinct meshes once; the textures again, with mipmaps, as GL holds them.
    EXPECT_EQ(cost.mesh_bytes, (5u << 20) + (1u << 20));
    EXPECT_EQ(cost.texture_bytes, 3u << 20);
    EXPECT_EQ(cost.gl_texture_bytes, 4u << 20);
    EXPECT_EQ(cost.target_bytes, 100u * 50 * 2 * kTargetBytesPerSample);
    EXPECT_EQ(cost.shadow_bytes, 3u * 1024 * 1024 * 4);
    // Every object's vertices and the ground's grid, each order^2 floats for its direct vector
    // and as many per bounce vector: the ground's, each textured object's Native and Unit
    // slots (4), the plain one's material (1).
    const std::uint64_t points = transfer_point_count(600 + 600 + 10000);
    EXPECT_EQ(cost.transfer_bytes, points * kTransferBakeOrder * kTransferBakeOrder *
                                       (1 + 1 + 4 + 4 + 1) * sizeof(float));
    // Every triangle drawn by the geometry pass, 3 shadow maps and the ground's visibility.
    EXPECT_DOUBLE_EQ(cost.draw_seconds, 22000.0 * 5 / kTrianglesPerSecond);
    EXPECT_DOUBLE_EQ(cost.shade_seconds, 100.0 * 50 * 2 * 4 / kSampleLightsPerSecond);
    const double rays = double(points) * transfer_ray_count(11200, 1e6);
    EXPECT_DOUBLE_EQ(cost.bake_seconds,
                     double(points) * kBakeSecondsPerPoint + 2.0 * rays / kRaysPerSecond);
    EXPECT_EQ(cost.memory_bytes(), cost.mesh_bytes + cost.gl_texture_bytes + cost.target_bytes +
                                       cost.shadow_bytes + cost.transfer_bytes);
}

// Past kMaxSeparateReflectors objects, one group of slots per mesh and colour.
TEST(RenderCost, ManyObjectsShareReflectorSlotsByMeshAndColour) {
    api::RenderSpec spec = spec_of(9);
    spec.occlusion = true;
    spec.bounce = Bounce::One;
    for (std::size_t i = 0; i < 9; ++i) {
        if (i % 2 == 1) {
            spec.objects[i].base_color = glm::dvec3(1.0, 0.0, 0.0);
        }
    }
    const RenderCost cost = estimate_render_cost(spec, std::vector<MeshSummary>(9, kPlainMesh),
                                                 std::vector<std::string>(9, "b"), 0, 1e6);
    // The ground's vector; the uncoloured and the red copies' material.
    const std::uint64_t points = transfer_point_count(9 * 10000);
    EXPECT_EQ(cost.transfer_bytes,
              points * kTransferBakeOrder * kTransferBakeOrder * (1 + 1 + 2) * sizeof(float));
    spec.bounce = Bounce::None;
    EXPECT_EQ(estimate_render_cost(spec, std::vector<MeshSummary>(9, kPlainMesh),
                                   std::vector<std::string>(9, "b"), 0, 1e6)
                  .transfer_bytes,
              points * kTransferBakeOrder * kTransferBakeOrder * sizeof(float));
}

TEST(RenderCost, LightsSwitchedOffAndShadowsOffDrawNoShadowMap) {
    api::RenderSpec spec = spec_of(1);
    spec.occlusion = false;
    spec.lights = {1.0, 0.0, 0.5};
    const RenderCost some = estimate_render_cost(spec, {kPlainMesh}, {"b"}, 3, 1e6);
    EXPECT_EQ(some.shadow_bytes, 2u * 1024 * 1024 * 4);
    EXPECT_EQ(some.transfer_bytes, 0u);
    EXPECT_EQ(some.bake_seconds, 0.0);
    spec.shadows.enabled = false;
    const RenderCost none = estimate_render_cost(spec, {kPlainMesh}, {"b"}, 3, 1e6);
    EXPECT_EQ(none.shadow_bytes, 0u);
    EXPECT_DOUBLE_EQ(none.draw_seconds, 20000.0 * 2 / kTrianglesPerSecond);
}

TEST(RenderCost, ARefusalNamesTheBudgetItIsOverAndItsFigures) {
    RenderCost cost;
    cost.shadow_bytes = 3ull << 30;
    RenderBudgets budgets;
    try {
        check_render_cost(cost, budgets);
        FAIL() << "3 GiB of shadow maps passed a 2 GiB budget";
    } catch (const HttpError& refusal) {
        EXPECT_EQ(refusal.problem().kind, ProblemKind::LimitExceeded);
        const std::string detail = refusal.problem().detail;
        EXPECT_NE(detail.find("3072 MiB of memory"), std::string::npos) << detail;
        EXPECT_NE(detail.find("budget of 2048 MiB"), std::string::npos) << detail;
        EXPECT_EQ(refusal.problem().extensions.at("estimate").at("memory_bytes"), 3ull << 30);
        EXPECT_EQ(refusal.problem().extensions.at("budget").at("memory_bytes"), 2ull << 30);
    }
    cost.shadow_bytes = 0;
    cost.bake_seconds = 31.0;
    EXPECT_THROW(check_render_cost(cost, budgets), HttpError);
    cost.bake_seconds = 29.0;
    EXPECT_NO_THROW(check_render_cost(cost, budgets));
}
