// glTF 2.0 materials in the mesh loader: the core metallic-roughness model (factors, the five
// textures and their encodings, samplers, KHR_texture_transform, KHR_materials_emissive_strength,
// alpha modes, double-sidedness), tangents from the file or generated, and every error, on
// assets built here and on the samples of Debian's assimp-testmodels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include "gltf_test_assets.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

const std::string kPngUri = std::string("data:image/png;base64,") + kTinyPng;

// A unit quad in the xz plane facing +y (two counter-clockwise triangles seen from above), its
// uv (x, z): u along +x, v along +z, the image upright seen from above with -z up.
struct Quad {
    std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
    std::vector<glm::vec3> normals{4, glm::vec3(0, 1, 0)};
    std::vector<glm::vec2> uv{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    std::vector<std::uint16_t> indices{0, 2, 1, 0, 3, 2};
};

template <typename T>
int attribute(GltfBuilder& b, const std::vector<T>& values, const char* type) {
    return b.accessor(b.view(values.data(), values.size() * sizeof(T)), kFloat, values.size(),
                      type);
}

// The quad's attributes ("POSITION", "NORMAL", "TEXCOORD_0" unless told not to) and indices.
json quad_primitive(GltfBuilder& b, const Quad& quad, bool texcoords = true) {
    json attributes = {{"POSITION", b.positions(quad.positions)},
                       {"NORMAL", attribute(b, quad.normals, "VEC3")}};
    if (texcoords) {
        attributes["TEXCOORD_0"] = attribute(b, quad.uv, "VEC2");
    }
    return {{"attributes", attributes},
            {"indices", b.indices(quad.indices, kUnsignedShort)},
            {"material", 0}};
}

// One quad whose material 0 is `material`, with images `images` (each the tiny PNG) and a
// texture per image (texture i shows image i), under a node `node` (its "mesh" set here).
std::string quad_asset(const json& material, int images = 1, json node = json::object(),
                       const json& samplers = nullptr) {
    GltfBuilder b;
    const Quad quad;
    b.mesh(json::array({quad_primitive(b, quad)}));
    node["mesh"] = 0;
    b.node(node);
    b.doc["materials"] = json::array({material});
    b.doc["images"] = json::array();
    b.doc["textures"] = json::array();
    for (int i = 0; i < images; ++i) {
        b.doc["images"].push_back({{"uri", kPngUri}});
        b.doc["textures"].push_back({{"source", i}});
    }
    if (!samplers.is_null()) {
        b.doc["samplers"] = samplers;
        b.doc["textures"][0]["sampler"] = 0;
    }
    return b.gltf();
}

const Material& material_of(const Mesh& mesh, std::size_t primitive = 0) {
    return mesh.materials.at(std::size_t(mesh.primitives.at(primitive).material));
}

void expect_unit_tangents(const Primitive& p) {
    ASSERT_EQ(p.tangents.size(), p.positions.size()) << p.name;
    for (std::size_t i = 0; i < p.tangents.size(); ++i) {
        const glm::vec4& t = p.tangents[i];
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-5f) << p.name << " vertex " << i;
        EXPECT_EQ(std::abs(t.w), 1.0f) << p.name << " vertex " << i;
        EXPECT_LT(std::abs(glm::dot(glm::vec3(t), p.normals[i])), 1e-4f)
            << p.name << " vertex " << i;
    }
}

// ---------------------------------------------------------------------------------------------
// The material model

TEST(GltfMaterials, EveryCoreFieldIsRead) {
    const json material = {
        {"name", "Leather"},
        {"pbrMetallicRoughness",
         {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}},
          {"baseColorTexture", {{"index", 0}}},
          {"metallicFactor", 0.25},
          {"roughnessFactor", 0.75},
          {"metallicRoughnessTexture", {{"index", 0}}}}},
        {"normalTexture", {{"index", 1}, {"scale", 0.5}}},
        {"occlusionTexture", {{"index", 1}, {"strength", 0.3}}},
        {"emissiveFactor", {1.0, 0.5, 0.25}},
        {"emissiveTexture", {{"index", 1}}},
        {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}},
        {"alphaMode", "MASK"},
        {"alphaCutoff", 0.25},
        {"doubleSided", true}};
    const Mesh mesh = load_gltf_text(quad_asset(material, 2));
    expect_valid(mesh);
    ASSERT_EQ(mesh.materials.size(), 1u);
    const Material& m = mesh.materials[0];
    EXPECT_EQ(m.name, "Leather");
    EXPECT_EQ(m.model, ShadingModel::MetallicRoughness);
    EXPECT_EQ(m.base_color, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
    EXPECT_EQ(m.metallic, 0.25f);
    EXPECT_EQ(m.roughness, 0.75f);
    EXPECT_EQ(m.normal_scale, 0.5f);
    EXPECT_FLOAT_EQ(m.occlusion_strength, 0.3f);
    EXPECT_EQ(m.emissive, glm::vec3(1.0f, 0.5f, 0.25f));
    EXPECT_EQ(m.emissive_strength, 4.0f);
    EXPECT_EQ(m.alpha_mode, AlphaMode::Mask);
    EXPECT_EQ(m.alpha_cutoff, 0.25f);
    EXPECT_TRUE(m.double_sided);
    // Image 0 as colour and as data, image 1 as data (twice) and as colour: four textures.
    ASSERT_EQ(mesh.textures.size(), 4u);
    const auto encoding = [&](const TextureReference& r) {
        return mesh.textures.at(std::size_t(r.texture)).encoding;
    };
    EXPECT_EQ(encoding(m.base_color_texture), TextureEncoding::Srgb);
    EXPECT_EQ(encoding(m.metallic_roughness_texture), TextureEncoding::Linear);
    EXPECT_EQ(encoding(m.normal_texture), TextureEncoding::Linear);
    EXPECT_EQ(encoding(m.emissive_texture), TextureEncoding::Srgb);
    EXPECT_EQ(m.occlusion_texture.texture, m.normal_texture.texture);
    const std::set<int> distinct{m.base_color_texture.texture, m.metallic_roughness_texture.texture,
                                 m.normal_texture.texture, m.emissive_texture.texture};
    EXPECT_EQ(distinct.size(), 4u);
    // The same pixels under either encoding: the values are not converted, only labelled.
    EXPECT_EQ(mesh.textures[std::size_t(m.base_color_texture.texture)].rgba,
              mesh.textures[std::size_t(m.metallic_roughness_texture.texture)].rgba);
    EXPECT_EQ(mesh.textures[std::size_t(m.normal_texture.texture)].rgba.size(), 16u);
    // A normal texture and no TANGENT: generated, one per position.
    expect_unit_tangents(mesh.primitives[0]);
}

TEST(GltfMaterials, AbsentPropertiesTakeTheSpecificationsDefaults) {
    const Mesh mesh = load_gltf_text(quad_asset({{"name", "Plain"}}));
    const Material& m = material_of(mesh);
    EXPECT_EQ(m.model, ShadingModel::MetallicRoughness);
    EXPECT_EQ(m.base_color, glm::vec4(1.0f));
    EXPECT_EQ(m.metallic, 1.0f);
    EXPECT_EQ(m.roughness, 1.0f);
    EXPECT_EQ(m.emissive, glm::vec3(0.0f));
    EXPECT_EQ(m.emissive_strength, 1.0f);
    EXPECT_EQ(m.normal_scale, 1.0f);
    EXPECT_EQ(m.occlusion_strength, 1.0f);
    EXPECT_EQ(m.alpha_mode, AlphaMode::Opaque);
    EXPECT_EQ(m.alpha_cutoff, 0.5f);
    EXPECT_FALSE(m.double_sided);
    for (const TextureReference* r :
         {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
          &m.occlusion_texture, &m.emissive_texture}) {
        EXPECT_FALSE(r->present());
    }
    EXPECT_TRUE(mesh.textures.empty());
    // No normal texture: no tangents kept.
    EXPECT_TRUE(mesh.primitives[0].tangents.empty());
}

// ---------------------------------------------------------------------------------------------
// The material extensions (mesh.hpp's layers), by their Khronos specifications

