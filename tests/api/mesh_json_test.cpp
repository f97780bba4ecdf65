// The description of a stored mesh (GET /v1/meshes/{id}).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_schema.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/default_product.hpp"

using namespace oer;
using Json = nlohmann::json;

namespace {

Mesh two_material_mesh() {
    Mesh mesh;
    Primitive first;
    first.positions = {{-1.0f, 0.0f, -0.5f}, {1.0f, 0.0f, -0.5f}, {0.0f, 2.0f, 0.25f}};
    first.normals = {{0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}};
    first.indices = {0, 1, 2};
    Primitive second = first;
    second.material = 1;
    mesh.primitives = {first, second};
    Material plain;
    plain.name = "plain";
    plain.base_color = {0.8f, 0.8f, 0.8f, 1.0f};
    plain.model = ShadingModel::Lambertian;
    Material textured;
    textured.name = "label";
    textured.base_color = {1.0f, 0.5f, 0.25f, 0.5f};
    textured.base_color_texture.texture = 0;
    textured.metallic = 0.0f;
    textured.roughness = 0.3f;
    textured.normal_texture.texture = 0;
    textured.emissive = {0.5f, 0.25f, 0.0f};
    textured.emissive_strength = 3.0f;
    textured.alpha_mode = AlphaMode::Mask;
    textured.alpha_cutoff = 0.3f;
    textured.double_sided = true;
    mesh.materials = {plain, textured};
    mesh.textures = {Texture{1, 1, {255, 0, 0, 255}}};
    mesh.bounds = {{-1.0f, 0.0f, -0.5f}, {1.0f, 2.0f, 0.25f}};
    mesh.triangle_count = 2;
    mesh.vertex_count = 6;
    mesh.repairs.normals_replaced = 3;
    mesh.repairs.normals_renormalised = 1;
    mesh.warnings = {"mtllib ignored"};
    return mesh;
}

}  // namespace

TEST(MeshJson, DescribesCountsBoundsMaterialsAndRepairs) {
    const std::string id(64, 'c');
    const Json json = api::mesh_to_json(two_material_mesh(), id, MeshFormat::Obj);
    const Json expected = {
        {"id", id},
        {"format", "obj"},
        {"counts",
         {{"triangles", 2}, {"vertices", 6}, {"primitives", 2}, {"materials", 2}, {"textures", 1}}},
        {"bounds", {{"min", {-1.0, 0.0, -0.5}}, {"max", {1.0, 2.0, 0.25}}}},
        {"materials",
         {{{"name", "plain"},
           {"model", "lambertian"},
           {"base_color", {0.8, 0.8, 0.8, 1.0}},
           {"has_texture", false},
           {"metallic", 1.0},
           {"roughness", 1.0},
           {"emissive", {0.0, 0.0, 0.0}},
           {"alpha_mode", "opaque"},
           {"double_sided", false},
           {"textures",
            {{"base_color", false},
             {"metallic_roughness", false},
             {"normal", false},
             {"occlusion", false},
             {"emissive", false}}},
           {"specular", false}},
          {{"name", "label"},
           {"model", "metallic_roughness"},
           {"base_color", {1.0, 0.5, 0.25, 0.5}},
           {"has_texture", true},
           {"metallic", 0.0},
           {"roughness", 0.3},
           {"emissive", {1.5, 0.75, 0.0}},
           {"alpha_mode", "mask"},
           {"alpha_cutoff", 0.3},
           {"double_sided", true},
           {"textures",
            {{"base_color", true},
             {"metallic_roughness", false},
             {"normal", true},
             {"occlusion", false},
             {"emissive", false}}},
           {"specular", true}}}},
        {"variants", Json::array()},
        {"cameras", Json::array()},
        {"repairs", {{"normals_replaced", 3}, {"normals_renormalised", 1}}},
        {"warnings", {"mtllib ignored"}}};
    EXPECT_EQ(json, expected) << json.dump(2);
    // Floats print as their shortest text, not as the double nearest them.
    EXPECT_NE(json.dump().find("\"roughness\":0.3,"), std::string::npos) << json.dump();
    // And the description is what api/openapi.yaml publishes.
    Json upload = json;
    upload["cached"] = false;
    EXPECT_EQ(oer::testing::openapi_schema_errors(upload, "#/components/schemas/MeshUpload"),
              std::vector<std::string>{});
}

TEST(MeshJson, EveryTextureKindAndAlphaModeIsNamed) {
    Mesh mesh = two_material_mesh();
    Material& m = mesh.materials[1];
    m.base_color_texture = TextureReference{};
    m.normal_texture = TextureReference{};
    m.metallic_roughness_texture.texture = 0;
    m.occlusion_texture.texture = 0;
    m.emissive_texture.texture = 0;
    m.alpha_mode = AlphaMode::Blend;
    const Json json = api::mesh_to_json(mesh, "default");
    const Json& material = json.at("materials").at(1);
    EXPECT_EQ(material.at("textures"), (Json{{"base_color", false},
                                             {"metallic_roughness", true},
                                             {"normal", false},
                                             {"occlusion", true},
                                             {"emissive", true}}));
    EXPECT_FALSE(material.at("has_texture"));
    EXPECT_EQ(material.at("alpha_mode"), "blend");
    EXPECT_FALSE(material.contains("alpha_cutoff"));  // mask only
    EXPECT_EQ(oer::testing::openapi_schema_errors(json, "#/components/schemas/Mesh"),
              std::vector<std::string>{});
}

