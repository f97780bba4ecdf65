// Refinement for per-vertex transfer (renderer/mesh, oer/mesh/mesh_refinement.hpp): no edge
// longer than the rule's length, the same surface with the same orientation, closed meshes kept
// closed (seams of duplicated vertices included), midpoints interpolating every attribute, the
// vertex cap, and the loaders applying it (glTF, the default product) while leaving a dense
// mesh (the Stanford bunny of glmark2-data) almost as it is.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gltf_test_assets.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/mesh/mesh_refinement.hpp"
#include "test_meshes.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

const glm::vec3 kGrey(0.5f);

// A unit cube of 8 corners shared by its 12 triangles (a closed surface through its indices),
// counter-clockwise seen from outside, with the smooth normals of its corners.
Mesh shared_corner_cube() {
    Primitive cube;
    cube.name = "cube";
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1));
        cube.positions.push_back(corner);
        cube.normals.push_back(glm::normalize(corner - glm::vec3(0.5f)));
    }
    const std::array<std::array<std::uint32_t, 4>, 6> faces{{
        {0, 2, 3, 1},  // z = 0
        {4, 5, 7, 6},  // z = 1
        {0, 1, 5, 4},  // y = 0
        {2, 6, 7, 3},  // y = 1
        {0, 4, 6, 2},  // x = 0
        {1, 3, 7, 5},  // x = 1
    }};
    for (const auto& [a, b, c, d] : faces) {
        cube.indices.insert(cube.indices.end(), {a, b, c, a, c, d});
    }
    Mesh mesh;
    mesh.primitives.push_back(std::move(cube));
    mesh.materials.push_back(oer::testing::lambertian(kGrey));
    oer::testing::finish(mesh);
    return mesh;
}

std::array<glm::dvec3, 3> corners(const Primitive& p, std::size_t triangle) {
    return {glm::dvec3(p.positions[p.indices[3 * triangle]]),
            glm::dvec3(p.positions[p.indices[3 * triangle + 1]]),
            glm::dvec3(p.positions[p.indices[3 * triangle + 2]])};
}

std::size_t triangle_count(const Primitive& p) {
    return p.indices.size() / 3;
}

double area(const Primitive& p, std::size_t triangle) {
    const auto [a, b, c] = corners(p, triangle);
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

double total_area(const Mesh& mesh) {
    double sum = 0.0;
    for (const Primitive& p : mesh.primitives) {
        for (std::size_t t = 0; t < triangle_count(p); ++t) {
            sum += area(p, t);
        }
    }
    return sum;
}

double longest_edge(const Mesh& mesh) {
    double longest = 0.0;
    for (const Primitive& p : mesh.primitives) {
        for (std::size_t t = 0; t < triangle_count(p); ++t) {
            const auto [a, b, c] = corners(p, t);
            longest =
                std::max({longest, glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
        }
    }
    return longest;
}

// The distance from x to the triangle (a, b, c): C. Ericson, "Real-Time Collision Detection",
// 2005, section 5.1.5, the closest point by the Voronoi regions of the triangle's features.
double distance_to_triangle(const glm::dvec3& x, const glm::dvec3& a, const glm::dvec3& b,
                            const glm::dvec3& c) {
    const glm::dvec3 ab = b - a;
    const glm::dvec3 ac = c - a;
    const glm::dvec3 ax = x - a;
    const double d1 = glm::dot(ab, ax);
    const double d2 = glm::dot(ac, ax);
    if (d1 <= 0.0 && d2 <= 0.0) {
        return glm::distance(x, a);
    }
    const glm::dvec3 bx = x - b;
    const double d3 = glm::dot(ab, bx);
    const double d4 = glm::dot(ac, bx);
    if (d3 >= 0.0 && d4 <= d3) {
        return glm::distance(x, b);
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        return glm::distance(x, a + d1 / (d1 - d3) * ab);
    }
    const glm::dvec3 cx = x - c;
    const double d5 = glm::dot(ab, cx);
    const double d6 = glm::dot(ac, cx);
    if (d6 >= 0.0 && d5 <= d6) {
        return glm::distance(x, c);
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        return glm::distance(x, a + d2 / (d2 - d6) * ac);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        return glm::distance(x, b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b));
    }
    const double denominator = 1.0 / (va + vb + vc);
    return glm::distance(x, a + ab * (vb * denominator) + ac * (vc * denominator));
}

// The distance from x to the nearest triangle of `original`.
double distance_to_surface(const Primitive& original, const glm::dvec3& x) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < triangle_count(original); ++t) {
        const auto [a, b, c] = corners(original, t);
        nearest = std::min(nearest, distance_to_triangle(x, a, b, c));
    }
    return nearest;
}

