// A glTF textureInfo as an oer::TextureReference (see gltf_textures.hpp).
#include "gltf_textures.hpp"

#include <cstddef>

#include "gltf_samplers.hpp"
#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

TextureReference TextureReferences::reference(const TextureUse& use, TextureEncoding encoding,
                                              const std::string& material) {
    TextureReference reference;
    if (use.index < 0) {
        return reference;
    }
    const std::string what = material + ": " + use.property;
    if (std::size_t(use.index) >= model_.textures.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             what + " refers to texture " + std::to_string(use.index) + ", which does not exist");
    }
    const TexCoordSet tex_coord = read_transform(use, what, reference);
    if (tex_coord.index != 0) {
        warnings_.push_back(what + " uses TEXCOORD_" + std::to_string(tex_coord.index) +
                            tex_coord.note + ", only TEXCOORD_0 is supported: texture ignored");
        return TextureReference{};
    }
    const tinygltf::Texture& texture = model_.textures[std::size_t(use.index)];
    const int image = texture.source;
    if (image < 0) {
        warnings_.push_back(what + " (texture " + std::to_string(use.index) +
                            ") has no PNG or JPEG source: texture ignored");
        return TextureReference{};
    }
    if (std::size_t(image) >= model_.images.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             what + ": texture " + std::to_string(use.index) + " refers to image " +
                 std::to_string(image) + ", which does not exist");
    }
    reference.sampler = read_sampler(model_, texture.sampler,
                                     what + ": texture " + std::to_string(use.index), asset_);
    reference.texture = images_.texture(image, encoding);
    return reference;
}

// KHR_texture_transform: its offset, rotation and scale into `reference`; its texCoord, when
// present, overrides the textureInfo's.
TextureReferences::TexCoordSet TextureReferences::read_transform(
    const TextureUse& use, const std::string& what, TextureReference& reference) const {
    TexCoordSet tex_coord{use.tex_coord, ""};
    const auto transform = use.extensions->find("KHR_texture_transform");
    if (transform == use.extensions->end()) {
        return tex_coord;
    }
    const tinygltf::Value& t = transform->second;
    const std::string at = what + ".extensions.KHR_texture_transform.";
    if (t.Has("offset")) {
        reference.offset = finite_vec2(asset_, t.Get("offset"), at + "offset");
    }
    if (t.Has("rotation")) {
        reference.rotation =
            finite_float(asset_, t.Get("rotation").GetNumberAsDouble(), at + "rotation");
    }
    if (t.Has("scale")) {
        reference.scale = finite_vec2(asset_, t.Get("scale"), at + "scale");
    }
    if (t.Has("texCoord")) {
        tex_coord =
            TexCoordSet{t.Get("texCoord").GetNumberAsInt(), " (KHR_texture_transform's texCoord)"};
    }
    return tex_coord;
}

}  // namespace oer::mesh_detail
