#pragma once
// Private to the glTF loader: the materials the primitives use, converted on first use to the
// glTF 2.0 metallic-roughness model (specification, section 3.9): factors, the five textures
// (gltf_textures.hpp), KHR_materials_emissive_strength, alpha modes and double-sidedness, and
// the material extensions KHR_materials_unlit, _ior, _specular, _clearcoat, _sheen,
// _transmission and _volume (their factors checked and their textures read as the core ones). A
// primitive without a material gets the glTF default one; a primitive that cannot map its
// material's normal texture gets a copy of the material without it.
#include <tiny_gltf.h>

#include <string>
#include <vector>

#include "gltf_textures.hpp"
#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

class GltfMaterials {
  public:
    // The converted materials are appended to `materials`, warnings to `warnings`.
    GltfMaterials(const tinygltf::Model& model, const std::string& asset,
                  TextureReferences& textures, std::vector<Material>& materials,
                  std::vector<std::string>& warnings)
        : model_(model),
          asset_(asset),
          textures_(textures),
          materials_(materials),
          warnings_(warnings),
          material_slot_(model.materials.size(), -1),
          material_without_normal_slot_(model.materials.size(), -1) {}

    // The index in `materials` of glTF material `index` (-1: the default material), used by
    // the primitive named `primitive`.
    int slot(int index, const std::string& primitive);

    // The glTF material `index` (already converted, at `slot`) without its normal texture, for
    // the primitive named `primitive`, which has no TEXCOORD_0 to map it with (a warning says
    // so).
    int without_normal_texture(int index, int slot, const std::string& primitive);

    // The default material, when no primitive used any: a mesh always has one.
    void ensure_one();

  private:
    Material convert(int index);
    void read_metallic_roughness(const tinygltf::Material& source, const std::string& name,
                                 Material& material);
    void read_normal_and_occlusion(const tinygltf::Material& source, const std::string& name,
                                   Material& material);
    void read_emission(const tinygltf::Material& source, const std::string& name,
                       Material& material);
    void read_alpha_and_sides(const tinygltf::Material& source, const std::string& name,
                              Material& material);
    void read_layers(const tinygltf::Material& source, const std::string& name, Material& material);
    // A material extension's texture `key` ("clearcoatTexture") read with `encoding`.
    TextureReference extension_texture(const tinygltf::Value& extension, const char* key,
                                       const char* property, TextureEncoding encoding,
                                       const std::string& name);

    const tinygltf::Model& model_;
    const std::string& asset_;
    TextureReferences& textures_;
    std::vector<Material>& materials_;
    std::vector<std::string>& warnings_;
    std::vector<int> material_slot_;  // glTF material -> index in materials_, or -1
    // glTF material -> its copy without the normal texture in materials_, or -1
    std::vector<int> material_without_normal_slot_;
    int default_slot_ = -1;
};

}  // namespace oer::mesh_detail