// Every factor and texture of the layer extensions, a texture transform and the second uv set
// on one of them, each texture in its kind's encoding.
TEST(GltfMaterialsExtensions, EveryLayerFactorAndTextureIsRead) {
    const json transformed = {
        {"index", 1},
        {"extensions",
         {{"KHR_texture_transform",
           {{"offset", {0.25, 0.5}}, {"scale", {2.0, 3.0}}, {"texCoord", 1}}}}}};
    const json material = {
        {"name", "Lacquer"},
        {"extensions",
         {{"KHR_materials_ior", {{"ior", 1.33}}},
          {"KHR_materials_specular",
           {{"specularFactor", 0.5},
            {"specularTexture", {{"index", 0}}},
            {"specularColorFactor", {2.0, 1.0, 0.5}},
            {"specularColorTexture", {{"index", 0}}}}},
          {"KHR_materials_clearcoat",
           {{"clearcoatFactor", 0.75},
            {"clearcoatTexture", {{"index", 1}}},
            {"clearcoatRoughnessFactor", 0.25},
            {"clearcoatRoughnessTexture", transformed},
            {"clearcoatNormalTexture", {{"index", 1}, {"scale", 0.5}}}}},
          {"KHR_materials_sheen",
           {{"sheenColorFactor", {0.9, 0.8, 0.7}},
            {"sheenColorTexture", {{"index", 0}}},
            {"sheenRoughnessFactor", 0.6},
            {"sheenRoughnessTexture", {{"index", 1}}}}},
          {"KHR_materials_transmission",
           {{"transmissionFactor", 0.4}, {"transmissionTexture", {{"index", 1}}}}},
          {"KHR_materials_volume",
           {{"thicknessFactor", 0.02},
            {"thicknessTexture", {{"index", 1}}},
            {"attenuationDistance", 0.5},
            {"attenuationColor", {0.9, 0.5, 0.25}}}}}}};
    const Mesh mesh = load_gltf_text(quad_asset(material, 2));
    expect_valid(mesh);
    const Material& m = material_of(mesh);
    EXPECT_EQ(m.model, ShadingModel::MetallicRoughness);
    EXPECT_TRUE(m.layered());
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_EQ(m.specular.factor, 0.5f);
    EXPECT_EQ(m.specular.color, glm::vec3(2.0f, 1.0f, 0.5f));
    EXPECT_EQ(m.clearcoat.factor, 0.75f);
    EXPECT_EQ(m.clearcoat.roughness, 0.25f);
    EXPECT_EQ(m.clearcoat.normal_scale, 0.5f);
    EXPECT_EQ(m.sheen.color, glm::vec3(0.9f, 0.8f, 0.7f));
    EXPECT_FLOAT_EQ(m.sheen.roughness, 0.6f);
    EXPECT_FLOAT_EQ(m.transmission.factor, 0.4f);
    EXPECT_FLOAT_EQ(m.volume.thickness, 0.02f);
    EXPECT_EQ(m.volume.attenuation_distance, 0.5f);
    EXPECT_EQ(m.volume.attenuation_color, glm::vec3(0.9f, 0.5f, 0.25f));
    const auto encoding = [&](const TextureReference& r) {
        EXPECT_TRUE(r.present());
        return r.present() ? mesh.textures.at(std::size_t(r.texture)).encoding
                           : TextureEncoding::Linear;
    };
    // Colours are sRGB (each extension's specification), the rest linear data.
    EXPECT_EQ(encoding(m.specular.color_texture), TextureEncoding::Srgb);
    EXPECT_EQ(encoding(m.sheen.color_texture), TextureEncoding::Srgb);
    for (const TextureReference* data :
         {&m.specular.texture, &m.clearcoat.texture, &m.clearcoat.roughness_texture,
          &m.clearcoat.normal_texture, &m.sheen.roughness_texture, &m.transmission.texture,
          &m.volume.thickness_texture}) {
        EXPECT_EQ(encoding(*data), TextureEncoding::Linear);
    }
    EXPECT_EQ(m.clearcoat.roughness_texture.offset, glm::vec2(0.25f, 0.5f));
    EXPECT_EQ(m.clearcoat.roughness_texture.scale, glm::vec2(2.0f, 3.0f));
    EXPECT_EQ(m.clearcoat.roughness_texture.texcoord, 1);
    EXPECT_TRUE(m.reads_uv_set(1));
    EXPECT_FALSE(mesh.primitives[0].texcoords1.empty());
    // The coat's normal texture alone asks for tangents.
    EXPECT_FALSE(m.normal_texture.present());
    expect_unit_tangents(mesh.primitives[0]);
    // Image 0 as colour and data, image 1 as data: three textures for eleven references.
    EXPECT_EQ(mesh.textures.size(), 3u);
}

// The specification's defaults, and extensions at their defaults, leave the core model, which
// the renderer shades without its layered programs.
TEST(GltfMaterialsExtensions, LayersAtTheirDefaultsLeaveTheCoreModel) {
    const Material m = material_of(load_gltf_text(
        quad_asset({{"extensions",
                     {{"KHR_materials_ior", json::object()},
                      {"KHR_materials_specular", {{"specularFactor", 1.0}}},
                      {"KHR_materials_clearcoat", {{"clearcoatRoughnessFactor", 0.5}}},
                      {"KHR_materials_sheen", {{"sheenRoughnessFactor", 0.5}}},
                      {"KHR_materials_transmission", json::object()},
                      {"KHR_materials_volume", {{"thicknessFactor", 1.0}}}}}})));
    EXPECT_EQ(m.ior, 1.5f);
    EXPECT_EQ(m.specular.factor, 1.0f);
    EXPECT_EQ(m.specular.color, glm::vec3(1.0f));
    EXPECT_EQ(m.clearcoat.factor, 0.0f);
    EXPECT_EQ(m.sheen.color, glm::vec3(0.0f));
    EXPECT_EQ(m.transmission.factor, 0.0f);
    EXPECT_EQ(m.volume.attenuation_distance, std::numeric_limits<float>::infinity());
    EXPECT_EQ(m.volume.attenuation_color, glm::vec3(1.0f));
    EXPECT_FALSE(m.layered());
    // Each layer alone makes it layered.
    for (const json& layer :
         {json{{"KHR_materials_ior", {{"ior", 1.4}}}}, json{{"KHR_materials_ior", {{"ior", 0.0}}}},
          json{{"KHR_materials_specular", {{"specularColorFactor", {1.0, 1.0, 0.9}}}}},
          json{{"KHR_materials_specular", {{"specularTexture", {{"index", 0}}}}}},
          json{{"KHR_materials_clearcoat", {{"clearcoatFactor", 0.1}}}},
          json{{"KHR_materials_sheen", {{"sheenColorFactor", {0.0, 0.0, 0.1}}}}},
          json{{"KHR_materials_transmission", {{"transmissionFactor", 0.1}}}}}) {
        SCOPED_TRACE(layer.dump());
        EXPECT_TRUE(material_of(load_gltf_text(quad_asset({{"extensions", layer}}))).layered());
    }
}

