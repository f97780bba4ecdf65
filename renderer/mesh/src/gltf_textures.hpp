#pragma once
// Private to the glTF loader: a material's textureInfo (glTF 2.0, section 5.22) as an
// oer::TextureReference: the texture and image it names, checked; its sampler
// (gltf_samplers.hpp); KHR_texture_transform's offset, rotation, scale and texCoord; the image
// decoded through TextureImages; its image: EXT_texture_webp's or EXT_texture_avif's source
// first, else the core one (KHR_texture_basisu's KTX2 source is not decoded: the core source is
// its fallback). A texture on a texCoord other than 0 and 1 (a normal texture: other than 0),
// or without a PNG, JPEG, WebP or AVIF source, is ignored with a warning.
#include <tiny_gltf.h>

#include <string>
#include <vector>

#include "gltf_texture_images.hpp"
#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

// The clear coat's normal texture, which reads TEXCOORD_0 alone as normalTexture does.
inline constexpr const char* kClearcoatNormalTexture =
    "KHR_materials_clearcoat.clearcoatNormalTexture";

// A textureInfo of any of its three kinds (the normal and occlusion ones add a number), from
// the core material or from a material extension's JSON.
struct TextureUse {
    const char* property;  // "baseColorTexture", "KHR_materials_clearcoat.clearcoatTexture", ...
    int index = -1;
    int tex_coord = 0;
    const tinygltf::Value* transform = nullptr;  // its KHR_texture_transform, if any

    template <typename Info>
    static TextureUse of(const Info& info, const char* property) {
        const auto transform = info.extensions.find("KHR_texture_transform");
        return TextureUse{property, info.index, info.texCoord,
                          transform == info.extensions.end() ? nullptr : &transform->second};
    }
    // Member `key` of a material extension's object (the schema has checked its types), or an
    // unused TextureUse when it has none.
    static TextureUse of_extension(const tinygltf::Value& extension, const char* key,
                                   const char* property);
};

class TextureReferences {
  public:
    // Warnings are appended to `warnings`.
    TextureReferences(const tinygltf::Model& model, const std::string& asset, TextureImages& images,
                      std::vector<std::string>& warnings)
        : model_(model), asset_(asset), images_(images), warnings_(warnings) {}

    // `use` of the material named `material` ("material 'M'"), its image read with `encoding`;
    // no texture (an empty reference) when the use has none or is ignored.
    TextureReference reference(const TextureUse& use, TextureEncoding encoding,
                               const std::string& material);

  private:
    // The texture coordinates a use reads: its texCoord, or KHR_texture_transform's.
    struct TexCoordSet {
        int index;
        const char* note;  // how it was chosen, for the warning when it is not read
    };

    TexCoordSet read_transform(const TextureUse& use, const std::string& what,
                               TextureReference& reference) const;
    // The image texture `index` shows for `use` ("material 'M': normalTexture"), or -1 (a
    // warning said why).
    int source_image(const tinygltf::Texture& texture, int index, const std::string& use);
    int extension_source(const tinygltf::Texture& texture, const char* name,
                         const std::string& what) const;
    void check_image_index(int image, const std::string& what) const;

    const tinygltf::Model& model_;
    const std::string& asset_;
    TextureImages& images_;
    std::vector<std::string>& warnings_;
};

}  // namespace oer::mesh_detail
