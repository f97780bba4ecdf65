// A glTF's images decoded once per encoding (see gltf_texture_images.hpp).
#include "gltf_texture_images.hpp"

#include <cstddef>
#include <utility>

#include "mesh_errors.hpp"
#include "texture_decoding.hpp"

namespace oer::mesh_detail {

int TextureImages::texture(int image, TextureEncoding encoding) {
    std::array<int, 2>& slots = image_slot_[std::size_t(image)];
    const std::size_t kind = encoding == TextureEncoding::Srgb ? 0 : 1;
    if (slots[kind] >= 0) {
        return slots[kind];
    }
    const std::string& asset = context_.asset;
    const auto encoded = context_.encoded_images.find(image);
    if (encoded == context_.encoded_images.end()) {
        fail(ErrorKind::Internal, asset,
             "image " + std::to_string(image) + " was not kept while parsing");
    }
    const std::string label = image_label(asset, image, model_.images[std::size_t(image)].name);
    const ImageHeader header =
        check_image_header(encoded->second, limits_.max_texture_pixels, label);
    const std::uint64_t pixels = std::uint64_t(header.width) * std::uint64_t(header.height);
    if (pixels > limits_.max_total_texture_pixels - texture_pixels_) {
        fail(ErrorKind::LimitExceeded, asset,
             "the textures together (an image used both as colour and as data counting "
             "twice) have more than the limit of " +
                 std::to_string(limits_.max_total_texture_pixels) + " pixels");
    }
    const int other = slots[1 - kind];
    Texture texture = other >= 0
                          ? textures_[std::size_t(other)]
                          : decode_texture(encoded->second, limits_.max_texture_pixels, label);
    texture.encoding = encoding;
    textures_.push_back(std::move(texture));
    texture_pixels_ += pixels;
    slots[kind] = int(textures_.size()) - 1;
    return slots[kind];
}

}  // namespace oer::mesh_detail
