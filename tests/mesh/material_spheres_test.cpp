// The material spheres (material_spheres.hpp), read back through the glTF loader as an upload
// of the .glb would be.
#include "oer/mesh/material_spheres.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "oer/core/error.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer {
namespace {

Mesh load_spheres(const MaterialSpheresOptions& options) {
    const std::vector<std::byte> glb = material_spheres_glb(options);
    return load_mesh_memory(glb, "spheres.glb", MeshFormat::Glb);
}

TEST(MaterialSpheres, RowsOfDielectricsAndMetalsWithRisingRoughness) {
    MaterialSpheresOptions options;
    options.columns = 5;
    const Mesh mesh = load_spheres(options);
    ASSERT_EQ(mesh.primitives.size(), 10u);
    ASSERT_EQ(mesh.materials.size(), 10u);
    for (const Primitive& primitive : mesh.primitives) {
        const Material& material = mesh.materials.at(std::size_t(primitive.material));
        EXPECT_EQ(material.model, ShadingModel::MetallicRoughness);
        // The centre of the sphere from its positions: its column gives the roughness, its row
        // the metal.
        glm::vec3 low(1e9f), high(-1e9f);
        for (const glm::vec3& p : primitive.positions) {
            low = glm::min(low, p);
            high = glm::max(high, p);
        }
        const glm::vec3 centre = (low + high) * 0.5f;
        EXPECT_NEAR(high.x - low.x, 2.0f * kMaterialSphereRadius, 1e-3f);
        const int column = int(std::lround(centre.x / kMaterialSphereSpacing + 2.0f));
        const bool top = centre.y > kMaterialSphereSpacing;
        EXPECT_NEAR(material.roughness, column / 4.0f, 1e-6f) << material.name;
        EXPECT_EQ(material.metallic, top ? 0.0f : 1.0f) << material.name;
        const glm::vec3 expected_color = top ? options.dielectric_color : options.metal_color;
        EXPECT_NEAR(material.base_color.r, expected_color.r, 1e-6f);
        EXPECT_NEAR(material.base_color.g, expected_color.g, 1e-6f);
        // Normals point outwards, unit.
        for (std::size_t i = 0; i < primitive.positions.size(); i += 97) {
            const glm::vec3 radial = glm::normalize(primitive.positions[i] - centre);
            EXPECT_GT(glm::dot(radial, primitive.normals[i]), 0.999f);
        }
    }
    EXPECT_NEAR(mesh.bounds.min.y, 0.0f, 1e-5f);
    EXPECT_NEAR(mesh.bounds.max.x - mesh.bounds.min.x,
                4.0f * kMaterialSphereSpacing + 2.0f * kMaterialSphereRadius, 1e-4f);
}

TEST(MaterialSpheres, TrianglesFaceOutwards) {
    const Mesh mesh = load_spheres({});
    const Primitive& primitive = mesh.primitives.front();
    int outward = 0;
    const std::size_t triangles = primitive.indices.size() / 3;
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::vec3& a = primitive.positions[primitive.indices[3 * t]];
        const glm::vec3& b = primitive.positions[primitive.indices[3 * t + 1]];
        const glm::vec3& c = primitive.positions[primitive.indices[3 * t + 2]];
        const glm::vec3 face = glm::cross(b - a, c - a);
        outward += glm::dot(face, primitive.normals[primitive.indices[3 * t]]) > 0.0f ? 1 : 0;
    }
    EXPECT_EQ(std::size_t(outward), triangles);
}

TEST(MaterialSpheres, RefusesOptionsOutOfRange) {
    MaterialSpheresOptions options;
    options.columns = 1;
    try {
        material_spheres_glb(options);
        FAIL() << "1 column accepted";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("columns must be in [2, 16], not 1"),
                  std::string::npos)
            << error.what();
    }
    options = {};
    options.rings = 1000;
    EXPECT_THROW(material_spheres_glb(options), Error);
    options = {};
    options.roughness = {0.0f, 1.5f};
    try {
        material_spheres_glb(options);
        FAIL() << "roughness 1.5 accepted";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("1.5"), std::string::npos) << error.what();
    }
    options.roughness = {0.5f};
    EXPECT_THROW(material_spheres_glb(options), Error);
}

TEST(MaterialSpheres, ColumnsTakeTheRoughnessValuesGiven) {
    MaterialSpheresOptions options;
    options.roughness = {0.0f, 0.05f, 0.3f};
    const Mesh mesh = load_spheres(options);
    ASSERT_EQ(mesh.materials.size(), 6u);
    for (const Primitive& primitive : mesh.primitives) {
        const Material& material = mesh.materials.at(std::size_t(primitive.material));
        const int column =
            int(std::lround(primitive.positions[0].x / kMaterialSphereSpacing + 1.0f));
        EXPECT_NEAR(material.roughness, options.roughness.at(std::size_t(column)), 1e-6f)
            << material.name;
    }
}

}  // namespace
}  // namespace oer
