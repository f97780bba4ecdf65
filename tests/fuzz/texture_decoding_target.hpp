#pragma once
// The body shared by the texture targets (fuzz_texture_webp, fuzz_texture_avif,
// fuzz_texture_ktx2): one glTF image's bytes through the mesh loader's private texture decoding
// (renderer/mesh/src/texture_decoding.hpp) at the default MeshLimits, as the loader checks every
// image's header while parsing and decodes those the materials use.
//
// Checked beyond the documented refusals: the header agrees with the declared format and keeps
// the pixel limit, a decode agrees with its header (size, RGBA bytes), and the resident set
// grows while decoding by at most the RGBA bytes plus a quarter and 16 MiB (the decoder's own
// buffers and AddressSanitizer's shadow, as fuzz_image allows).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "texture_decoding.hpp"

namespace oer::fuzz {

inline void decode_texture_image(std::span<const std::byte> bytes,
                                 mesh_detail::ImageFormat expected) {
    const std::uint64_t max_pixels = MeshLimits{}.max_texture_pixels;
    const mesh_detail::ImageHeader header =
        mesh_detail::check_image_header(bytes, max_pixels, "image 0");
    if (header.format != expected) {
        return;  // another format's signature, which its own target exercises
    }
    const std::uint64_t pixels = std::uint64_t(header.width) * std::uint64_t(header.height);
    if (header.width <= 0 || header.height <= 0 || pixels > max_pixels) {
        finding("the header was accepted at " + std::to_string(header.width) + "x" +
                std::to_string(header.height));
    }
    ResidentGrowth growth;
    const Texture texture = mesh_detail::decode_texture(bytes, max_pixels, "image 0");
    const std::uint64_t grown = growth.bytes();
    if (texture.width != header.width || texture.height != header.height ||
        texture.rgba.size() != pixels * 4) {
        finding("the header said " + std::to_string(header.width) + "x" +
                std::to_string(header.height) + ", the decode gave " +
                std::to_string(texture.width) + "x" + std::to_string(texture.height) + " in " +
                std::to_string(texture.rgba.size()) + " bytes");
    }
    const std::uint64_t allowed = pixels * 4 + pixels + (16u << 20);
    if (grown > allowed) {
        finding(std::to_string(header.width) + "x" + std::to_string(header.height) +
                ": decoding grew the resident set by " + std::to_string(grown) + " bytes");
    }
}

}  // namespace oer::fuzz