// KHR_materials_unlit is its own model: no specular term, no layers (the extensions exclude
// each other), alpha as in the core model.
TEST(GltfMaterialsExtensions, UnlitIsItsOwnModelWithoutLayers) {
    const Material m = material_of(load_gltf_text(
        quad_asset({{"pbrMetallicRoughness", {{"baseColorFactor", {0.25, 0.5, 1.0, 0.5}}}},
                    {"alphaMode", "BLEND"},
                    {"extensions",
                     {{"KHR_materials_unlit", json::object()},
                      {"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}}}}})));
    EXPECT_EQ(m.model, ShadingModel::Unlit);
    EXPECT_FALSE(m.glossy());
    EXPECT_FALSE(m.layered());
    EXPECT_EQ(m.clearcoat.factor, 0.0f);
    EXPECT_EQ(m.base_color, glm::vec4(0.25f, 0.5f, 1.0f, 0.5f));
    EXPECT_EQ(m.alpha_mode, AlphaMode::Blend);
}

// An asset that requires every layer extension loads, and says nothing of them.
TEST(GltfMaterialsExtensions, AssetsRequiringTheLayersLoad) {
    const std::vector<std::string> layers{"KHR_materials_unlit",    "KHR_materials_ior",
                                          "KHR_materials_specular", "KHR_materials_clearcoat",
                                          "KHR_materials_sheen",    "KHR_materials_transmission",
                                          "KHR_materials_volume"};
    json document = json::parse(quad_asset(
        {{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}}));
    document["extensionsUsed"] = layers;
    document["extensionsRequired"] = layers;
    const Mesh mesh = load_gltf_text(document.dump());
    EXPECT_EQ(material_of(mesh).transmission.factor, 1.0f);
    for (const std::string& warning : mesh.warnings) {
        EXPECT_EQ(warning.find("KHR_materials"), std::string::npos) << warning;
    }
}

// Factors bounded to [0, 1] are clamped as the core ones are; a number the specification
// excludes, or one of the wrong JSON type, is refused naming the material and the field.
TEST(GltfMaterialsExtensions, HostileValuesAreRefusedNamingMaterialAndField) {
    const Material clamped = material_of(load_gltf_text(
        quad_asset({{"extensions",
                     {{"KHR_materials_clearcoat",
                       {{"clearcoatFactor", 2.0}, {"clearcoatRoughnessFactor", -1.0}}},
                      {"KHR_materials_sheen", {{"sheenColorFactor", {-1.0, 0.5, 3.0}}}},
                      {"KHR_materials_transmission", {{"transmissionFactor", 1.5}}},
                      {"KHR_materials_volume", {{"attenuationColor", {2.0, -1.0, 0.5}}}}}}})));
    EXPECT_EQ(clamped.clearcoat.factor, 1.0f);
    EXPECT_EQ(clamped.clearcoat.roughness, 0.0f);
    EXPECT_EQ(clamped.sheen.color, glm::vec3(0.0f, 0.5f, 1.0f));
    EXPECT_EQ(clamped.transmission.factor, 1.0f);
    EXPECT_EQ(clamped.volume.attenuation_color, glm::vec3(1.0f, 0.0f, 0.5f));

    const auto named = [](const json& extensions) {
        return json{{"name", "Glass"}, {"extensions", extensions}};
    };
    const std::vector<std::pair<json, std::string>> refused{
        {named({{"KHR_materials_ior", {{"ior", 0.5}}}}),
         "material 'Glass': KHR_materials_ior.ior 0.5 is neither 0 nor at least 1"},
        {named({{"KHR_materials_ior", {{"ior", -1.0}}}}),
         "material 'Glass': KHR_materials_ior.ior -1 is neither 0 nor at least 1"},
        {named({{"KHR_materials_ior", {{"ior", 1e39}}}}),
         "material 'Glass': KHR_materials_ior.ior 1e+39 is not finite as a 32-bit float"},
        {named({{"KHR_materials_specular", {{"specularColorFactor", {1.0, -0.5, 1.0}}}}}),
         "material 'Glass': KHR_materials_specular.specularColorFactor -0.5 is negative"},
        {named({{"KHR_materials_clearcoat",
                 {{"clearcoatNormalTexture", {{"index", 0}, {"scale", 1e300}}}}}}),
         "material 'Glass': KHR_materials_clearcoat.clearcoatNormalTexture.scale 1e+300 is not "
         "finite"},
        {named({{"KHR_materials_volume", {{"thicknessFactor", -0.1}}}}),
         "material 'Glass': KHR_materials_volume.thicknessFactor -0.1 is negative"},
        {named({{"KHR_materials_volume", {{"attenuationDistance", 0.0}}}}),
         "material 'Glass': KHR_materials_volume.attenuationDistance 0 is not above 0"},
        {named({{"KHR_materials_volume", {{"attenuationDistance", -2.0}}}}),
         "material 'Glass': KHR_materials_volume.attenuationDistance -2 is not above 0"},
        {named({{"KHR_materials_sheen", {{"sheenColorTexture", {{"index", 7}}}}}}),
         "material 'Glass': KHR_materials_sheen.sheenColorTexture refers to texture 7, which "
         "does not exist"},
        {named({{"KHR_materials_clearcoat", {{"clearcoatFactor", "full"}}}}),
         "invalid glTF: materials[0].extensions.KHR_materials_clearcoat.clearcoatFactor must be "
         "a number, not a string"},
        {named({{"KHR_materials_sheen", {{"sheenColorFactor", {1.0, 1.0}}}}}),
         "invalid glTF: materials[0].extensions.KHR_materials_sheen.sheenColorFactor must be an "
         "array of 3 numbers"},
        {named({{"KHR_materials_transmission", {{"transmissionTexture", {{"texCoord", 0}}}}}}),
         "invalid glTF: materials[0].extensions.KHR_materials_transmission.transmissionTexture."
         "index is required"},
        {named({{"KHR_materials_volume", "thin"}}),
         "invalid glTF: materials[0].extensions.KHR_materials_volume must be an object"},
    };
    for (const auto& [material, message] : refused) {
        SCOPED_TRACE(material.dump());
        expect_error([&material = material] { load_gltf_text(quad_asset(material)); },
                     ErrorKind::InvalidInput, {"test.gltf: " + message});
    }
}

// The coat's normal texture reads TEXCOORD_0 alone, as the material's does (its tangents follow
// that set): on another set it is dropped with a warning, and a primitive without TEXCOORD_0
// draws the material without it.
TEST(GltfMaterialsExtensions, TheCoatsNormalTextureFollowsTheFirstUvSet) {
    const Mesh mesh = load_gltf_text(
        quad_asset({{"name", "Coat"},
                    {"extensions",
                     {{"KHR_materials_clearcoat",
                       {{"clearcoatFactor", 1.0},
                        {"clearcoatNormalTexture", {{"index", 0}, {"texCoord", 1}}}}}}}}));
    EXPECT_FALSE(material_of(mesh).clearcoat.normal_texture.present());
    EXPECT_NE(std::find(mesh.warnings.begin(), mesh.warnings.end(),
                        "material 'Coat': KHR_materials_clearcoat.clearcoatNormalTexture uses "
                        "TEXCOORD_1, only TEXCOORD_0 is supported for a normal texture: texture "
                        "ignored"),
              mesh.warnings.end());
}

TEST(GltfMaterials, AlphaModesAreReadAndAnyOtherIsRejectedNamingIt) {
    const std::vector<std::pair<std::string, AlphaMode>> modes{
        {"OPAQUE", AlphaMode::Opaque}, {"MASK", AlphaMode::Mask}, {"BLEND", AlphaMode::Blend}};
    for (const auto& [name, mode] : modes) {
        EXPECT_EQ(material_of(load_gltf_text(quad_asset({{"alphaMode", name}}))).alpha_mode, mode)
            << name;
    }
    expect_error(
        [] {
            load_gltf_text(quad_asset({{"name", "Glass"}, {"alphaMode", "blend"}}));
        },
        ErrorKind::InvalidInput,
        {"test.gltf: material 'Glass': alphaMode 'blend' is not one of OPAQUE, MASK and "
         "BLEND"});
    expect_error(
        [] {
            load_gltf_text(quad_asset({{"alphaMode", 2}}));
        },
        ErrorKind::InvalidInput, {"invalid glTF: materials[0].alphaMode must be a string, not 2"});
    expect_error(
        [] {
            load_gltf_text(quad_asset({{"doubleSided", "yes"}}));
        },
        ErrorKind::InvalidInput,
        {"invalid glTF: materials[0].doubleSided must be a boolean, not a string"});
}

TEST(GltfMaterials, BoundedFactorsAreClampedAndOtherNumbersMustBeFiniteFloats) {
    const Material clamped = material_of(load_gltf_text(
        quad_asset({{"pbrMetallicRoughness", {{"metallicFactor", 2.0}, {"roughnessFactor", -1.0}}},
                    {"emissiveFactor", {-1.0, 2.0, 0.5}},
                    {"occlusionTexture", {{"index", 0}, {"strength", 3.0}}}})));
    EXPECT_EQ(clamped.metallic, 1.0f);
    EXPECT_EQ(clamped.roughness, 0.0f);
    EXPECT_EQ(clamped.emissive, glm::vec3(0.0f, 1.0f, 0.5f));
    EXPECT_EQ(clamped.occlusion_strength, 1.0f);

    const std::vector<std::pair<json, std::string>> refused{
        {{{"name", "M"}, {"normalTexture", {{"index", 0}, {"scale", 1e300}}}},
         "material 'M': normalTexture.scale 1e+300 is not finite as a 32-bit float"},
        {{{"name", "M"},
          {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -1.0}}}}}},
         "material 'M': KHR_materials_emissive_strength.emissiveStrength -1 is negative"},
        {{{"name", "M"},
          {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e39}}}}}},
         "material 'M': KHR_materials_emissive_strength.emissiveStrength 1e+39 is not finite"},
        {{{"name", "M"}, {"alphaCutoff", -0.5}},
         "material 'M': alphaCutoff -0.5 is negative (it must be at least 0)"},
        {{{"name", "M"}, {"alphaCutoff", -1e300}},
         "material 'M': alphaCutoff -1e+300 is not finite"},
    };
    for (const auto& [material, message] : refused) {
        SCOPED_TRACE(material.dump());
        expect_error([&material = material] { load_gltf_text(quad_asset(material)); },
                     ErrorKind::InvalidInput, {"test.gltf: " + message});
    }
    // JSON has no infinity: a number beyond a double is refused as the JSON it is not.
    std::string text = quad_asset({{"emissiveFactor", {0.123456, 0.0, 0.0}}});
    text.replace(text.find("0.123456"), 8, "1e999");
    expect_error([&] { load_gltf_text(text); }, ErrorKind::InvalidInput,
                 {"test.gltf: not valid JSON", "1e999"});
    expect_error(
        [] {
            load_gltf_text(quad_asset({{"emissiveFactor", {1, 1}}}));
        },
        ErrorKind::InvalidInput,
        {"invalid glTF: materials[0].emissiveFactor must be an array of 3 numbers"});
}

