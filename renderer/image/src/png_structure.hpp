#pragma once
// Private to image_encoding.cpp: a PNG's chunk structure, checked before the bytes reach
// OpenImageIO.
//
// OpenImageIO 2.4's PNG reader leaks a string when its read callback runs out of data (it
// longjmps through libpng past the string's destructor), and says only "hit end of file".
// Walking the chunks first turns a truncated PNG into a precise message and keeps it away
// from that path.
#include <cstdint>
#include <span>
#include <string>

namespace oer::png_detail {

// Empty if bytes hold the PNG signature, an IHDR chunk first and whole chunks up to IEND;
// otherwise what is wrong, e.g. "truncated PNG: chunk IDAT at byte 57 declares 8192 bytes,
// 4000 remain". CRCs are left to libpng.
std::string structure_error(std::span<const std::uint8_t> bytes);

}  // namespace oer::png_detail
