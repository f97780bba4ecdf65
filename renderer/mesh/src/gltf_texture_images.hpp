#pragma once
// Private to the glTF loader: the images the materials use, decoded (texture_decoding.hpp) into
// the mesh's textures on first use, one texture per image and encoding: an image read both as
// colour and as data is decoded once and stored twice, and counts twice against the limit on
// the textures' pixels together.
#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_parsing.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

class TextureImages {
  public:
    // The decoded textures are appended to `textures`; the encoded bytes are those parsing kept
    // (ParseContext::encoded_images).
    TextureImages(const tinygltf::Model& model, const ParseContext& context,
                  const MeshLimits& limits, std::vector<Texture>& textures)
        : model_(model),
          context_(context),
          limits_(limits),
          textures_(textures),
          image_slot_(model.images.size(), {-1, -1}) {}

    // The index in `textures` of image `image` (which exists) read with `encoding`.
    int texture(int image, TextureEncoding encoding);

  private:
    const tinygltf::Model& model_;
    const ParseContext& context_;
    const MeshLimits& limits_;
    std::vector<Texture>& textures_;
    // glTF image -> index in textures_ as sRGB [0] and as linear [1], or -1
    std::vector<std::array<int, 2>> image_slot_;
    std::uint64_t texture_pixels_ = 0;
};

}  // namespace oer::mesh_detail