glm::dvec3 unit_normal(const Primitive& p, std::size_t triangle) {
    const auto [a, b, c] = corners(p, triangle);
    return glm::normalize(glm::cross(b - a, c - a));
}

// Each undirected edge (by vertex index) and how often each direction is used.
std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<int, int>> edge_uses(
    const std::vector<std::uint32_t>& indices) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<int, int>> uses;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t from = indices[t + k];
            const std::uint32_t to = indices[t + (k + 1) % 3];
            auto& [forward, backward] = uses[{std::min(from, to), std::max(from, to)}];
            ++(from < to ? forward : backward);
        }
    }
    return uses;
}

// The indices with every vertex replaced by the first vertex at its position: the surface as
// its positions connect it, whatever vertices were duplicated for their attributes.
std::vector<std::uint32_t> welded_indices(const Primitive& p) {
    std::map<std::tuple<float, float, float>, std::uint32_t> first_at;
    std::vector<std::uint32_t> welded;
    for (std::uint32_t index : p.indices) {
        const glm::vec3& v = p.positions[index];
        welded.push_back(first_at.try_emplace({v.x, v.y, v.z}, index).first->second);
    }
    return welded;
}

// Closed and consistently wound: every edge used once in each direction.
void expect_closed(const std::vector<std::uint32_t>& indices) {
    std::size_t open_or_reused = 0;
    for (const auto& [edge, use] : edge_uses(indices)) {
        open_or_reused += use == std::pair{1, 1} ? 0 : 1;
    }
    EXPECT_EQ(open_or_reused, 0u);
}

TEST(MeshRefinement, TheTargetIsASixteenthOfTheBoundsDiagonal) {
    EXPECT_DOUBLE_EQ(transfer_edge_length(Bounds{glm::vec3(-0.5f), glm::vec3(0.5f)}),
                     std::sqrt(3.0) / 16.0);
    EXPECT_DOUBLE_EQ(transfer_edge_length(Bounds{{0, 0, 0}, {3, 0, 4}}), 5.0 / 16.0);
    EXPECT_EQ(transfer_edge_length(Bounds{glm::vec3(2.0f), glm::vec3(2.0f)}), 0.0);
}

TEST(MeshRefinement, EveryEdgeOfAUnitBoxIsAtMostTheTargetAndItsFacesAreEvenGrids) {
    Mesh box = oer::testing::box(glm::vec3(-0.5f), glm::vec3(0.5f), kGrey);
    ASSERT_EQ(box.primitives[0].positions.size(), 24u);
    const double target = transfer_edge_length(box.bounds);
    ASSERT_GT(longest_edge(box), target);
    const MeshRefinement refinement = refine_mesh(box, target, MeshLimits{});
    EXPECT_LE(longest_edge(box), target);
    EXPECT_FALSE(refinement.stopped_early);
    EXPECT_TRUE(box.warnings.empty());
    // Sides halved 4 times (1/16 <= sqrt(3)/16, and so is a square's diagonal, sqrt(2)/16):
    // 17 x 17 vertices and 16 x 16 x 2 triangles per face.
    EXPECT_EQ(refinement.passes, 4);
    EXPECT_EQ(box.primitives[0].positions.size(), 6u * 17u * 17u);
    EXPECT_EQ(triangle_count(box.primitives[0]), 6u * 16u * 16u * 2u);
    EXPECT_EQ(refinement.vertices_added, 6u * 17u * 17u - 24u);
    EXPECT_EQ(refinement.triangles_added, 6u * 16u * 16u * 2u - 12u);
}

TEST(MeshRefinement, TheRefinedSurfaceIsTheSameSurface) {
    const std::vector<Mesh> originals{oer::testing::box(glm::vec3(-0.5f), glm::vec3(0.5f), kGrey),
                                      shared_corner_cube(),
                                      // Not flat anywhere, with degenerate triangles at the poles.
                                      oer::testing::uv_sphere({1, 2, 3}, 2.0f, 7, 4, kGrey)};
    for (const Mesh& original : originals) {
        SCOPED_TRACE(original.primitives[0].name);
        Mesh refined = original;
        refine_mesh(refined, transfer_edge_length(original.bounds), MeshLimits{});
        const Primitive& before = original.primitives[0];
        const Primitive& after = refined.primitives[0];
        ASSERT_GT(after.positions.size(), 10 * before.positions.size());
        // The original vertices first, unchanged; every new one on an original triangle.
        ASSERT_TRUE(
            std::equal(before.positions.begin(), before.positions.end(), after.positions.begin()));
        double farthest = 0.0;
        for (std::size_t i = before.positions.size(); i < after.positions.size(); ++i) {
            farthest =
                std::max(farthest, distance_to_surface(before, glm::dvec3(after.positions[i])));
        }
        EXPECT_LT(farthest, 1e-6);
        EXPECT_NEAR(total_area(refined), total_area(original), 1e-6 * total_area(original));
    }
}

