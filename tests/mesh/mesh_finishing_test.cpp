// What every loader does last (renderer/mesh/src/mesh_finishing.hpp), on meshes built by code:
// tangents generated where a normal texture needs them (after refinement), texture coordinates
// where any texture does, and the invariants on tangents and texture references checked.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "mesh_finishing.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

using namespace oer;

namespace {

// Two unit squares in the xz plane facing +y, x in [0, 2], their uv mirrored about x = 1, so
// that the seam's two vertices need a copy each for their tangents; material 0 normal-mapped.
Mesh mirrored_squares() {
    Mesh mesh;
    Primitive p;
    p.name = "squares";
    for (float z : {0.0f, 1.0f}) {
        for (float x : {0.0f, 1.0f, 2.0f}) {
            p.positions.push_back({x, 0, z});
            p.texcoords.push_back({1 - std::abs(x - 1), z});
        }
    }
    p.indices = {0, 4, 1, 0, 3, 4, 1, 5, 2, 1, 4, 5};
    mesh.primitives = {p};
    Material material;
    material.name = "Bumpy";
    material.normal_texture.texture = 0;
    mesh.materials = {material};
    mesh.textures = {Texture{1, 1, {128, 128, 255, 255}, TextureEncoding::Linear}};
    return mesh;
}

// The default limits with refinement off (mesh_refinement_test.cpp tests it): the squares'
// own triangles.
const MeshLimits kUnrefined{.max_refined_vertices = 0};

void expect_internal(Mesh mesh, const std::string& part) {
    try {
        mesh_detail::finish_mesh(mesh, "built", MeshLimits{});
        ADD_FAILURE() << "no error; expected one containing '" << part << "'";
    } catch (const Error& error) {
        EXPECT_EQ(int(error.kind()), int(ErrorKind::Internal)) << error.what();
        EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    }
}

TEST(MeshFinishing, TangentsAreGeneratedWhereANormalTextureNeedsThemOnly) {
    Mesh mesh = mirrored_squares();
    Primitive plain = mesh.primitives[0];
    plain.material = 1;
    mesh.primitives.push_back(plain);
    Material lambertian;
    lambertian.model = ShadingModel::Lambertian;
    mesh.materials.push_back(lambertian);
    mesh_detail::finish_mesh(mesh, "built", kUnrefined);
    const Primitive& mapped = mesh.primitives[0];
    // Normals computed first (+y), then tangents, the seam's vertices split: 6 + 2.
    ASSERT_EQ(mapped.positions.size(), 8u);
    ASSERT_EQ(mapped.tangents.size(), 8u);
    for (std::size_t t = 0; t < 4; ++t) {
        for (std::size_t k = 0; k < 3; ++k) {
            const glm::vec4& tangent = mapped.tangents[mapped.indices[3 * t + k]];
            EXPECT_EQ(tangent, t < 2 ? glm::vec4(1, 0, 0, 1) : glm::vec4(-1, 0, 0, -1))
                << "triangle " << t;
        }
    }
    EXPECT_EQ(mapped.normals, std::vector<glm::vec3>(8, glm::vec3(0, 1, 0)));
    EXPECT_TRUE(mesh.primitives[1].tangents.empty());
    EXPECT_EQ(mesh.vertex_count, 8u + 6u);
}

TEST(MeshFinishing, MeshesAreRefinedBeforeTheirTangentsAreGenerated) {
    Mesh mesh = mirrored_squares();
    mesh_detail::finish_mesh(mesh, "built", MeshLimits{});
    const Primitive& p = mesh.primitives[0];
    EXPECT_GT(p.positions.size(), 100u);
    EXPECT_TRUE(mesh.warnings.empty());
    EXPECT_EQ(mesh.bounds.min, glm::vec3(0, 0, 0));
    EXPECT_EQ(mesh.bounds.max, glm::vec3(2, 0, 1));
    // MikkTSpace saw the refined triangles: every corner has its square's tangent, the mirrored
    // one's reversed, the seam's vertices split.
    ASSERT_EQ(p.tangents.size(), p.positions.size());
    for (std::size_t t = 0; t < p.indices.size(); t += 3) {
        const float centre_x = (p.positions[p.indices[t]].x + p.positions[p.indices[t + 1]].x +
                                p.positions[p.indices[t + 2]].x) /
                               3.0f;
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(p.tangents[p.indices[t + k]],
                      centre_x < 1.0f ? glm::vec4(1, 0, 0, 1) : glm::vec4(-1, 0, 0, -1))
                << "triangle " << t / 3;
        }
    }
}

TEST(MeshFinishing, TheVertexLimitCountsTheCopiesMadeForTangents) {
    MeshLimits limits = kUnrefined;
    limits.max_vertices = 7;
    Mesh mesh = mirrored_squares();
    try {
        mesh_detail::finish_mesh(mesh, "built", limits);
        ADD_FAILURE() << "no error";
    } catch (const Error& error) {
        EXPECT_EQ(int(error.kind()), int(ErrorKind::LimitExceeded));
        EXPECT_STREQ(error.what(),
                     "built: 8 vertices, more than the limit of 7 (2 of them copies made for "
                     "their tangents)");
    }
    limits.max_vertices = 8;
    mesh = mirrored_squares();
    mesh_detail::finish_mesh(mesh, "built", limits);
    EXPECT_EQ(mesh.vertex_count, 8u);
}

TEST(MeshFinishing, AnyTextureGivesTexcoordsWhereThereAreNone) {
    for (const auto member : {&Material::base_color_texture, &Material::metallic_roughness_texture,
                              &Material::occlusion_texture, &Material::emissive_texture}) {
        Mesh mesh = mirrored_squares();
        mesh.materials[0].normal_texture = TextureReference{};
        (mesh.materials[0].*member).texture = 0;
        mesh.primitives[0].texcoords.clear();
        mesh_detail::finish_mesh(mesh, "built", kUnrefined);
        EXPECT_EQ(mesh.primitives[0].texcoords, std::vector<glm::vec2>(6, glm::vec2(0.0f)));
        EXPECT_TRUE(mesh.primitives[0].tangents.empty());
    }
    Mesh untextured = mirrored_squares();
    untextured.materials[0].normal_texture = TextureReference{};
    untextured.primitives[0].texcoords.clear();
    mesh_detail::finish_mesh(untextured, "built", kUnrefined);
    EXPECT_TRUE(untextured.primitives[0].texcoords.empty());
}

TEST(MeshFinishing, BrokenTangentsAndTextureReferencesAreInternalErrors) {
    Mesh mesh = mirrored_squares();
    mesh.primitives[0].tangents.assign(5, glm::vec4(1, 0, 0, 1));
    expect_internal(mesh, "squares: tangents and positions differ in number");
    mesh.primitives[0].tangents.assign(6, glm::vec4(1, 0, 0, 1));
    mesh.primitives[0].tangents[2].w = 0.5f;
    expect_internal(mesh, "squares: vertex 2 has a non-finite tangent or a bitangent sign");
    mesh = mirrored_squares();
    mesh.materials[0].occlusion_texture.texture = 1;
    expect_internal(mesh, "material 'Bumpy': its occlusionTexture 1 does not exist");
    mesh = mirrored_squares();
    mesh.materials[0].emissive_texture.texture = -2;
    expect_internal(mesh, "material 'Bumpy': its emissiveTexture -2 does not exist");
}

}  // namespace
