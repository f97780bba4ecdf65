// The glTF materials converted (see gltf_materials.hpp).
#include "gltf_materials.hpp"

#include <cstddef>
#include <string>
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

// Member `key` of a material extension's object, or `fallback` when it is absent (the schema has
// checked that it is a number).
double number_or(const tinygltf::Value& extension, const char* key, double fallback) {
    return extension.Has(key) ? extension.Get(key).GetNumberAsDouble() : fallback;
}

// Member `key`, an array of 3 numbers (the schema has checked it), each read by `read`, or
// `fallback` when it is absent.
template <typename Read>
glm::vec3 vec3_or(const tinygltf::Value& extension, const char* key, glm::vec3 fallback,
                  Read read) {
    if (!extension.Has(key)) {
        return fallback;
    }
    const tinygltf::Value& array = extension.Get(key);
    glm::vec3 value;
    for (int c = 0; c < 3; ++c) {
        value[c] = read(array.Get(c).GetNumberAsDouble());
    }
    return value;
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
        without.clearcoat.normal_texture = TextureReference{};
        without.clearcoat.normal_scale = 1.0f;
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
    read_layers(source, name, material);
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

TextureReference GltfMaterials::extension_texture(const tinygltf::Value& extension, const char* key,
                                                  const char* property, TextureEncoding encoding,
                                                  const std::string& name) {
    return textures_.reference(TextureUse::of_extension(extension, key, property), encoding, name);
}

// The material extensions of docs/materials.md, each by its specification (Khronos's
// extensions/2.0/Khronos/KHR_materials_*/README.md): factors bounded to [0, 1] are clamped as the
// core ones are, every other number is refused by name where the specification excludes it.
void GltfMaterials::read_layers(const tinygltf::Material& source, const std::string& name,
                                Material& material) {
    const auto extension = [&](const char* extension_name) -> const tinygltf::Value* {
        const auto found = source.extensions.find(extension_name);
        return found == source.extensions.end() ? nullptr : &found->second;
    };
    const auto unit = [&](const std::string& field) {
        return [this, what = name + ": " + field](double value) {
            return unit_factor(asset_, value, what);
        };
    };
    if (extension("KHR_materials_unlit") != nullptr) {
        // The other layers do not apply to an unlit material (each extension's "Exclusions").
        material.model = ShadingModel::Unlit;
        return;
    }
    if (const tinygltf::Value* ior = extension("KHR_materials_ior")) {
        const std::string what = name + ": KHR_materials_ior.ior";
        const double value = number_or(*ior, "ior", 1.5);
        material.ior = finite_float(asset_, value, what);
        if (material.ior != 0.0f && material.ior < 1.0f) {
            fail(ErrorKind::InvalidInput, asset_,
                 what + " " + number_text(value) + " is neither 0 nor at least 1");
        }
    }
    if (const tinygltf::Value* specular = extension("KHR_materials_specular")) {
        const std::string at = name + ": KHR_materials_specular.";
        material.specular.factor = unit("KHR_materials_specular.specularFactor")(
            number_or(*specular, "specularFactor", 1.0));
        material.specular.texture = extension_texture(*specular, "specularTexture",
                                                      "KHR_materials_specular.specularTexture",
                                                      TextureEncoding::Linear, name);
        material.specular.color =
            vec3_or(*specular, "specularColorFactor", glm::vec3(1.0f), [&](double value) {
                return non_negative_float(asset_, value, at + "specularColorFactor");
            });
        material.specular.color_texture = extension_texture(
            *specular, "specularColorTexture", "KHR_materials_specular.specularColorTexture",
            TextureEncoding::Srgb, name);
    }
    if (const tinygltf::Value* clearcoat = extension("KHR_materials_clearcoat")) {
        material.clearcoat.factor = unit("KHR_materials_clearcoat.clearcoatFactor")(
            number_or(*clearcoat, "clearcoatFactor", 0.0));
        material.clearcoat.texture = extension_texture(*clearcoat, "clearcoatTexture",
                                                       "KHR_materials_clearcoat.clearcoatTexture",
                                                       TextureEncoding::Linear, name);
        material.clearcoat.roughness = unit("KHR_materials_clearcoat.clearcoatRoughnessFactor")(
            number_or(*clearcoat, "clearcoatRoughnessFactor", 0.0));
        material.clearcoat.roughness_texture = extension_texture(
            *clearcoat, "clearcoatRoughnessTexture",
            "KHR_materials_clearcoat.clearcoatRoughnessTexture", TextureEncoding::Linear, name);
        material.clearcoat.normal_texture =
            extension_texture(*clearcoat, "clearcoatNormalTexture", kClearcoatNormalTexture,
                              TextureEncoding::Linear, name);
        if (clearcoat->Has("clearcoatNormalTexture")) {
            material.clearcoat.normal_scale = finite_float(
                asset_, number_or(clearcoat->Get("clearcoatNormalTexture"), "scale", 1.0),
                name + ": KHR_materials_clearcoat.clearcoatNormalTexture.scale");
        }
    }
    if (const tinygltf::Value* sheen = extension("KHR_materials_sheen")) {
        material.sheen.color = vec3_or(*sheen, "sheenColorFactor", glm::vec3(0.0f),
                                       unit("KHR_materials_sheen.sheenColorFactor"));
        material.sheen.color_texture =
            extension_texture(*sheen, "sheenColorTexture", "KHR_materials_sheen.sheenColorTexture",
                              TextureEncoding::Srgb, name);
        material.sheen.roughness = unit("KHR_materials_sheen.sheenRoughnessFactor")(
            number_or(*sheen, "sheenRoughnessFactor", 0.0));
        material.sheen.roughness_texture = extension_texture(
            *sheen, "sheenRoughnessTexture", "KHR_materials_sheen.sheenRoughnessTexture",
            TextureEncoding::Linear, name);
    }
    if (const tinygltf::Value* transmission = extension("KHR_materials_transmission")) {
        material.transmission.factor = unit("KHR_materials_transmission.transmissionFactor")(
            number_or(*transmission, "transmissionFactor", 0.0));
        material.transmission.texture = extension_texture(
            *transmission, "transmissionTexture", "KHR_materials_transmission.transmissionTexture",
            TextureEncoding::Linear, name);
    }
    if (const tinygltf::Value* volume = extension("KHR_materials_volume")) {
        const std::string at = name + ": KHR_materials_volume.";
        material.volume.thickness = non_negative_float(
            asset_, number_or(*volume, "thicknessFactor", 0.0), at + "thicknessFactor");
        material.volume.thickness_texture =
            extension_texture(*volume, "thicknessTexture", "KHR_materials_volume.thicknessTexture",
                              TextureEncoding::Linear, name);
        if (volume->Has("attenuationDistance")) {
            const double distance = volume->Get("attenuationDistance").GetNumberAsDouble();
            material.volume.attenuation_distance =
                finite_float(asset_, distance, at + "attenuationDistance");
            if (material.volume.attenuation_distance <= 0.0f) {
                fail(ErrorKind::InvalidInput, asset_,
                     at + "attenuationDistance " + number_text(distance) +
                         " is not above 0 (it is a distance)");
            }
        }
        material.volume.attenuation_color = vec3_or(*volume, "attenuationColor", glm::vec3(1.0f),
                                                    unit("KHR_materials_volume.attenuationColor"));
    }
}

}  // namespace oer::mesh_detail