TEST(MeshRefinement, EachTriangleFacesAsItsParent) {
    for (Mesh original :
         {shared_corner_cube(), oer::testing::uv_sphere({0, 0, 0}, 1.0f, 7, 4, kGrey)}) {
        SCOPED_TRACE(original.primitives[0].name);
        Mesh refined = original;
        refine_mesh(refined, transfer_edge_length(original.bounds), MeshLimits{});
        const Primitive& before = original.primitives[0];
        const Primitive& after = refined.primitives[0];
        std::size_t turned = 0;
        for (std::size_t t = 0; t < triangle_count(after); ++t) {
            if (area(after, t) < 1e-9) {
                continue;  // a child of the sphere's degenerate triangles at its poles (zero
                           // area but for the rounding of its corners, and no direction)
            }
            // Its parent: the original triangle that holds its three corners (a neighbour
            // holds two at most, unless coplanar, when it faces the same way).
            const auto [a, b, c] = corners(after, t);
            std::size_t parent = triangle_count(before);
            for (std::size_t o = 0; o < triangle_count(before) && parent == triangle_count(before);
                 ++o) {
                const auto [p, q, r] = corners(before, o);
                if (std::max({distance_to_triangle(a, p, q, r), distance_to_triangle(b, p, q, r),
                              distance_to_triangle(c, p, q, r)}) < 1e-6) {
                    parent = o;
                }
            }
            ASSERT_LT(parent, triangle_count(before)) << "triangle " << t;
            turned += glm::dot(unit_normal(after, t), unit_normal(before, parent)) > 0.999 ? 0 : 1;
        }
        EXPECT_EQ(turned, 0u);
    }
}

TEST(MeshRefinement, AClosedSurfaceStaysClosed) {
    Mesh cube = shared_corner_cube();
    expect_closed(cube.primitives[0].indices);
    refine_mesh(cube, transfer_edge_length(cube.bounds), MeshLimits{});
    const Primitive& p = cube.primitives[0];
    expect_closed(p.indices);
    // A sphere's Euler characteristic, V - E + F = 2, and the 16 x 16 grids of the faces
    // sharing the cube's edges and corners: 8 + 12 x 15 + 6 x 15 x 15 vertices.
    const auto edges = std::int64_t(edge_uses(p.indices).size());
    EXPECT_EQ(std::int64_t(p.positions.size()) - edges + std::int64_t(triangle_count(p)), 2);
    EXPECT_EQ(p.positions.size(), 8u + 12u * 15u + 6u * 15u * 15u);
}

TEST(MeshRefinement, SeamsOfDuplicatedVerticesGetNoTJunction) {
    // The box's faces share no vertex: only their positions meet, and must still meet after.
    Mesh box = oer::testing::box(glm::vec3(-0.5f), glm::vec3(0.5f), kGrey);
    expect_closed(welded_indices(box.primitives[0]));
    refine_mesh(box, transfer_edge_length(box.bounds), MeshLimits{});
    expect_closed(welded_indices(box.primitives[0]));
    // Two primitives meeting along an edge of different lengths of triangles: a long thin one
    // and a fan of short ones. Both split the shared edge at the same positions.
    Mesh pair;
    Primitive thin;
    thin.name = "thin";
    thin.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 0.05f, 0}};
    thin.indices = {0, 1, 2};
    Primitive wide = thin;
    wide.name = "wide";
    wide.positions = {{1, 0, 0}, {0, 0, 0}, {0.5f, -1, 0}};
    pair.primitives = {thin, wide};
    for (Primitive& p : pair.primitives) {
        p.normals.assign(3, glm::vec3(0, 0, 1));
    }
    refine_mesh(pair, 0.1, MeshLimits{});
    Primitive joined = pair.primitives[0];
    const auto offset = std::uint32_t(joined.positions.size());
    const Primitive& second = pair.primitives[1];
    joined.positions.insert(joined.positions.end(), second.positions.begin(),
                            second.positions.end());
    for (std::uint32_t index : second.indices) {
        joined.indices.push_back(offset + index);
    }
    // Every welded edge on y = 0 used once from each side: the same points on both.
    std::size_t unmatched = 0;
    const std::vector<std::uint32_t> welded = welded_indices(joined);
    for (const auto& [edge, use] : edge_uses(welded)) {
        const bool on_seam =
            joined.positions[edge.first].y == 0.0f && joined.positions[edge.second].y == 0.0f;
        unmatched += on_seam && use != std::pair{1, 1} ? 1 : 0;
    }
    EXPECT_EQ(unmatched, 0u);
}

