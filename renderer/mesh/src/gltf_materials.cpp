// The glTF materials converted (see gltf_materials.hpp).
#include "gltf_materials.hpp"

#include <cstddef>
#include <utility>

#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

Material default_material() {
    Material material;
    material.name = "default (glTF)";
    return material;  // glTF defaults: white, metallic 1, roughness 1, opaque, one-sided
}

AlphaMode alpha_mode(const std::string& mode, const std::string& material,
                     const std::string& asset) {
    if (mode == "OPAQUE") {
        return AlphaMode::Opaque;
    }
    if (mode == "MASK") {
        return AlphaMode::Mask;
    }
    if (mode == "BLEND") {
        return AlphaMode::Blend;
    }
    fail(
        ErrorKind::InvalidInput, asset,
        material + ": alphaMode '" + one_line(mode, 40) + "' is not one of OPAQUE, MASK and BLEND");
}

}  // namespace

int GltfMaterials::slot(int index, const std::string& primitive) {
    if (index < 0) {
        if (default_slot_ < 0) {
            default_slot_ = int(materials_.size());
            materials_.push_back(default_material());
        }
        return default_slot_;
    }
    if (std::size_t(index) >= model_.materials.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             primitive + ": material " + std::to_string(index) + " does not exist");
    }
    int& slot = material_slot_[std::size_t(index)];
    if (slot < 0) {
        Material converted = convert(index);
        slot = int(materials_.size());
        materials_.push_back(std::move(converted));
    }
    return slot;
}

int GltfMaterials::without_normal_texture(int index, int slot, const std::string& primitive) {
    const Material& with = materials_[std::size_t(slot)];
    warnings_.push_back(primitive + " has no TEXCOORD_0 for the normal texture of " + "material '" +
                        one_line(with.name, 80) + "': normal texture ignored on it");
    int& variant = material_without_normal_slot_[std::size_t(index)];
    if (variant < 0) {
        Material without = with;
        without.name += " (without its normal texture)";
        without.normal_texture = TextureReference{};
        without.normal_scale = 1.0f;
        variant = int(materials_.size());
        materials_.push_back(std::move(without));
    }
    return variant;
}

void GltfMaterials::ensure_one() {
    if (materials_.empty()) {
        materials_.push_back(default_material());
    }
}

Material GltfMaterials::convert(int index) {
    const tinygltf::Material& source = model_.materials[std::size_t(index)];
    const std::string name = source.name.empty() ? "material " + std::to_string(index)
                                                 : "material '" + one_line(source.name, 80) + "'";
    Material material;
    material.name = source.name.empty() ? name : source.name;
    material.model = ShadingModel::MetallicRoughness;
    read_metallic_roughness(source, name, material);
    read_normal_and_occlusion(source, name, material);
    read_emission(source, name, material);
    read_alpha_and_sides(source, name, material);
    return material;
}

void GltfMaterials::read_metallic_roughness(const tinygltf::Material& source,
                                            const std::string& name, Material& material) {
    const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4) {
        fail(ErrorKind::InvalidInput, asset_, name + ": baseColorFactor needs 4 numbers");
    }
    for (int c = 0; c < 4; ++c) {
        material.base_color[c] =
            unit_factor(asset_, pbr.baseColorFactor[std::size_t(c)], name + ": baseColorFactor");
    }
    material.metallic = unit_factor(asset_, pbr.metallicFactor, name + ": metallicFactor");
    material.roughness = unit_factor(asset_, pbr.roughnessFactor, name + ": roughnessFactor");
    material.base_color_texture = textures_.reference(
        TextureUse::of(pbr.baseColorTexture, "baseColorTexture"), TextureEncoding::Srgb, name);
    material.metallic_roughness_texture = textures_.reference(
        TextureUse::of(pbr.metallicRoughnessTexture, "metallicRoughnessTexture"),
        TextureEncoding::Linear, name);
}

void GltfMaterials::read_normal_and_occlusion(const tinygltf::Material& source,
                                              const std::string& name, Material& material) {
    material.normal_texture = textures_.reference(
        TextureUse::of(source.normalTexture, "normalTexture"), TextureEncoding::Linear, name);
    material.normal_scale =
        finite_float(asset_, source.normalTexture.scale, name + ": normalTexture.scale");
    material.occlusion_texture = textures_.reference(
        TextureUse::of(source.occlusionTexture, "occlusionTexture"), TextureEncoding::Linear, name);
    material.occlusion_strength =
        unit_factor(asset_, source.occlusionTexture.strength, name + ": occlusionTexture.strength");
}

// emissiveFactor, emissiveTexture and KHR_materials_emissive_strength's multiplier.
void GltfMaterials::read_emission(const tinygltf::Material& source, const std::string& name,
                                  Material& material) {
    if (source.emissiveFactor.size() != 3) {
        fail(ErrorKind::InvalidInput, asset_, name + ": emissiveFactor needs 3 numbers");
    }
    for (int c = 0; c < 3; ++c) {
        material.emissive[c] =
            unit_factor(asset_, source.emissiveFactor[std::size_t(c)], name + ": emissiveFactor");
    }
    material.emissive_texture = textures_.reference(
        TextureUse::of(source.emissiveTexture, "emissiveTexture"), TextureEncoding::Srgb, name);
    if (const auto strength = source.extensions.find("KHR_materials_emissive_strength");
        strength != source.extensions.end() && strength->second.Has("emissiveStrength")) {
        material.emissive_strength =
            non_negative_float(asset_, strength->second.Get("emissiveStrength").GetNumberAsDouble(),
                               name + ": KHR_materials_emissive_strength.emissiveStrength");
    }
}

// The alpha mode and cutoff, and whether both sides are shaded.
void GltfMaterials::read_alpha_and_sides(const tinygltf::Material& source, const std::string& name,
                                         Material& material) {
    material.alpha_mode = alpha_mode(source.alphaMode, name, asset_);
    material.alpha_cutoff = non_negative_float(asset_, source.alphaCutoff, name + ": alphaCutoff");
    material.double_sided = source.doubleSided;
}

}  // namespace oer::mesh_detail
