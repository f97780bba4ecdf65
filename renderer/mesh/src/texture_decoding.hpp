#pragma once
// Private to the glTF loader: texture images (PNG or JPEG) to 8-bit RGBA, with their size
// checked on the header before any pixel memory is allocated.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

struct ImageHeader {
    int width = 0;
    int height = 0;
};

// Reads the size from a PNG or JPEG header (other formats: ErrorKind::Unsupported; a damaged
// header: InvalidInput) and checks width * height <= max_pixels (else LimitExceeded).
// `what` names the image in messages ("asset: image 0").
ImageHeader check_image_header(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                               const std::string& what);

// check_image_header, then decodes to RGBA8 (row 0 at the top), encoding Srgb: the caller sets
// the encoding of its use.
Texture decode_texture(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                       const std::string& what);

}  // namespace oer::mesh_detail