TEST(MeshRefinement, MidpointsInterpolateEveryAttribute) {
    // A 2 x 2 square (sides 2, diagonal 2 sqrt 2) with a target of 1.9: one pass splits all
    // five edges at their midpoints, the next none.
    Mesh quad = oer::testing::quad({0, 0, 0}, 1.0f, kGrey);
    Primitive& p = quad.primitives[0];
    p.texcoords = {{0.1f, 0.7f}, {0.33f, 0.2f}, {0.9f, 0.45f}, {0.05f, 0.61f}};
    p.texcoords1 = {{0.5f, 0.25f}, {0.75f, 0.125f}, {0.0f, 1.0f}, {0.375f, 0.5f}};
    p.colors = {{1, 0, 0, 1}, {0, 0.5f, 0, 0.25f}, {0, 0, 1, 0.5f}, {0.25f, 0.75f, 0.5f, 1}};
    p.normals = {glm::normalize(glm::vec3(0.1f, 0, 1)), glm::normalize(glm::vec3(0, 0.2f, 1)),
                 glm::vec3(0, 0, 1), glm::normalize(glm::vec3(-0.3f, 0.1f, 1))};
    p.tangents = {{1, 0, 0, 1}, {0, 1, 0, 1}, {1, 0, 0, -1}, {1, 0, 0, 1}};
    const Primitive original = p;
    const MeshRefinement refinement = refine_mesh(quad, 1.9, MeshLimits{});
    EXPECT_EQ(refinement.passes, 1);
    ASSERT_EQ(p.positions.size(), 4u + 5u);
    ASSERT_EQ(p.normals.size(), 9u);
    ASSERT_EQ(p.texcoords.size(), 9u);
    ASSERT_EQ(p.texcoords1.size(), 9u);
    ASSERT_EQ(p.colors.size(), 9u);
    ASSERT_EQ(p.tangents.size(), 9u);
    for (std::size_t i = 4; i < 9; ++i) {
        // Its ends: the original edge whose midpoint it is.
        std::size_t found = 0;
        for (const auto& [edge, use] : edge_uses(original.indices)) {
            const auto [a, b] = edge;
            if (p.positions[i] != (original.positions[a] + original.positions[b]) * 0.5f) {
                continue;
            }
            ++found;
            SCOPED_TRACE("midpoint of " + std::to_string(a) + " and " + std::to_string(b));
            EXPECT_EQ(p.texcoords[i], (original.texcoords[a] + original.texcoords[b]) * 0.5f);
            EXPECT_EQ(p.texcoords1[i], (original.texcoords1[a] + original.texcoords1[b]) * 0.5f);
            EXPECT_EQ(p.colors[i], (original.colors[a] + original.colors[b]) * 0.5f);
            const glm::vec3 normal = glm::normalize(original.normals[a] + original.normals[b]);
            EXPECT_NEAR(glm::distance(p.normals[i], normal), 0.0f, 1e-6f);
            const glm::vec3 tangent =
                glm::normalize(glm::vec3(original.tangents[a]) + glm::vec3(original.tangents[b]));
            EXPECT_NEAR(glm::distance(glm::vec3(p.tangents[i]), tangent), 0.0f, 1e-6f);
            // The lower-indexed end's sign where the two differ (vertex 2's is -1).
            EXPECT_EQ(p.tangents[i].w, original.tangents[a].w);
        }
        EXPECT_EQ(found, 1u) << "vertex " << i;
    }
}