TEST(GltfMaterials, MissingTexturesAndImagesAreRejectedNamingMaterialAndProperty) {
    expect_error(
        [] {
            load_gltf_text(quad_asset({{"name", "M"}, {"normalTexture", {{"index", 5}}}}));
        },
        ErrorKind::InvalidInput,
        {"test.gltf: material 'M': normalTexture refers to texture 5, which does not exist"});
    expect_error(
        [] {
            load_gltf_text(quad_asset(
                {{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 1}}}}}}));
        },
        ErrorKind::InvalidInput,
        {"material 0: metallicRoughnessTexture refers to texture 1, which does not exist"});
    // A texture whose image does not exist.
    json d = json::parse(quad_asset({{"name", "M"}, {"emissiveTexture", {{"index", 0}}}}));
    d["textures"][0]["source"] = 7;
    expect_error([&] { load_gltf_text(d.dump()); }, ErrorKind::InvalidInput,
                 {"material 'M': emissiveTexture: texture 0 refers to image 7"});
    // A texture without a source (an extension's image format): ignored, said so.
    d["textures"][0].erase("source");
    const Mesh mesh = load_gltf_text(d.dump());
    EXPECT_FALSE(material_of(mesh).emissive_texture.present());
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_EQ(mesh.warnings[0],
              "material 'M': emissiveTexture (texture 0) has no PNG, JPEG, WebP or AVIF "
              "source: texture ignored");
}

TEST(GltfMaterials, OtherTexCoordSetsAreDroppedWithAWarning) {
    const Mesh mesh = load_gltf_text(quad_asset(
        {{"name", "M"},
         {"occlusionTexture", {{"index", 0}, {"texCoord", 2}}},
         {"emissiveTexture",
          {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 2}}}}}}},
         // KHR_texture_transform's texCoord overrides the textureInfo's.
         {"normalTexture",
          {{"index", 0},
           {"texCoord", 1},
           {"extensions", {{"KHR_texture_transform", {{"texCoord", 0}}}}}}}}));
    const Material& m = material_of(mesh);
    EXPECT_FALSE(m.occlusion_texture.present());
    EXPECT_FALSE(m.emissive_texture.present());
    EXPECT_TRUE(m.normal_texture.present());
    EXPECT_EQ(m.normal_texture.texcoord, 0);
    EXPECT_EQ(mesh.warnings, (std::vector<std::string>{
                                 "material 'M': occlusionTexture uses TEXCOORD_2, only TEXCOORD_0 "
                                 "and TEXCOORD_1 are supported: texture ignored",
                                 "material 'M': emissiveTexture uses TEXCOORD_2 "
                                 "(KHR_texture_transform's texCoord), only TEXCOORD_0 and "
                                 "TEXCOORD_1 are supported: texture ignored"}));
    // Only the normal texture's image was decoded.
    ASSERT_EQ(mesh.textures.size(), 1u);
    EXPECT_EQ(mesh.textures[0].encoding, TextureEncoding::Linear);
    EXPECT_TRUE(mesh.primitives[0].texcoords1.empty());
}

TEST(GltfMaterials, ANormalTextureOnTheSecondUvSetIsDroppedWithAWarning) {
    // Its tangent frame follows TEXCOORD_0.
    const Mesh mesh = load_gltf_text(quad_asset(
        {{"name", "M"},
         {"normalTexture",
          {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}}}));
    EXPECT_FALSE(material_of(mesh).normal_texture.present());
    EXPECT_EQ(mesh.warnings,
              (std::vector<std::string>{"material 'M': normalTexture uses TEXCOORD_1 "
                                        "(KHR_texture_transform's texCoord), only TEXCOORD_0 is "
                                        "supported for a normal texture: texture ignored"}));
}

