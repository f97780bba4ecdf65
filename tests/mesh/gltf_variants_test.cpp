// KHR_materials_variants in the glTF loader (renderer/mesh/src/gltf_variants.hpp): the variants'
// names, each primitive's material under each, and hostile declarations refused by name.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gltf_test_assets.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_testing {
namespace {

// The variants' mappings of the body (primitive 0 of mesh 0).
json& body_mappings(GltfBuilder& b) {
    return b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"];
}

}  // namespace

TEST(GltfVariants, EachVariantDrawsItsMappedMaterialsAndTheDefaultElsewhere) {
    GltfBuilder b = variants_product();
    const Mesh mesh = load_gltf_text(b.gltf());
    expect_valid(mesh);
    EXPECT_EQ(mesh.variants, (std::vector<std::string>{"Red", "Blue", "Unchanged"}));
    ASSERT_EQ(mesh.primitives.size(), 2u);
    const Primitive& body = mesh.primitives[0];
    const Primitive& stand = mesh.primitives[1];
    ASSERT_EQ(body.variant_materials.size(), 3u);
    ASSERT_EQ(stand.variant_materials.size(), 3u);
    const auto name_under = [&](const Primitive& primitive, std::optional<std::uint32_t> variant) {
        return mesh.materials.at(std::size_t(primitive.material_under(variant))).name;
    };
    EXPECT_EQ(name_under(body, std::nullopt), "Body");
    EXPECT_EQ(name_under(body, 0u), "Red");
    EXPECT_EQ(name_under(body, 1u), "Blue");
    EXPECT_EQ(name_under(body, 2u), "Body");
    for (std::uint32_t v = 0; v < 3; ++v) {
        EXPECT_EQ(name_under(stand, v), "Stand");
    }
    EXPECT_EQ(body.materials_drawn().size(), 3u);
    EXPECT_EQ(mesh.materials[std::size_t(body.material_under(0u))].base_color,
              glm::vec4(0.8f, 0.05f, 0.05f, 1.0f));
    // Supported: no warning names the extension.
    for (const std::string& warning : mesh.warnings) {
        EXPECT_EQ(warning.find("KHR_materials_variants"), std::string::npos) << warning;
    }
    // An asset without the extension has no variants and no per-variant materials.
    const Mesh plain = load_gltf_text(variants_product(2).gltf());
    EXPECT_TRUE(plain.variants.empty());
    EXPECT_TRUE(plain.primitives[0].variant_materials.empty());
    EXPECT_EQ(plain.materials.at(std::size_t(plain.primitives[0].material)).name, "Red");
}

TEST(GltfVariantsHostile, BadDeclarationsAndMappingsAreRefusedNamingWhatIsWrong) {
    const auto refused = [](const std::function<void(GltfBuilder&)>& damage,
                            const std::vector<std::string>& parts,
                            ErrorKind kind = ErrorKind::InvalidInput) {
        GltfBuilder b = variants_product();
        damage(b);
        const std::string text = b.gltf();
        expect_error([&] { load_gltf_text(text); }, kind, parts);
    };
    refused(
        [](GltfBuilder& b) {
            b.doc["extensions"]["KHR_materials_variants"]["variants"][1]["name"] = "Red";
        },
        {"variants[1].name 'Red' names an earlier variant"});
    refused(
        [](GltfBuilder& b) {
            b.doc["extensions"]["KHR_materials_variants"]["variants"][0]["name"] = "";
        },
        {"variants[0].name is empty"});
    refused([](GltfBuilder& b) { b.doc["extensions"]["KHR_materials_variants"]["variants"] = 3; },
            {"KHR_materials_variants.variants must be an array"});
    refused([](GltfBuilder& b) { body_mappings(b)[0]["material"] = 9; },
            {"mesh 'Product' primitive 0", "mappings[0].material 9 does not exist"});
    refused([](GltfBuilder& b) { body_mappings(b)[1]["variants"] = {3}; },
            {"mappings[1].variants[0] is not the index of a declared variant (0 to 2)"});
    refused([](GltfBuilder& b) { body_mappings(b)[1]["variants"] = {-1}; },
            {"mappings[1].variants[0] is not the index"});
    refused([](GltfBuilder& b) { body_mappings(b)[1]["variants"] = {0}; },
            {"mappings[1] maps variant 0, which an earlier mapping of the primitive maps already"});
    refused([](GltfBuilder& b) { b.doc["extensions"].erase("KHR_materials_variants"); },
            {"maps variants, but the asset declares none"});
    refused(
        [](GltfBuilder& b) {
            json& list = b.doc["extensions"]["KHR_materials_variants"]["variants"];
            for (int i = 3; i <= 256; ++i) {
                list.push_back({{"name", "v" + std::to_string(i)}});
            }
        },
        {"declares 257 variants, more than the limit of 256"}, ErrorKind::LimitExceeded);
}

}  // namespace oer::mesh_testing