TEST(MeshRefinement, TheVertexCapStopsRefinementWithAWarning) {
    // The unit box: 24 vertices, then 24 + 6 x 5 = 54 after the first pass, and 6 x 5 x 5 = 150
    // after the second, beyond a cap of 100: it stops at 54, still without T-junctions.
    MeshLimits limits;
    limits.max_refined_vertices = 100;
    Mesh box = oer::testing::box(glm::vec3(-0.5f), glm::vec3(0.5f), kGrey);
    const double target = transfer_edge_length(box.bounds);
    const MeshRefinement refinement = refine_mesh(box, target, limits);
    EXPECT_TRUE(refinement.stopped_early);
    EXPECT_EQ(refinement.passes, 1);
    EXPECT_EQ(box.primitives[0].positions.size(), 54u);
    EXPECT_GT(longest_edge(box), target);
    expect_closed(welded_indices(box.primitives[0]));
    ASSERT_EQ(box.warnings.size(), 1u);
    EXPECT_EQ(box.warnings[0].find("refined for per-vertex lighting to 54 vertices and 48 "
                                   "triangles only (the next pass would pass the limit of 100 "
                                   "vertices or 5000000 triangles): edges up to 0.707107 remain"),
              0u)
        << box.warnings[0];

    // The triangle limit stops it too; through a loader, the mesh loads with the warning.
    limits = MeshLimits{};
    limits.max_triangles = 500;
    const Mesh loaded = load_obj_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", limits);
    expect_valid(loaded);
    EXPECT_EQ(loaded.triangle_count, 2u * 4u * 4u * 4u);  // three 1-to-4 passes; a fourth: 512
    ASSERT_EQ(loaded.warnings.size(), 1u);
    EXPECT_NE(loaded.warnings[0].find("or 500 triangles"), std::string::npos) << loaded.warnings[0];
    // Without the limit, a fourth pass, and no more: the cells' diagonals, 1/16 of the square's,
    // are the target itself, and are not split again.
    EXPECT_EQ(load_obj_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").triangle_count,
              2u * 16u * 16u);
}

TEST(MeshRefinementGltf, ABoxLoadsRefinedWithItsAttributes) {
    // The box of 24 vertices as a glTF asset, with normals and texture coordinates.
    const Mesh source = oer::testing::box(glm::vec3(0.0f), glm::vec3(1.0f), kGrey);
    const Primitive& box = source.primitives[0];
    std::vector<glm::vec2> uv;
    for (const glm::vec3& p : box.positions) {
        uv.emplace_back(p.x + 0.5f * p.z, p.y);
    }
    GltfBuilder b;
    json primitive = {{"attributes",
                       {{"POSITION", b.positions(box.positions)},
                        {"NORMAL", b.positions(box.normals)},
                        {"TEXCOORD_0", b.accessor(b.view(uv.data(), uv.size() * sizeof(glm::vec2)),
                                                  kFloat, uv.size(), "VEC2")}}}};
    primitive["indices"] = b.indices(box.indices, kUnsignedInt);
    b.mesh(json::array({primitive}), "Box");
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf());
    expect_valid(mesh);
    EXPECT_TRUE(mesh.warnings.empty());
    EXPECT_LE(longest_edge(mesh), transfer_edge_length(mesh.bounds));
    EXPECT_EQ(mesh.vertex_count, 6u * 17u * 17u);
    EXPECT_EQ(mesh.triangle_count, 6u * 16u * 16u * 2u);
    const Primitive& p = mesh.primitives[0];
    ASSERT_EQ(p.texcoords.size(), p.positions.size());
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
        // Affine in the position on each face, so interpolated exactly (up to rounding).
        const glm::vec2 expected(p.positions[i].x + 0.5f * p.positions[i].z, p.positions[i].y);
        EXPECT_NEAR(glm::distance(p.texcoords[i], expected), 0.0f, 1e-6f) << "vertex " << i;
        // Each face's own normal, unchanged by the interpolation.
        const glm::vec3& n = p.normals[i];
        EXPECT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f) << "vertex " << i;
    }
}

TEST(MeshRefinement, TheDefaultProductHasNoEdgeLongerThanTheTarget) {
    const Mesh product = make_default_product();
    EXPECT_LE(longest_edge(product), transfer_edge_length(product.bounds));
    EXPECT_TRUE(product.warnings.empty());
}

TEST(MeshRefinementBunny, ADenseMeshGainsAlmostNoVertices) {
    const std::string path = "/usr/share/glmark2/models/bunny.obj";
    if (!std::filesystem::exists(path)) {
        GTEST_SKIP() << "*** glmark2-data is not installed: no " << path
                     << "; refinement of a dense mesh is NOT tested ***";
    }
    const Mesh file = load_mesh_file(path, kUnrefined);
    const Mesh refined = load_mesh_file(path);
    expect_valid(refined);
    EXPECT_LE(longest_edge(refined), transfer_edge_length(refined.bounds));
    const std::uint64_t gained = refined.vertex_count - file.vertex_count;
    RecordProperty("vertices_gained", std::to_string(gained));
    // 3 of 34,835: the few triangles that span the file's largest holes (under the bunny).
    EXPECT_LE(gained, file.vertex_count / 1000);
    EXPECT_EQ(refined.bounds.min, file.bounds.min);
    EXPECT_EQ(refined.bounds.max, file.bounds.max);
}

}  // namespace
