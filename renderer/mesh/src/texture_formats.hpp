#pragma once
// Private to texture_decoding.cpp: the formats beyond stb's PNG and JPEG, each in a file of its
// own (texture_webp.cpp, texture_avif.cpp, texture_ktx2.cpp). Every function names the image by
// `what` in its errors.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "texture_decoding.hpp"

namespace oer::mesh_detail {

// Refuses an empty size (InvalidInput) or one of more than max_pixels (LimitExceeded).
void check_pixel_count(std::uint64_t width, std::uint64_t height, std::uint64_t max_pixels,
                       const std::string& what);

// WebP (RIFF "WEBP"): lossy VP8, lossless VP8L, or extended VP8X (alpha, metadata).
bool is_webp(std::span<const std::byte> bytes);
// Its size from the bitstream's header (WebPGetFeatures), within max_pixels; an animation is
// Unsupported (a texture is one image), a damaged header InvalidInput.
ImageHeader webp_header(std::span<const std::byte> bytes, std::uint64_t max_pixels,
                        const std::string& what);
// Decodes into `rgba` (header.width * header.height * 4 bytes, allocated by the caller after
// the header was checked): libwebp allocates no output of its own.
void decode_webp(std::span<const std::byte> bytes, const ImageHeader& header,
                 std::span<unsigned char> rgba, const std::string& what);

// AVIF (an ISO BMFF "ftyp" of brand avif or avis).
bool is_avif(std::span<const std::byte> bytes);
// Its size from the container (libavif's parse, no AV1 decoding), within max_pixels; a damaged
// or truncated container InvalidInput, a sequence of more than one image refused by libavif.
ImageHeader avif_header(std::span<const std::byte> bytes, std::uint64_t max_pixels,
                        const std::string& what);
// Decodes into `rgba`, as decode_webp.
void decode_avif(std::span<const std::byte> bytes, const ImageHeader& header,
                 std::span<unsigned char> rgba, const std::string& what);

// KTX 2.0 (the 12-byte identifier «KTX 20»).
bool is_ktx2(std::span<const std::byte> bytes);
// Its size within max_pixels, and its layout checked as KHR_texture_basisu requires it: one 2D
// image (no depth, layers or cube faces), at most the mip levels its size has, the level index
// and every level inside the file.
ImageHeader ktx2_header(std::span<const std::byte> bytes, std::uint64_t max_pixels,
                        const std::string& what);
// The Unsupported error of a checked KTX2 image, naming its payload (ETC1S or UASTC, and
// Zstandard supercompression).
[[noreturn]] void refuse_ktx2_decoding(std::span<const std::byte> bytes, const std::string& what);

}  // namespace oer::mesh_detail