// A variant lists the materials it draws, and its swatch is the material it draws on the most
// triangles among those it changes; one that changes nothing takes the most drawn overall.
TEST(MeshJson, ListsTheVariantsWithTheirMaterialsAndSwatches) {
    Mesh mesh = two_material_mesh();
    Material red = mesh.materials[0];
    red.name = "red";
    red.base_color = {0.9f, 0.1f, 0.1f, 1.0f};
    mesh.materials.push_back(red);
    Primitive big = mesh.primitives[0];
    big.indices = {0, 1, 2, 0, 2, 1};
    mesh.primitives.push_back(big);
    mesh.variants = {"Red label", "As filed"};
    mesh.primitives[0].variant_materials = {0, 0};
    mesh.primitives[1].variant_materials = {2, 1};  // the label, 1 triangle
    mesh.primitives[2].variant_materials = {0, 0};  // plain, 2 triangles
    const Json json = api::mesh_to_json(mesh, "default");
    ASSERT_EQ(json.at("variants").size(), 2u);
    const Json& changed = json.at("variants").at(0);
    EXPECT_EQ(changed.at("name"), "Red label");
    EXPECT_EQ(changed.at("materials"), (Json{0, 2}));
    EXPECT_EQ(changed.at("swatch").at("material"), 2);
    EXPECT_EQ(changed.at("swatch").at("base_color"), (Json{0.9, 0.1, 0.1, 1.0}));
    EXPECT_FALSE(changed.at("swatch").at("has_texture"));
    const Json& unchanged = json.at("variants").at(1);
    EXPECT_EQ(unchanged.at("materials"), (Json{0, 1}));
    EXPECT_EQ(unchanged.at("swatch").at("material"), 0);  // plain: 3 triangles against 1
    EXPECT_EQ(oer::testing::openapi_schema_errors(json, "#/components/schemas/Mesh"),
              std::vector<std::string>{});
}

// The asset's cameras, in their order: index, name, type, placement; fov_y for a perspective
// camera only, aspect_ratio and zfar only where the file gives them.
TEST(MeshJson, ListsTheAssetsCameras) {
    Mesh mesh = two_material_mesh();
    AssetCamera front;
    front.name = "Front";
    front.camera = {{1.0f, 2.0f, 3.0f}, {0.5f, 2.0f, 3.0f}, {0.0f, 1.0f, 0.0f}, 45.5f};
    front.aspect_ratio = 1.5f;
    front.znear = 0.01f;
    front.zfar = 100.0f;
    AssetCamera top;
    top.name = "Top";
    top.projection = CameraProjection::Orthographic;
    top.camera = {{0.0f, 2.0f, 5.0f}, {0.0f, 0.5f, 5.0f}, {0.0f, 0.0f, -1.0f}, 0.0f};
    top.znear = 0.1f;
    mesh.cameras = {front, top};
    const Json json = api::mesh_to_json(mesh, "default");
    EXPECT_EQ(json.at("cameras"), (Json{{{"index", 0},
                                         {"name", "Front"},
                                         {"type", "perspective"},
                                         {"eye", {1.0, 2.0, 3.0}},
                                         {"target", {0.5, 2.0, 3.0}},
                                         {"up", {0.0, 1.0, 0.0}},
                                         {"fov_y", 45.5},
                                         {"aspect_ratio", 1.5},
                                         {"znear", 0.01},
                                         {"zfar", 100.0}},
                                        {{"index", 1},
                                         {"name", "Top"},
                                         {"type", "orthographic"},
                                         {"eye", {0.0, 2.0, 5.0}},
                                         {"target", {0.0, 0.5, 5.0}},
                                         {"up", {0.0, 0.0, -1.0}},
                                         {"znear", 0.1}}}))
        << json.at("cameras").dump(2);
    EXPECT_EQ(oer::testing::openapi_schema_errors(json, "#/components/schemas/Mesh"),
              std::vector<std::string>{});
}

TEST(MeshJson, TheBuiltInProductHasNoFormat) {
    const Mesh product = make_default_product();
    const Json json = api::mesh_to_json(product, "default");
    EXPECT_EQ(json.at("id"), "default");
    EXPECT_FALSE(json.contains("format"));
    EXPECT_EQ(json.at("counts").at("triangles"), product.triangle_count);
    EXPECT_EQ(json.at("counts").at("vertices"), product.vertex_count);
    EXPECT_EQ(json.at("counts").at("primitives"), product.primitives.size());
    EXPECT_EQ(json.at("materials").size(), product.materials.size());
    // The shortest text of a float reads back as that float.
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(float(json.at("bounds").at("min")[i]), product.bounds.min[i]);
        EXPECT_EQ(float(json.at("bounds").at("max")[i]), product.bounds.max[i]);
    }
}

TEST(MeshJson, FormatNamesReadBack) {
    for (const MeshFormat format : {MeshFormat::Glb, MeshFormat::Gltf, MeshFormat::Obj}) {
        EXPECT_EQ(api::mesh_format_from_string(api::to_string(format)), format);
    }
    EXPECT_EQ(api::to_string(MeshFormat::Gltf), "gltf");
    EXPECT_THROW(api::mesh_format_from_string("stl"), Error);
    EXPECT_THROW(api::mesh_format_from_string("GLB"), Error);
}
