// A glTF textureInfo as an oer::TextureReference (see gltf_textures.hpp).
#include "gltf_textures.hpp"

#include <cstddef>
#include <string_view>

#include "gltf_samplers.hpp"
#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

TextureUse TextureUse::of_extension(const tinygltf::Value& extension, const char* key,
                                    const char* property) {
    TextureUse use{property};
    if (!extension.Has(key)) {
        return use;
    }
    const tinygltf::Value& info = extension.Get(key);
    use.index = info.Get("index").GetNumberAsInt();
    if (info.Has("texCoord")) {
        use.tex_coord = info.Get("texCoord").GetNumberAsInt();
    }
    if (info.Has("extensions") && info.Get("extensions").Has("KHR_texture_transform")) {
        use.transform = &info.Get("extensions").Get("KHR_texture_transform");
    }
    return use;
}

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
    // A normal texture's tangent frame follows TEXCOORD_0 (the file's TANGENT or MikkTSpace's),
    // the clear coat's too.
    const bool normal = std::string_view(use.property) == "normalTexture" ||
                        std::string_view(use.property) == kClearcoatNormalTexture;
    if (tex_coord.index != 0 && (normal || tex_coord.index != 1)) {
        warnings_.push_back(what + " uses TEXCOORD_" + std::to_string(tex_coord.index) +
                            tex_coord.note +
                            (normal ? ", only TEXCOORD_0 is supported for a normal texture"
                                    : ", only TEXCOORD_0 and TEXCOORD_1 are supported") +
                            ": texture ignored");
        return TextureReference{};
    }
    reference.texcoord = tex_coord.index;
    const tinygltf::Texture& texture = model_.textures[std::size_t(use.index)];
    const int image = source_image(texture, use.index, what);
    if (image < 0) {
        return TextureReference{};
    }
    reference.sampler = read_sampler(model_, texture.sampler,
                                     what + ": texture " + std::to_string(use.index), asset_);
    reference.texture = images_.texture(image, encoding);
    return reference;
}

// The image a texture shows: EXT_texture_webp's source when it has one, else
// EXT_texture_avif's, else the core source. Both extensions let the core source be a PNG or
// JPEG fallback for viewers without the format, so their image, the one the asset was made to
// show, wins; WebP before AVIF when a texture has both: it decodes about twice as fast
// (renderer/mesh/README.md). KHR_texture_basisu's KTX2 source is never decoded
// (texture_decoding.hpp): its fallback is used, or the texture is ignored, with a warning either
// way.
int TextureReferences::source_image(const tinygltf::Texture& texture, int index,
                                    const std::string& use) {
    const std::string what = use + ": texture " + std::to_string(index);
    const std::string warned = use + " (texture " + std::to_string(index) + ")";
    for (const char* extension : {"EXT_texture_webp", "EXT_texture_avif"}) {
        const int image = extension_source(texture, extension, what);
        if (image >= 0) {
            return image;
        }
    }
    const bool ktx2 = extension_source(texture, "KHR_texture_basisu", what) >= 0;
    if (texture.source < 0) {
        warnings_.push_back(
            warned + (ktx2 ? " has only a KTX2 source (KHR_texture_basisu), which is not decoded "
                             "(no Basis Universal transcoder in this build), and no PNG, JPEG, "
                             "WebP or AVIF fallback: texture ignored"
                           : " has no PNG, JPEG, WebP or AVIF source: texture ignored"));
        return -1;
    }
    check_image_index(texture.source, what);
    if (ktx2) {
        warnings_.push_back(warned +
                            ": its KTX2 source (KHR_texture_basisu) is not decoded (no Basis "
                            "Universal transcoder in this build): its fallback, image " +
                            std::to_string(texture.source) + ", is used");
    }
    return texture.source;
}

// The image index of the texture's extension `name` ({"source": index}), checked, or -1 when
// the texture does not have the extension.
int TextureReferences::extension_source(const tinygltf::Texture& texture, const char* name,
                                        const std::string& what) const {
    const auto extension = texture.extensions.find(name);
    if (extension == texture.extensions.end()) {
        return -1;
    }
    const std::string at = what + ": extensions." + name + ".source";
    const tinygltf::Value& value = extension->second;
    if (!value.Has("source") || !value.Get("source").IsInt() ||
        value.Get("source").GetNumberAsInt() < 0) {
        fail(ErrorKind::InvalidInput, asset_, at + " must be an image index");
    }
    const int image = value.Get("source").GetNumberAsInt();
    check_image_index(image, at);
    return image;
}

void TextureReferences::check_image_index(int image, const std::string& what) const {
    if (std::size_t(image) >= model_.images.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             what + " refers to image " + std::to_string(image) + ", which does not exist");
    }
}

// KHR_texture_transform: its offset, rotation and scale into `reference`; its texCoord, when
// present, overrides the textureInfo's.
TextureReferences::TexCoordSet TextureReferences::read_transform(
    const TextureUse& use, const std::string& what, TextureReference& reference) const {
    TexCoordSet tex_coord{use.tex_coord, ""};
    if (use.transform == nullptr) {
        return tex_coord;
    }
    const tinygltf::Value& t = *use.transform;
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
