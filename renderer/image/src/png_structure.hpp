#pragma once
// Private to oer_image: a PNG's chunk structure, checked before the bytes reach OpenImageIO
// (image_encoding.cpp decoding frames, image_claims.cpp before a map's pixels are allocated).
//
// OpenImageIO 2.4's PNG reader leaks a string when its read callback runs out of data (it
// longjmps through libpng past the string's destructor), and says only "hit end of file".
// Walking the chunks first turns a truncated PNG into a precise message and keeps it away
// from that path.
#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace oer::png_detail {

// What the chunks say (PNG specification, 3rd edition, sections 5.3 and 11.2.1).
struct PngLayout {
    // Empty if the bytes hold the PNG signature, an IHDR chunk first and whole chunks up to
    // IEND; otherwise what is wrong, e.g. "truncated PNG: chunk IDAT at byte 57 declares 8192
    // bytes, 4000 remain". CRCs are left to libpng.
    std::string error;
    std::uint32_t width = 0;  // IHDR's fields
    std::uint32_t height = 0;
    int bit_depth = 0;
    int color_type = 0;
    int interlace = 0;
    std::uint64_t idat_bytes = 0;  // the zlib stream of the image data, all IDAT chunks together
};

// Fills `out` with the n bytes at offset; false when fewer are there.
using ByteReader = std::function<bool(std::uint64_t offset, std::uint8_t* out, std::size_t n)>;

PngLayout read_layout(std::uint64_t size, const ByteReader& read);
PngLayout read_layout(std::span<const std::uint8_t> bytes);

}  // namespace oer::png_detail
