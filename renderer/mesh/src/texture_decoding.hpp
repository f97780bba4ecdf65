#pragma once
// Private to the glTF loader: texture images to 8-bit RGBA, with their size checked on the
// header before any pixel memory is allocated. PNG and JPEG (glTF 2.0 core) through stb, WebP
// (EXT_texture_webp) through libwebp, AVIF (EXT_texture_avif) through libavif; a KTX2 container
// (KHR_texture_basisu) has its header checked, but cannot be decoded: there is no Basis Universal
// transcoder in the build (the loader uses the texture's PNG or JPEG fallback instead,
// gltf_textures.hpp).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

enum class ImageFormat { Png, Jpeg, Webp, Avif, Ktx2 };

struct ImageHeader {
    ImageFormat format = ImageFormat::Png;
    int width = 0;
    int height = 0;
};

// Reads the format and size from the image's header and checks width * height <= max_pixels
// (else LimitExceeded). A format the loader does not read: ErrorKind::Unsupported, naming the
// format when its signature is known (GIF, BMP, ...); a damaged or truncated header:
// InvalidInput. `what` names the image in messages ("asset: image 0").
ImageHeader check_image_header(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                               const std::string& what);

// check_image_header, then decodes to RGBA8 (row 0 at the top, alpha straight), encoding Srgb:
// the caller sets the encoding of its use. A KTX2 image: ErrorKind::Unsupported.
Texture decode_texture(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                       const std::string& what);

}  // namespace oer::mesh_detail
