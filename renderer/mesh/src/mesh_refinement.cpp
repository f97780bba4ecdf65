// Refinement of coarse meshes for per-vertex transfer (see oer/mesh/mesh_refinement.hpp): passes
// of midpoint splits of the edges that are too long, with red-green templates per triangle.
#include "oer/mesh/mesh_refinement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace oer {

namespace {

// Segments along the bounds' diagonal (mesh_refinement.hpp says why 16).
constexpr double kEdgesPerDiagonal = 16.0;

// How much longer than the target an edge must be to be split. Edges of exactly the target's
// length are common (the cells of a rectangle halved 4 times have its diagonal / 16 as their
// diagonal), and float positions, rounded at every midpoint, must not decide them either way.
constexpr double kLengthTolerance = 1e-6;

// An undirected edge of a primitive: its two vertex indices, the lower first.
struct Edge {
    std::uint32_t low;
    std::uint32_t high;
};

Edge make_edge(std::uint32_t a, std::uint32_t b) {
    return a < b ? Edge{a, b} : Edge{b, a};
}

std::uint64_t edge_key(const Edge& edge) {
    return (std::uint64_t(edge.low) << 32) | edge.high;
}

// Computed in double from the floats, so that the result does not depend on the order of the
// ends: the two triangles on either side of an edge, whichever indices they use, decide alike.
double squared_distance(const glm::vec3& a, const glm::vec3& b) {
    const glm::dvec3 d = glm::dvec3(a) - glm::dvec3(b);
    return glm::dot(d, d);
}

// The exact midpoint, rounded once (and the same for either order of the ends).
glm::vec3 midpoint(const glm::vec3& a, const glm::vec3& b) {
    return glm::vec3(0.5 * (glm::dvec3(a) + glm::dvec3(b)));
}

glm::vec2 midpoint(const glm::vec2& a, const glm::vec2& b) {
    return glm::vec2(0.5 * (glm::dvec2(a) + glm::dvec2(b)));
}

glm::vec4 midpoint(const glm::vec4& a, const glm::vec4& b) {
    return glm::vec4(0.5 * (glm::dvec4(a) + glm::dvec4(b)));
}

// The direction halfway between two unit vectors; `fallback` where they are opposite.
glm::vec3 halfway_direction(const glm::vec3& a, const glm::vec3& b, const glm::vec3& fallback) {
    const glm::vec3 sum = a + b;
    const float length = glm::length(sum);
    return length > 1e-6f ? sum / length : fallback;
}

bool needs_split(const Primitive& primitive, const Edge& edge, double max_squared_length) {
    const glm::vec3& a = primitive.positions[edge.low];
    const glm::vec3& b = primitive.positions[edge.high];
    if (!(squared_distance(a, b) > max_squared_length)) {
        return false;
    }
    const glm::vec3 middle = midpoint(a, b);
    return middle != a && middle != b;
}

// One pass's splits in one primitive: the midpoint vertex of every edge to split, numbered
// after the primitive's vertices in the order the edges were first met (deterministic).
struct PassSplits {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoint_of;
    std::vector<Edge> edges;  // in the order of their midpoints' indices
    std::uint64_t triangles_added = 0;
    double longest_squared = 0.0;  // of the edges to split
};

PassSplits plan_pass(const Primitive& primitive, double max_squared_length) {
    PassSplits splits;
    const auto first_new = std::uint32_t(primitive.positions.size());
    const std::vector<std::uint32_t>& indices = primitive.indices;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            const Edge edge = make_edge(indices[t + k], indices[t + (k + 1) % 3]);
            if (!needs_split(primitive, edge, max_squared_length)) {
                continue;
            }
            ++splits.triangles_added;  // each split edge of a triangle adds one triangle
            const auto [it, inserted] = splits.midpoint_of.try_emplace(
                edge_key(edge), first_new + std::uint32_t(splits.edges.size()));
            if (inserted) {
                splits.edges.push_back(edge);
                splits.longest_squared = std::max(splits.longest_squared,
                                                  squared_distance(primitive.positions[edge.low],
                                                                   primitive.positions[edge.high]));
            }
        }
    }
    return splits;
}

void add_midpoint_vertex(Primitive& primitive, const Edge& edge) {
    const std::uint32_t a = edge.low;
    const std::uint32_t b = edge.high;
    primitive.positions.push_back(midpoint(primitive.positions[a], primitive.positions[b]));
    if (!primitive.normals.empty()) {
        primitive.normals.push_back(
            halfway_direction(primitive.normals[a], primitive.normals[b], primitive.normals[a]));
    }
    if (!primitive.texcoords.empty()) {
        primitive.texcoords.push_back(midpoint(primitive.texcoords[a], primitive.texcoords[b]));
    }
    if (!primitive.colors.empty()) {
        primitive.colors.push_back(midpoint(primitive.colors[a], primitive.colors[b]));
    }
    if (!primitive.texcoords1.empty()) {
        primitive.texcoords1.push_back(midpoint(primitive.texcoords1[a], primitive.texcoords1[b]));
    }
    if (!primitive.tangents.empty()) {
        const glm::vec4& ta = primitive.tangents[a];
        const glm::vec4& tb = primitive.tangents[b];
        primitive.tangents.emplace_back(
            halfway_direction(glm::vec3(ta), glm::vec3(tb), glm::vec3(ta)), ta.w);
    }
}