// The quad with a TEXCOORD_1 of another layout than its TEXCOORD_0 (u and v swapped, halved
// and moved), under `material`: as floats, or as normalized unsigned bytes (255 steps).
std::string second_uv_set_asset(const json& material, bool normalized_bytes = false) {
    GltfBuilder b;
    const Quad quad;
    json primitive = quad_primitive(b, quad);
    if (normalized_bytes) {
        const std::vector<std::uint8_t> bytes{0, 255, 0, 51, 255, 51, 255, 255};
        primitive["attributes"]["TEXCOORD_1"] =
            b.accessor(b.view(bytes.data(), bytes.size()), kUnsignedByte, 4, "VEC2");
        b.doc["accessors"].back()["normalized"] = true;
    } else {
        std::vector<glm::vec2> uv1;
        for (const glm::vec2& uv : quad.uv) {
            uv1.push_back(glm::vec2(uv.y, uv.x) * 0.5f + glm::vec2(0.25f, 0.125f));
        }
        primitive["attributes"]["TEXCOORD_1"] = attribute(b, uv1, "VEC2");
    }
    b.mesh(json::array({primitive}));
    b.node({{"mesh", 0}});
    b.doc["materials"] = json::array({material});
    b.doc["images"] = json::array({{{"uri", kPngUri}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    return b.gltf();
}

TEST(GltfMaterials, ATextureOnTheSecondUvSetKeepsItAndTheSet) {
    // The 3D Commerce certification's layout: the occlusion map on TEXCOORD_1, the base colour
    // on TEXCOORD_0.
    const json material = {{"name", "M"},
                           {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
                           {"occlusionTexture", {{"index", 0}, {"texCoord", 1}}}};
    const Mesh mesh = load_gltf_text(second_uv_set_asset(material), kUnrefined);
    expect_valid(mesh);
    EXPECT_TRUE(mesh.warnings.empty());
    const Material& m = material_of(mesh);
    ASSERT_TRUE(m.occlusion_texture.present());
    EXPECT_EQ(m.occlusion_texture.texcoord, 1);
    ASSERT_TRUE(m.base_color_texture.present());
    EXPECT_EQ(m.base_color_texture.texcoord, 0);
    const Primitive& p = mesh.primitives[0];
    const Quad quad;
    ASSERT_EQ(p.texcoords.size(), p.positions.size());
    ASSERT_EQ(p.texcoords1.size(), p.positions.size());
    for (std::size_t i = 0; i < quad.positions.size(); ++i) {
        EXPECT_EQ(p.texcoords[i], quad.uv[i]) << "vertex " << i;
        EXPECT_EQ(p.texcoords1[i],
                  glm::vec2(quad.uv[i].y, quad.uv[i].x) * 0.5f + glm::vec2(0.25f, 0.125f))
            << "vertex " << i;
    }
    // KHR_texture_transform's texCoord names the set too.
    const json transformed = {
        {"name", "M"},
        {"emissiveTexture",
         {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}}};
    const Mesh by_transform = load_gltf_text(second_uv_set_asset(transformed), kUnrefined);
    EXPECT_EQ(material_of(by_transform).emissive_texture.texcoord, 1);
    EXPECT_EQ(by_transform.primitives[0].texcoords1.size(), 4u);
}

TEST(GltfMaterials, TheSecondUvSetIsReadAsTheFirstNormalizedBytesIncluded) {
    const json material = {{"occlusionTexture", {{"index", 0}, {"texCoord", 1}}}};
    const Mesh mesh = load_gltf_text(second_uv_set_asset(material, true), kUnrefined);
    const std::vector<glm::vec2> expected{{0, 1}, {0, 0.2f}, {1, 0.2f}, {1, 1}};
    ASSERT_EQ(mesh.primitives[0].texcoords1.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(glm::distance(mesh.primitives[0].texcoords1[i], expected[i]), 0.0f, 1e-6f)
            << "vertex " << i;
    }
}

TEST(GltfMaterials, TheSecondUvSetIsReadForAVariantsMaterial) {
    // The body's default material has no texture; its variant "Red" has an occlusion texture on
    // TEXCOORD_1: the body keeps the set, the stand (never drawn with it) has none.
    GltfBuilder b = variants_product();
    std::vector<glm::vec2> uv1;
    for (int i = 0; i < 24; ++i) {
        uv1.emplace_back(float(i) / 24.0f, 0.5f);
    }
    for (json& primitive : b.doc["meshes"][0]["primitives"]) {
        primitive["attributes"]["TEXCOORD_1"] = attribute(b, uv1, "VEC2");
    }
    b.doc["materials"][2]["occlusionTexture"] = {{"index", 0}, {"texCoord", 1}};
    b.doc["images"] = json::array({{{"uri", kPngUri}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.primitives.size(), 2u);
    EXPECT_EQ(mesh.primitives[0].texcoords1, uv1);
    EXPECT_TRUE(mesh.primitives[1].texcoords1.empty());
}

TEST(GltfMaterials, TheSecondUvSetIsReadOnlyWhereAMaterialUsesIt) {
    // No texture on set 1: TEXCOORD_1 is not kept.
    const Mesh unused = load_gltf_text(
        second_uv_set_asset({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}));
    EXPECT_TRUE(unused.primitives[0].texcoords1.empty());
    // A texture on set 1 of a primitive without TEXCOORD_1: zeros, as for set 0.
    const Mesh missing =
        load_gltf_text(quad_asset({{"occlusionTexture", {{"index", 0}, {"texCoord", 1}}}}));
    EXPECT_EQ(missing.primitives[0].texcoords1,
              std::vector<glm::vec2>(missing.primitives[0].positions.size(), glm::vec2(0.0f)));
}

TEST(GltfMaterials, TextureTransformIsReadOnEveryTextureInfo) {
    const json transform = {{"offset", {0.25, -0.5}}, {"rotation", 0.75}, {"scale", {2.0, 3.0}}};
    const json info = {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}};
    const Material m = material_of(load_gltf_text(quad_asset(
        {{"pbrMetallicRoughness", {{"baseColorTexture", info}, {"metallicRoughnessTexture", info}}},
         {"normalTexture", info},
         {"occlusionTexture", info},
         {"emissiveTexture", info}})));
    for (const TextureReference* r :
         {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
          &m.occlusion_texture, &m.emissive_texture}) {
        EXPECT_EQ(r->offset, glm::vec2(0.25f, -0.5f));
        EXPECT_EQ(r->rotation, 0.75f);
        EXPECT_EQ(r->scale, glm::vec2(2.0f, 3.0f));
    }
    // Absent: the identity.
    const Material plain = material_of(load_gltf_text(
        quad_asset({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}})));
    EXPECT_EQ(plain.base_color_texture.offset, glm::vec2(0.0f));
    EXPECT_EQ(plain.base_color_texture.rotation, 0.0f);
    EXPECT_EQ(plain.base_color_texture.scale, glm::vec2(1.0f));

    expect_error(
        [] {
            load_gltf_text(quad_asset(
                {{"name", "M"},
                 {"normalTexture",
                  {{"index", 0},
                   {"extensions", {{"KHR_texture_transform", {{"scale", {1e300, 1.0}}}}}}}}}));
        },
        ErrorKind::InvalidInput,
        {"material 'M': normalTexture.extensions.KHR_texture_transform.scale 1e+300 is not "
         "finite"});
    expect_error(
        [] {
            load_gltf_text(
                quad_asset({{"emissiveTexture",
                             {{"index", 0},
                              {"extensions", {{"KHR_texture_transform", {{"offset", {1}}}}}}}}}));
        },
        ErrorKind::InvalidInput,
        {"invalid glTF: materials[0].emissiveTexture.extensions.KHR_texture_transform.offset "
         "must be an array of 2 numbers"});
    expect_error(
        [] {
            load_gltf_text(quad_asset(
                {{"emissiveTexture",
                  {{"index", 0},
                   {"extensions", {{"KHR_texture_transform", {{"rotation", "quarter"}}}}}}}}));
        },
        ErrorKind::InvalidInput,
        {"invalid glTF: materials[0].emissiveTexture.extensions.KHR_texture_transform.rotation "
         "must be a number, not a string"});
}

TEST(GltfMaterials, SamplersAreReadAndUnknownEnumsRejectedNamingThem) {
    const json textured = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    const auto sampler_of = [&](const json& sampler) {
        return material_of(
                   load_gltf_text(quad_asset(textured, 1, json::object(), json::array({sampler}))))
            .base_color_texture.sampler;
    };
    const TextureSampler read =
        sampler_of({{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9984}});
    EXPECT_EQ(read.wrap_s, TextureWrap::ClampToEdge);
    EXPECT_EQ(read.wrap_t, TextureWrap::MirroredRepeat);
    EXPECT_EQ(read.mag_filter, TextureFilter::Nearest);
    EXPECT_EQ(read.min_filter, TextureFilter::NearestMipmapNearest);
    const std::vector<std::pair<int, TextureFilter>> minifications{
        {9728, TextureFilter::Nearest},
        {9729, TextureFilter::Linear},
        {9984, TextureFilter::NearestMipmapNearest},
        {9985, TextureFilter::LinearMipmapNearest},
        {9986, TextureFilter::NearestMipmapLinear},
        {9987, TextureFilter::LinearMipmapLinear}};
    for (const auto& [value, filter] : minifications) {
        EXPECT_EQ(sampler_of({{"minFilter", value}}).min_filter, filter) << value;
    }
    EXPECT_EQ(sampler_of({{"magFilter", 9729}}).mag_filter, TextureFilter::Linear);
    EXPECT_EQ(sampler_of({{"wrapT", 10497}, {"wrapS", 33648}}).wrap_t, TextureWrap::Repeat);
    // An empty sampler, and none at all: the defaults (repeat, linear, linear mipmaps).
    EXPECT_EQ(sampler_of(json::object()), TextureSampler{});
    EXPECT_EQ(material_of(load_gltf_text(quad_asset(textured))).base_color_texture.sampler,
              TextureSampler{});
    const TextureSampler defaults;
    EXPECT_EQ(defaults.wrap_s, TextureWrap::Repeat);
    EXPECT_EQ(defaults.mag_filter, TextureFilter::Linear);
    EXPECT_EQ(defaults.min_filter, TextureFilter::LinearMipmapLinear);

    const std::vector<std::pair<json, std::string>> refused{
        {{{"wrapS", 1234}},
         "sampler 0: wrapS 1234 is not one of CLAMP_TO_EDGE (33071), MIRRORED_REPEAT (33648) "
         "and REPEAT (10497)"},
        {{{"wrapT", 9729}}, "sampler 0: wrapT 9729 is not one of CLAMP_TO_EDGE"},
        {{{"magFilter", 9987}},
         "sampler 0: magFilter 9987 is not one of NEAREST (9728) and LINEAR (9729)"},
        {{{"minFilter", 9988}},
         "sampler 0: minFilter 9988 is not one of NEAREST (9728), LINEAR (9729) and the mipmap "
         "filters 9984 to 9987"},
    };
    for (const auto& [sampler, message] : refused) {
        SCOPED_TRACE(sampler.dump());
        expect_error([&, &sampler = sampler] { sampler_of(sampler); }, ErrorKind::InvalidInput,
                     {"test.gltf: " + message});
    }
    expect_error(
        [&] {
            sampler_of({{"wrapS", "REPEAT"}});
        },
        ErrorKind::InvalidInput,
        {"invalid glTF: samplers[0].wrapS must be a non-negative integer, not a string"});
    json d = json::parse(quad_asset(textured, 1, json::object(), json::array({json::object()})));
    d["textures"][0]["sampler"] = 3;
    expect_error([&] { load_gltf_text(d.dump()); }, ErrorKind::InvalidInput,
                 {"test.gltf: material 0: baseColorTexture: texture 0 refers to sampler 3, which "
                  "does not exist"});
}

TEST(GltfMaterials, TexturesCountOncePerImageAndEncodingAgainstTheLimits) {
    // One 2x2 image as base colour, metallic-roughness and occlusion: two textures, 8 pixels.
    const std::string text = quad_asset(
        {{"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}},
         {"occlusionTexture", {{"index", 0}}}});
    MeshLimits limits;
    limits.max_total_texture_pixels = 7;
    expect_error([&] { load_gltf_text(text, limits); }, ErrorKind::LimitExceeded,
                 {"the textures together", "more than the limit of 7 pixels"});
    limits.max_total_texture_pixels = 8;
    const Mesh mesh = load_gltf_text(text, limits);
    ASSERT_EQ(mesh.textures.size(), 2u);
    const Material& m = material_of(mesh);
    EXPECT_EQ(m.occlusion_texture.texture, m.metallic_roughness_texture.texture);
    EXPECT_NE(m.base_color_texture.texture, m.metallic_roughness_texture.texture);
    // The per-image limit applies to every kind, on the header, before decoding.
    json d = json::parse(quad_asset({{"normalTexture", {{"index", 0}}}}));
    d["images"][0]["uri"] = "data:image/png;base64," + base64(png_header(5000, 5000));
    limits = MeshLimits{};
    limits.max_texture_pixels = 1'000'000;
    expect_error([&] { load_gltf_text(d.dump(), limits); }, ErrorKind::LimitExceeded,
                 {"image 0", "5000x5000 pixels, more than the limit of 1000000"});
}

// Found by tests/fuzz/fuzz_gltf: stb's reason for refusing an image quotes a PNG chunk's type,
// any four bytes; one that was not UTF-8 made the error unwritable as JSON (a 500 from the
// service). It is escaped, as every third-party message is (one_line.hpp).
TEST(GltfMaterials, UndecodableImagesAreRefusedInUtf8) {
    json d = json::parse(quad_asset({{"normalTexture", {{"index", 0}}}}));
    std::vector<std::uint8_t> png = png_header(2, 2);
    png.insert(png.end(), {0, 0, 0, 0, 'I', 'E', 'N', 0x82, 0, 0, 0, 0});  // an unknown chunk
    d["images"][0]["uri"] = "data:image/png;base64," + base64(png);
    try {
        load_gltf_text(d.dump());
        ADD_FAILURE() << "loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("image 0: the image cannot be decoded (IEN\\x82"),
                  std::string::npos)
            << e.what();
        EXPECT_NO_THROW((void)json(std::string(e.what())).dump());
    }
}

// ---------------------------------------------------------------------------------------------
// Tangents

// The quad with `tangents` as TANGENT, material 0 `material`, under node `node`.
std::string quad_with_tangents(const std::vector<glm::vec4>& tangents, const json& material,
                               json node = json::object()) {
    GltfBuilder b;
    const Quad quad;
    json primitive = quad_primitive(b, quad);
    primitive["attributes"]["TANGENT"] = attribute(b, tangents, "VEC4");
    b.mesh(json::array({primitive}), "Q");
    node["mesh"] = 0;
    b.node(node);
    b.doc["materials"] = json::array({material});
    b.doc["images"] = {{{"uri", kPngUri}}};
    b.doc["textures"] = {{{"source", 0}}};
    return b.gltf();
}

const json kNormalMapped = {{"name", "N"}, {"normalTexture", {{"index", 0}}}};

TEST(GltfMaterials, FileTangentsAreValidatedAndMadeUnit) {
    const std::vector<glm::vec4> tangents{
        {2, 0, 0, 1}, {1, 0, 0, 0.9995f}, {1, 0, 0.01f, -1.0004f}, {0.5f, 0, 0, -1}};
    const Mesh mesh = load_gltf_text(quad_with_tangents(tangents, kNormalMapped), kUnrefined);
    const Primitive& p = mesh.primitives[0];
    ASSERT_EQ(p.tangents.size(), 4u);
    EXPECT_EQ(p.tangents[0], glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(p.tangents[1], glm::vec4(1, 0, 0, 1));
    EXPECT_NEAR(p.tangents[2].x, 1.0f / std::sqrt(1.0001f), 1e-6f);
    EXPECT_EQ(p.tangents[2].w, -1.0f);
    EXPECT_EQ(p.tangents[3], glm::vec4(1, 0, 0, -1));

    std::vector<glm::vec4> bad = tangents;
    bad[1].w = 0.5f;
    expect_error([&] { load_gltf_text(quad_with_tangents(bad, kNormalMapped)); },
                 ErrorKind::InvalidInput,
                 {"test.gltf: mesh 'Q' primitive 0: vertex 1 has TANGENT w = 0.5, not +1 or -1"});
    bad = tangents;
    bad[2] = glm::vec4(std::numeric_limits<float>::quiet_NaN(), 0, 0, 1);
    expect_error([&] { load_gltf_text(quad_with_tangents(bad, kNormalMapped)); },
                 ErrorKind::InvalidInput, {"vertex 2 has a non-finite TANGENT"});
    bad = tangents;
    bad[3] = glm::vec4(0, 0, 0, 1);
    expect_error([&] { load_gltf_text(quad_with_tangents(bad, kNormalMapped)); },
                 ErrorKind::InvalidInput, {"vertex 3 has a zero-length TANGENT"});
    bad = {tangents[0], tangents[1], tangents[2]};
    expect_error([&] { load_gltf_text(quad_with_tangents(bad, kNormalMapped)); },
                 ErrorKind::InvalidInput, {"TANGENT has 3 elements, POSITION 4"});
    // Without a normal texture TANGENT is not needed: not read, not kept, not judged.
    bad = tangents;
    bad[1].w = 0.5f;
    const Mesh plain = load_gltf_text(quad_with_tangents(bad, {{"name", "Plain"}}));
    EXPECT_TRUE(plain.primitives[0].tangents.empty());
}

TEST(GltfMaterials, FileTangentsOfTheWrongTypeAreRejected) {
    GltfBuilder b;
    const Quad quad;
    json primitive = quad_primitive(b, quad);
    primitive["attributes"]["TANGENT"] = attribute(b, quad.normals, "VEC3");
    b.mesh(json::array({primitive}), "Q");
    b.node({{"mesh", 0}});
    b.doc["materials"] = json::array({kNormalMapped});
    b.doc["images"] = {{{"uri", kPngUri}}};
    b.doc["textures"] = {{{"source", 0}}};
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::Unsupported,
                 {"mesh 'Q' primitive 0: TANGENT: accessor",
                  "is VEC3 of FLOAT; expected VEC4 "
                  "of FLOAT"});
}

TEST(GltfMaterials, FileTangentsAreBakedByTheLinearPartAndMirroringFlipsTheirSign) {
    const std::vector<glm::vec4> diagonal(4, glm::vec4(glm::normalize(glm::vec3(1, 0, 1)), 1));
    // Stretched along x: a tangent follows the surface, (2, 0, 1) normalised (the inverse
    // transpose, for normals, would give (0.5, 0, 1)).
    const Mesh stretched =
        load_gltf_text(quad_with_tangents(diagonal, kNormalMapped, {{"scale", {2.0, 1.0, 1.0}}}));
    const glm::vec3 expected = glm::normalize(glm::vec3(2, 0, 1));
    for (const glm::vec4& t : stretched.primitives[0].tangents) {
        EXPECT_NEAR(glm::distance(glm::vec3(t), expected), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
    // Mirrored in x: the tangent mirrored, the bitangent's sign flipped; a rotation by 90
    // degrees about y keeps the sign.
    const Mesh mirrored =
        load_gltf_text(quad_with_tangents(diagonal, kNormalMapped, {{"scale", {-1.0, 1.0, 1.0}}}));
    for (const glm::vec4& t : mirrored.primitives[0].tangents) {
        EXPECT_NEAR(glm::distance(glm::vec3(t), glm::normalize(glm::vec3(-1, 0, 1))), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, -1.0f);
    }
    const float h = std::sqrt(0.5f);
    const Mesh turned = load_gltf_text(
        quad_with_tangents(diagonal, kNormalMapped, {{"rotation", {0.0, h, 0.0, h}}}));
    for (const glm::vec4& t : turned.primitives[0].tangents) {
        // (x, z) -> (z, -x) about +y: (1, 0, 1) -> (1, 0, -1).
        EXPECT_NEAR(glm::distance(glm::vec3(t), glm::normalize(glm::vec3(1, 0, -1))), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
}

TEST(GltfMaterials, GeneratedTangentsAgreeWithTheFilesUnderAnyNodeTransform) {
    // The quad's own tangent frame: u along +x, and the image's up (decreasing v) along -z,
    // which is cross((0, 1, 0), (1, 0, 0)): w = +1.
    const std::vector<glm::vec4> frame(4, glm::vec4(1, 0, 0, 1));
    for (const json& node :
         {json::object(), json{{"scale", {-1.0, 1.0, 1.0}}}, json{{"scale", {1.0, 1.0, -3.0}}},
          json{{"rotation", {0.0, 0.0, std::sqrt(0.5), std::sqrt(0.5)}}}}) {
        SCOPED_TRACE(node.dump());
        const Mesh from_file =
            load_gltf_text(quad_with_tangents(frame, kNormalMapped, node), kUnrefined);
        const Mesh generated = load_gltf_text(quad_asset(kNormalMapped, 1, node), kUnrefined);
        const Primitive& f = from_file.primitives[0];
        const Primitive& g = generated.primitives[0];
        expect_unit_tangents(g);
        ASSERT_EQ(g.positions.size(), 4u);  // a flat quad: no vertex split
        for (std::size_t i = 0; i < 4; ++i) {
            EXPECT_NEAR(glm::distance(glm::vec3(g.tangents[i]), glm::vec3(f.tangents[i])), 0.0f,
                        1e-5f)
                << "vertex " << i;
            EXPECT_EQ(g.tangents[i].w, f.tangents[i].w) << "vertex " << i;
        }
    }
}

TEST(GltfMaterials, NormalTextureWithoutTexcoordsIsDroppedOnThatPrimitiveOnly) {
    GltfBuilder b;
    const Quad quad;
    b.mesh(json::array({quad_primitive(b, quad, false), quad_primitive(b, quad, true)}), "Two");
    b.node({{"mesh", 0}});
    b.doc["materials"] = {{{"name", "Bumpy"},
                           {"normalTexture", {{"index", 0}}},
                           {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.doc["images"] = {{{"uri", kPngUri}}};
    b.doc["textures"] = {{{"source", 0}}};
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.materials.size(), 2u);
    const Material& without = material_of(mesh, 0);
    const Material& with = material_of(mesh, 1);
    EXPECT_EQ(without.name, "Bumpy (without its normal texture)");
    EXPECT_FALSE(without.normal_texture.present());
    EXPECT_EQ(without.base_color_texture.texture, with.base_color_texture.texture);
    EXPECT_TRUE(with.normal_texture.present());
    EXPECT_TRUE(mesh.primitives[0].tangents.empty());
    // Its base colour texture still needs texture coordinates: (0, 0).
    EXPECT_EQ(mesh.primitives[0].texcoords, std::vector<glm::vec2>(4, glm::vec2(0.0f)));
    expect_unit_tangents(mesh.primitives[1]);
    EXPECT_EQ(mesh.warnings,
              (std::vector<std::string>{"mesh 'Two' primitive 0 has no TEXCOORD_0 for the normal "
                                        "texture of material 'Bumpy': normal texture ignored on "
                                        "it"}));
}

TEST(GltfMaterials, AnyTextureGivesAPrimitiveWithoutTexcoordsZeros) {
    GltfBuilder b;
    const Quad quad;
    b.mesh(json::array({quad_primitive(b, quad, false)}));
    b.node({{"mesh", 0}});
    b.doc["materials"] = {{{"emissiveTexture", {{"index", 0}}}}};
    b.doc["images"] = {{{"uri", kPngUri}}};
    b.doc["textures"] = {{{"source", 0}}};
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    EXPECT_EQ(mesh.primitives[0].texcoords, std::vector<glm::vec2>(4, glm::vec2(0.0f)));
    b.doc["materials"] = json::array({json::object()});
    EXPECT_TRUE(load_gltf_text(b.gltf(), kUnrefined).primitives[0].texcoords.empty());
}

// ---------------------------------------------------------------------------------------------
// Debian's samples (assimp-testmodels)

// A sample's JSON: the .gltf, or a .glb's JSON chunk.
json sample_document(const std::string& relative) {
    const std::vector<std::uint8_t> bytes = read_bytes(kAssimpGltf / relative);
    if (!relative.ends_with(".glb")) {
        return json::parse(bytes);
    }
    const std::uint32_t length = std::uint32_t(bytes.at(12)) | std::uint32_t(bytes.at(13)) << 8 |
                                 std::uint32_t(bytes.at(14)) << 16 |
                                 std::uint32_t(bytes.at(15)) << 24;
    return json::parse(bytes.begin() + 20, bytes.begin() + 20 + length);
}

// glTF's sampler enums (specification, section 5.26), as the tests expect them read.
TextureWrap wrap_of(int value) {
    return value == 33071   ? TextureWrap::ClampToEdge
           : value == 33648 ? TextureWrap::MirroredRepeat
                            : TextureWrap::Repeat;
}

TEST(GltfMaterialsSamples, BoxTexturedInEveryVariantHasItsColourTextureAndSampler) {
    REQUIRE_ASSIMP_SAMPLES();
    std::set<int> wraps;
    for (const std::string file :
         {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
          "BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
        SCOPED_TRACE(file);
        const Mesh mesh = load_sample(file);
        expect_valid(mesh);
        ASSERT_EQ(mesh.materials.size(), 1u);
        ASSERT_EQ(mesh.textures.size(), 1u);
        const Material& m = mesh.materials[0];
        EXPECT_EQ(m.model, ShadingModel::MetallicRoughness);
        EXPECT_EQ(m.base_color_texture.texture, 0);
        EXPECT_EQ(mesh.textures[0].encoding, TextureEncoding::Srgb);
        EXPECT_EQ(mesh.textures[0].width, 211);
        EXPECT_EQ(m.metallic, 0.0f);
        EXPECT_EQ(m.roughness, 1.0f);
        // The file's sampler (the variants differ: the .gltf beside its files mirrors and
        // clamps, the others repeat); both minify with NEAREST_MIPMAP_LINEAR.
        const json sampler = sample_document(file)["samplers"][0];
        const TextureSampler& s = m.base_color_texture.sampler;
        EXPECT_EQ(s.wrap_s, wrap_of(sampler["wrapS"]));
        EXPECT_EQ(s.wrap_t, wrap_of(sampler["wrapT"]));
        EXPECT_EQ(s.mag_filter, TextureFilter::Linear);
        EXPECT_EQ(s.min_filter, TextureFilter::NearestMipmapLinear);
        wraps.insert(int(s.wrap_s));
        wraps.insert(int(s.wrap_t));
        EXPECT_TRUE(mesh.primitives[0].tangents.empty());
    }
    EXPECT_EQ(wraps.size(), 3u);  // repeat, mirrored repeat, clamp: each read
}

TEST(GltfMaterialsSamples, ClearCoatTestHasItsNormalRoughnessAndEmissiveTexturesAndTangents) {
    REQUIRE_ASSIMP_SAMPLES();
    const std::string file = "ClearCoat-glTF/ClearCoatTest.gltf";
    const Mesh mesh = load_sample(file);
    expect_valid(mesh);
    // Its clear coat is read now: no warning says it is ignored.
    for (const std::string& warning : mesh.warnings) {
        EXPECT_EQ(warning.find("KHR_materials_clearcoat"), std::string::npos) << warning;
    }
    const json d = sample_document(file);
    // Every material the file gives a texture gets it, in the encoding of its kind.
    std::size_t normal_mapped = 0;
    std::size_t coat_textures = 0;
    for (std::size_t i = 0; i < d["materials"].size(); ++i) {
        const json& source = d["materials"][i];
        const std::string name = source["name"];
        SCOPED_TRACE(name);
        const auto found = std::find_if(mesh.materials.begin(), mesh.materials.end(),
                                        [&](const Material& m) { return m.name == name; });
        ASSERT_NE(found, mesh.materials.end());
        const Material& m = *found;
        const json pbr = source.value("pbrMetallicRoughness", json::object());
        const auto check = [&](bool in_file, const TextureReference& r, TextureEncoding e) {
            EXPECT_EQ(r.present(), in_file);
            if (in_file && r.present()) {
                EXPECT_EQ(mesh.textures.at(std::size_t(r.texture)).encoding, e);
            }
        };
        check(source.contains("normalTexture"), m.normal_texture, TextureEncoding::Linear);
        check(pbr.contains("metallicRoughnessTexture"), m.metallic_roughness_texture,
              TextureEncoding::Linear);
        check(pbr.contains("baseColorTexture"), m.base_color_texture, TextureEncoding::Srgb);
        check(source.contains("emissiveTexture"), m.emissive_texture, TextureEncoding::Srgb);
        EXPECT_FLOAT_EQ(m.roughness, pbr.value("roughnessFactor", 1.0));
        const json coat = source.value("extensions", json::object())
                              .value("KHR_materials_clearcoat", json::object());
        EXPECT_FLOAT_EQ(m.clearcoat.factor, coat.value("clearcoatFactor", 0.0));
        EXPECT_FLOAT_EQ(m.clearcoat.roughness, coat.value("clearcoatRoughnessFactor", 0.0));
        EXPECT_EQ(m.layered(), coat.value("clearcoatFactor", 0.0) > 0.0);
        check(coat.contains("clearcoatTexture"), m.clearcoat.texture, TextureEncoding::Linear);
        check(coat.contains("clearcoatRoughnessTexture"), m.clearcoat.roughness_texture,
              TextureEncoding::Linear);
        check(coat.contains("clearcoatNormalTexture"), m.clearcoat.normal_texture,
              TextureEncoding::Linear);
        coat_textures += coat.contains("clearcoatTexture") ? 1 : 0;
        coat_textures += coat.contains("clearcoatRoughnessTexture") ? 1 : 0;
        coat_textures += coat.contains("clearcoatNormalTexture") ? 1 : 0;
        EXPECT_EQ(m.alpha_mode, source.value("alphaMode", "OPAQUE") == "BLEND" ? AlphaMode::Blend
                                                                               : AlphaMode::Opaque);
        normal_mapped += source.contains("normalTexture") ? 1 : 0;
    }
    EXPECT_EQ(normal_mapped, 6u);
    EXPECT_EQ(coat_textures, 4u);
    // Images used: PartialCoating (the coat's weight, data), PartialCoating_Alpha (colour),
    // RoughnessStripes (data, for the base and the coat), RibsNormal (data, through four
    // textures, the coat's normal among them), PlasticWrap_normals (data, likewise),
    // ClearCoatLabels (colour).
    EXPECT_EQ(mesh.textures.size(), 6u);
    // Tangents exactly where a normal texture (the material's or its coat's) is, generated (the
    // file has no TANGENT).
    std::size_t with_tangents = 0;
    for (const Primitive& p : mesh.primitives) {
        const Material& m = mesh.materials[std::size_t(p.material)];
        if (m.needs_tangents()) {
            expect_unit_tangents(p);
            ++with_tangents;
        } else {
            EXPECT_TRUE(p.tangents.empty()) << p.name;
        }
    }
    // The six normal-mapped materials' primitives and CoatNorm_Coated's, whose coat alone is.
    EXPECT_EQ(with_tangents, 7u);
    const auto label = std::find_if(mesh.materials.begin(), mesh.materials.end(),
                                    [](const Material& m) { return m.name == "LabelMaterial"; });
    ASSERT_NE(label, mesh.materials.end());
    EXPECT_EQ(label->emissive, glm::vec3(1.0f));
}

TEST(GltfMaterialsSamples, TextureTransformTestHasTheFilesTransforms) {
    REQUIRE_ASSIMP_SAMPLES();
    const std::string file = "textureTransform/TextureTransformTest.gltf";
    const Mesh mesh = load_sample(file);
    expect_valid(mesh);
    const json d = sample_document(file);
    std::size_t transformed = 0;
    for (const json& source : d["materials"]) {
        const std::string name = source["name"];
        SCOPED_TRACE(name);
        const auto found = std::find_if(mesh.materials.begin(), mesh.materials.end(),
                                        [&](const Material& m) { return m.name == name; });
        ASSERT_NE(found, mesh.materials.end());
        const TextureReference& r = found->base_color_texture;
        ASSERT_TRUE(r.present());
        const json info = source["pbrMetallicRoughness"]["baseColorTexture"];
        const json t = info.contains("extensions") ? info["extensions"]["KHR_texture_transform"]
                                                   : json::object();
        const json offset = t.value("offset", json{0.0, 0.0});
        const json scale = t.value("scale", json{1.0, 1.0});
        EXPECT_EQ(r.offset, glm::vec2(float(offset[0]), float(offset[1])));
        EXPECT_EQ(r.rotation, float(t.value("rotation", 0.0)));
        EXPECT_EQ(r.scale, glm::vec2(float(scale[0]), float(scale[1])));
        transformed += t.empty() ? 0 : 1;
        // Textures 0 and 1 use the file's sampler (clamp, linear); the others none.
        const TextureSampler expected =
            info["index"] <= 1 ? TextureSampler{TextureWrap::ClampToEdge, TextureWrap::ClampToEdge,
                                                TextureFilter::Linear, TextureFilter::Linear}
                               : TextureSampler{};
        EXPECT_EQ(r.sampler, expected);
    }
    EXPECT_EQ(transformed, 6u);
    // Two of them by their numbers, as the file writes them.
    const auto named = [&](const std::string& name) -> const TextureReference& {
        return std::find_if(mesh.materials.begin(), mesh.materials.end(),
                            [&](const Material& m) { return m.name == name; })
            ->base_color_texture;
    };
    EXPECT_EQ(named("Offset U").offset, glm::vec2(0.5f, 0.0f));
    EXPECT_EQ(named("Rotation").rotation, 0.39269908169872414f);
    EXPECT_EQ(named("All").offset, glm::vec2(-0.2f, -0.1f));
    EXPECT_EQ(named("All").rotation, 0.3f);
    EXPECT_EQ(named("All").scale, glm::vec2(1.5f));
}

TEST(GltfMaterialsSamples, TwoCylinderEngineHasTheFilesCountsAndMaterials) {
    REQUIRE_ASSIMP_SAMPLES();
    const Mesh mesh = load_sample("2CylinderEngine-glTF-Binary/2CylinderEngine.glb", kUnrefined);
    expect_valid(mesh);
    // The counts from the .glb's JSON chunk: every node's instance of a mesh, all triangles.
    const json d = sample_document("2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;
    std::size_t primitives = 0;
    std::set<int> materials;
    for (const json& node : d["nodes"]) {
        if (!node.contains("mesh")) {
            continue;
        }
        for (const json& p : d["meshes"][std::size_t(node["mesh"])]["primitives"]) {
            triangles += std::uint64_t(d["accessors"][std::size_t(p["indices"])]["count"]) / 3;
            vertices +=
                std::uint64_t(d["accessors"][std::size_t(p["attributes"]["POSITION"])]["count"]);
            materials.insert(int(p["material"]));
            ++primitives;
        }
    }
    EXPECT_EQ(mesh.triangle_count, triangles);
    EXPECT_EQ(mesh.vertex_count, vertices);
    EXPECT_EQ(mesh.primitives.size(), primitives);
    EXPECT_EQ(mesh.materials.size(), materials.size());
    for (const Material& m : mesh.materials) {
        EXPECT_EQ(m.model, ShadingModel::MetallicRoughness) << m.name;
        EXPECT_EQ(m.metallic, 0.0f) << m.name;
    }
    EXPECT_TRUE(mesh.textures.empty());
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Vertex colours (COLOR_0)

namespace {

// kTriangle with COLOR_0 of `type` ("VEC3", "VEC4") in `component_type`, from `bytes`.
std::string coloured_triangle(const void* bytes, std::size_t size, int component_type,
                              const std::string& type, bool normalized) {
    GltfBuilder b;
    const int color = b.accessor(b.view(bytes, size), component_type, 3, type);
    if (normalized) {
        b.doc["accessors"][std::size_t(color)]["normalized"] = true;
    }
    json primitive = {{"attributes", {{"POSITION", b.positions(kTriangle)}, {"COLOR_0", color}}}};
    b.mesh(json::array({primitive}));
    b.node({{"mesh", 0}});
    return b.gltf();
}

}  // namespace

TEST(GltfMaterials, VertexColoursAreReadAsLinearRgba) {
    // RGB floats: alpha 1; beyond [0, 1] clamped.
    const std::vector<float> rgb{1.0f, 0.5f, 0.0f, 0.25f, 2.0f, -1.0f, 0.0f, 0.0f, 1.0f};
    const Mesh floats = load_gltf_text(
        coloured_triangle(rgb.data(), rgb.size() * 4, kFloat, "VEC3", false), kUnrefined);
    expect_valid(floats);
    EXPECT_EQ(floats.primitives[0].colors,
              (std::vector<glm::vec4>{
                  {1.0f, 0.5f, 0.0f, 1.0f}, {0.25f, 1.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f, 1.0f}}));
    // RGBA normalized unsigned bytes and shorts.
    const std::vector<std::uint8_t> bytes{255, 0, 0, 255, 0, 51, 0, 0, 0, 0, 255, 102};
    const Mesh from_bytes = load_gltf_text(
        coloured_triangle(bytes.data(), bytes.size(), kUnsignedByte, "VEC4", true), kUnrefined);
    const std::vector<std::uint16_t> shorts{65535, 0, 0, 65535, 0, 13107, 0, 0, 0, 0, 65535, 26214};
    const Mesh from_shorts = load_gltf_text(
        coloured_triangle(shorts.data(), shorts.size() * 2, kUnsignedShort, "VEC4", true),
        kUnrefined);
    const std::vector<glm::vec4> expected{{1, 0, 0, 1}, {0, 0.2f, 0, 0}, {0, 0, 1, 0.4f}};
    for (const Mesh* mesh : {&from_bytes, &from_shorts}) {
        ASSERT_EQ(mesh->primitives[0].colors.size(), 3u);
        for (std::size_t i = 0; i < 3; ++i) {
            EXPECT_NEAR(glm::distance(mesh->primitives[0].colors[i], expected[i]), 0.0f, 1e-6f)
                << "vertex " << i;
        }
    }
    // Without COLOR_0: none.
    EXPECT_TRUE(load_gltf_text(quad_asset({{"name", "M"}})).primitives[0].colors.empty());
}

TEST(GltfMaterials, VertexColoursMustBeNormalizedAndFinite) {
    const std::vector<std::uint8_t> bytes(12, 255);
    expect_error(
        [&] {
            load_gltf_text(
                coloured_triangle(bytes.data(), bytes.size(), kUnsignedByte, "VEC4", false));
        },
        ErrorKind::InvalidInput, {"COLOR_0", "must be normalized"});
    const std::vector<float> nan{0.0f, std::nanf(""), 0.0f, 0, 0, 0, 0, 0, 0};
    expect_error(
        [&] {
            load_gltf_text(coloured_triangle(nan.data(), nan.size() * 4, kFloat, "VEC3", false));
        },
        ErrorKind::InvalidInput, {"vertex 0 has a non-finite COLOR_0"});
    const std::vector<float> two(6, 0.5f);
    expect_error(
        [&] {
            load_gltf_text(coloured_triangle(two.data(), two.size() * 4, kFloat, "VEC2", false));
        },
        ErrorKind::Unsupported, {"COLOR_0", "is VEC2 of FLOAT"});
}
