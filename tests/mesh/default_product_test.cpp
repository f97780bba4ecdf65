// The built-in dress form: its size, its materials, and that every part is a closed surface
// wound counter-clockwise seen from outside, with unit normals that agree with the winding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "oer/mesh/default_product.hpp"
#include "oer/mesh/mesh.hpp"

using namespace oer;

namespace {

const Primitive& find_primitive(const Mesh& mesh, const std::string& name) {
    for (const Primitive& p : mesh.primitives) {
        if (p.name == name) {
            return p;
        }
    }
    throw std::runtime_error("no primitive " + name);
}

TEST(DefaultProduct, StandsOnTheGroundAboutOnePointSixTall) {
    const Mesh mesh = make_default_product();
    EXPECT_EQ(mesh.bounds.min.y, 0.0f);
    EXPECT_NEAR(mesh.bounds.max.y, 1.6f, 1e-6f);
    // The round base (radius 0.3) is the widest part; centred on the y axis.
    EXPECT_NEAR(mesh.bounds.max.x, 0.3f, 1e-6f);
    EXPECT_NEAR(mesh.bounds.min.x, -0.3f, 1e-6f);
    EXPECT_NEAR(mesh.bounds.max.z, 0.3f, 1e-3f);
    EXPECT_NEAR(mesh.bounds.min.z, -0.3f, 1e-3f);
    // Bounds and counts agree with the primitives.
    glm::vec3 low(1e9f);
    glm::vec3 high(-1e9f);
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;
    for (const Primitive& p : mesh.primitives) {
        for (const glm::vec3& v : p.positions) {
            low = glm::min(low, v);
            high = glm::max(high, v);
        }
        triangles += p.indices.size() / 3;
        vertices += p.positions.size();
    }
    EXPECT_EQ(low, mesh.bounds.min);
    EXPECT_EQ(high, mesh.bounds.max);
    EXPECT_EQ(mesh.triangle_count, triangles);
    EXPECT_EQ(mesh.vertex_count, vertices);
    // "A few thousand triangles": 6,496 when written (torso 48 rings x 64, base 64, pole 24).
    EXPECT_GE(mesh.triangle_count, 3000u);
    EXPECT_LE(mesh.triangle_count, 10000u);
}

TEST(DefaultProduct, TorsoIsWiderThanDeepAndNarrowestAtTheWaist) {
    const Mesh mesh = make_default_product();
    const Primitive& torso = find_primitive(mesh, "dress form torso");
    // Half-width (x) and half-depth (z) of the torso in horizontal slabs.
    auto extent = [&](float y0, float y1) {
        glm::vec2 e(0.0f);
        for (const glm::vec3& v : torso.positions) {
            if (v.y >= y0 && v.y <= y1) {
                e = glm::max(e, glm::vec2(std::abs(v.x), std::abs(v.z)));
            }
        }
        return e;
    };
    const glm::vec2 hips = extent(0.93f, 1.00f);
    const glm::vec2 waist = extent(1.16f, 1.20f);
    const glm::vec2 bust = extent(1.30f, 1.34f);
    const glm::vec2 shoulders = extent(1.42f, 1.46f);
    const glm::vec2 neck = extent(1.56f, 1.60f);
    for (const glm::vec2& e : {hips, waist, bust, shoulders}) {
        EXPECT_GT(e.x, e.y * 1.2f);  // elliptical: wider in x than deep in z
    }
    EXPECT_LT(waist.x, hips.x * 0.8f);
    EXPECT_LT(waist.x, bust.x * 0.85f);
    EXPECT_GT(shoulders.x, bust.x);
    EXPECT_LT(neck.x, 0.06f);
    // The torso spans about 0.9 to 1.6.
    float low = 1e9f;
    float high = -1e9f;
    for (const glm::vec3& v : torso.positions) {
        low = std::min(low, v.y);
        high = std::max(high, v.y);
    }
    EXPECT_NEAR(low, 0.9f, 1e-6f);
    EXPECT_NEAR(high, 1.6f, 1e-6f);
}

TEST(DefaultProduct, TwoMaterialsFabricAndDarkStandNoTextures) {
    const Mesh mesh = make_default_product();
    ASSERT_EQ(mesh.materials.size(), 2u);
    EXPECT_TRUE(mesh.textures.empty());
    const Material& fabric =
        mesh.materials[std::size_t(find_primitive(mesh, "dress form torso").material)];
    const Material& stand =
        mesh.materials[std::size_t(find_primitive(mesh, "dress form stand").material)];
    EXPECT_NEAR(fabric.base_color.r, 0.85f, 1e-6f);
    EXPECT_NEAR(fabric.base_color.g, 0.80f, 1e-6f);
    EXPECT_NEAR(fabric.base_color.b, 0.75f, 1e-6f);
    EXPECT_NEAR(stand.base_color.r, 0.10f, 1e-6f);
    EXPECT_FALSE(fabric.base_color_texture.present());
    EXPECT_FALSE(stand.base_color_texture.present());
    EXPECT_NE(&fabric, &stand);
}

TEST(DefaultProduct, NormalsAreUnitAndAgreeWithTheWinding) {
    const Mesh mesh = make_default_product();
    for (const Primitive& p : mesh.primitives) {
        ASSERT_EQ(p.normals.size(), p.positions.size());
        for (const glm::vec3& n : p.normals) {
            ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << p.name;
        }
        std::size_t degenerate = 0;
        for (std::size_t t = 0; t < p.indices.size(); t += 3) {
            const glm::vec3& a = p.positions[p.indices[t]];
            const glm::vec3& b = p.positions[p.indices[t + 1]];
            const glm::vec3& c = p.positions[p.indices[t + 2]];
            const glm::vec3 g = glm::cross(b - a, c - a);
            if (glm::length(g) < 1e-12f) {
                ++degenerate;
                continue;
            }
            for (int k = 0; k < 3; ++k) {
                ASSERT_GT(glm::dot(g, p.normals[p.indices[t + k]]), 0.0f)
                    << p.name << " triangle " << t / 3 << " corner " << k;
            }
        }
        EXPECT_EQ(degenerate, 0u) << p.name;
    }
}

TEST(DefaultProduct, EveryPartIsClosedAndWoundOutward) {
    const Mesh mesh = make_default_product();
    for (const Primitive& p : mesh.primitives) {
        // Weld by position (caps repeat their rim's positions with other normals), then every
        // directed edge must appear once and its reverse once: closed, consistently wound.
        std::map<std::tuple<float, float, float>, std::uint32_t> weld;
        std::vector<std::uint32_t> id(p.positions.size());
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            const glm::vec3& v = p.positions[i];
            id[i] = weld.emplace(std::make_tuple(v.x, v.y, v.z), std::uint32_t(weld.size()))
                        .first->second;
        }
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
        for (std::size_t t = 0; t < p.indices.size(); t += 3) {
            for (int k = 0; k < 3; ++k) {
                ++edges[{id[p.indices[t + k]], id[p.indices[t + (k + 1) % 3]]}];
            }
        }
        for (const auto& [edge, count] : edges) {
            ASSERT_EQ(count, 1) << p.name << ": edge used twice in one direction";
            const auto reverse = edges.find({edge.second, edge.first});
            ASSERT_TRUE(reverse != edges.end()) << p.name << ": open edge";
        }
        // Outward winding: positive signed volume.
        double volume = 0.0;
        for (std::size_t t = 0; t < p.indices.size(); t += 3) {
            const glm::dvec3 a(p.positions[p.indices[t]]);
            const glm::dvec3 b(p.positions[p.indices[t + 1]]);
            const glm::dvec3 c(p.positions[p.indices[t + 2]]);
            volume += glm::dot(a, glm::cross(b, c)) / 6.0;
        }
        EXPECT_GT(volume, 0.0) << p.name;
        if (p.name == "dress form stand") {
            // Base disc pi 0.3^2 0.03 plus the pole pi 0.012^2 0.9, less the polygon's deficit.
            const double expected =
                std::numbers::pi * 0.09 * 0.03 + std::numbers::pi * 0.012 * 0.012 * 0.9;
            EXPECT_NEAR(volume, expected, expected * 0.01);
        }
    }
}

TEST(DefaultProduct, IsDeterministic) {
    const Mesh a = make_default_product();
    const Mesh b = make_default_product();
    ASSERT_EQ(a.primitives.size(), b.primitives.size());
    for (std::size_t i = 0; i < a.primitives.size(); ++i) {
        EXPECT_EQ(a.primitives[i].positions, b.primitives[i].positions);
        EXPECT_EQ(a.primitives[i].normals, b.primitives[i].normals);
        EXPECT_EQ(a.primitives[i].indices, b.primitives[i].indices);
    }
}

}  // namespace