// The triangle (corner[0], corner[1], corner[2]) with middle[k] the midpoint of the edge from
// corner k to corner k + 1 (or -1: not split), replaced by the triangles of its template, each
// counter-clockwise where the parent is.
void split_triangle(const Primitive& primitive, std::array<std::uint32_t, 3> corner,
                    std::array<std::int64_t, 3> middle, std::vector<std::uint32_t>& out) {
    const int split_count =
        int(std::count_if(middle.begin(), middle.end(), [](std::int64_t m) { return m >= 0; }));
    auto emit = [&out](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        out.insert(out.end(), {a, b, c});
    };
    // Turns the corners (keeping the winding) until edge 0 is the one the template starts from:
    // the split edge when one is, the unsplit edge when two are.
    auto rotate_until = [&](auto&& edge_0_is_right) {
        while (!edge_0_is_right()) {
            std::rotate(corner.begin(), corner.begin() + 1, corner.end());
            std::rotate(middle.begin(), middle.begin() + 1, middle.end());
        }
    };
    switch (split_count) {
        case 0:
            emit(corner[0], corner[1], corner[2]);
            return;
        case 1: {
            rotate_until([&] { return middle[0] >= 0; });
            const auto m = std::uint32_t(middle[0]);
            emit(corner[0], m, corner[2]);
            emit(m, corner[1], corner[2]);
            return;
        }
        case 2: {
            rotate_until([&] { return middle[0] < 0; });
            const std::uint32_t a = corner[0];
            const std::uint32_t b = corner[1];
            const std::uint32_t c = corner[2];
            const auto m_bc = std::uint32_t(middle[1]);
            const auto m_ca = std::uint32_t(middle[2]);
            emit(m_bc, c, m_ca);
            // The quadrilateral a, b, m_bc, m_ca, cut along its shorter diagonal.
            const std::vector<glm::vec3>& p = primitive.positions;
            if (squared_distance(p[a], p[m_bc]) <= squared_distance(p[b], p[m_ca])) {
                emit(a, b, m_bc);
                emit(a, m_bc, m_ca);
            } else {
                emit(a, b, m_ca);
                emit(b, m_bc, m_ca);
            }
            return;
        }
        default: {
            const auto m_ab = std::uint32_t(middle[0]);
            const auto m_bc = std::uint32_t(middle[1]);
            const auto m_ca = std::uint32_t(middle[2]);
            emit(corner[0], m_ab, m_ca);
            emit(m_ab, corner[1], m_bc);
            emit(m_ca, m_bc, corner[2]);
            emit(m_ab, m_bc, m_ca);
            return;
        }
    }
}

void apply_pass(Primitive& primitive, const PassSplits& splits) {
    for (const Edge& edge : splits.edges) {
        add_midpoint_vertex(primitive, edge);
    }
    const std::vector<std::uint32_t>& indices = primitive.indices;
    std::vector<std::uint32_t> refined;
    refined.reserve(indices.size() + 3 * splits.triangles_added);
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        const std::array<std::uint32_t, 3> corner{indices[t], indices[t + 1], indices[t + 2]};
        std::array<std::int64_t, 3> middle{-1, -1, -1};
        for (int k = 0; k < 3; ++k) {
            const auto found =
                splits.midpoint_of.find(edge_key(make_edge(corner[k], corner[(k + 1) % 3])));
            if (found != splits.midpoint_of.end()) {
                middle[k] = found->second;
            }
        }
        split_triangle(primitive, corner, middle, refined);
    }
    primitive.indices = std::move(refined);
}

}  // namespace

double transfer_edge_length(const Bounds& bounds) {
    return glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) / kEdgesPerDiagonal;
}

MeshRefinement refine_mesh(Mesh& mesh, double max_edge_length, const MeshLimits& limits) {
    const std::uint64_t max_vertices = std::min(limits.max_refined_vertices, limits.max_vertices);
    const double max_squared_length =
        max_edge_length * max_edge_length * (1.0 + kLengthTolerance) * (1.0 + kLengthTolerance);
    std::uint64_t vertices = 0;
    std::uint64_t triangles = 0;
    for (const Primitive& primitive : mesh.primitives) {
        vertices += primitive.positions.size();
        triangles += primitive.indices.size() / 3;
    }
    MeshRefinement result;
    for (;;) {
        // Planned for every primitive before any is changed, so that a pass is made everywhere
        // or nowhere: primitives meeting along an edge then split it alike.
        std::vector<PassSplits> plans;
        std::uint64_t new_vertices = 0;
        std::uint64_t new_triangles = 0;
        double longest_squared = 0.0;
        for (const Primitive& primitive : mesh.primitives) {
            plans.push_back(plan_pass(primitive, max_squared_length));
            new_vertices += plans.back().edges.size();
            new_triangles += plans.back().triangles_added;
            longest_squared = std::max(longest_squared, plans.back().longest_squared);
        }
        if (new_vertices == 0) {
            return result;
        }
        if (vertices + new_vertices > max_vertices ||
            triangles + new_triangles > limits.max_triangles) {
            result.stopped_early = true;
            mesh.warnings.push_back(
                "refined for per-vertex lighting to " + std::to_string(vertices) +
                " vertices and " + std::to_string(triangles) +
                " triangles only (the next pass would pass the limit of " +
                std::to_string(max_vertices) + " vertices or " +
                std::to_string(limits.max_triangles) + " triangles): edges up to " +
                std::to_string(std::sqrt(longest_squared)) + " remain, longer than " +
                std::to_string(max_edge_length));
            return result;
        }
        for (std::size_t i = 0; i < plans.size(); ++i) {
            apply_pass(mesh.primitives[i], plans[i]);
        }
        vertices += new_vertices;
        triangles += new_triangles;
        result.vertices_added += new_vertices;
        result.triangles_added += new_triangles;
        ++result.passes;
    }
}

}  // namespace oer
