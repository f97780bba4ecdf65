#pragma once
// Encoding frames for the wire: 8-bit sRGB JPEG (libjpeg-turbo) and PNG (with alpha), and
// linear float EXR, all in memory (no temporary files).
//
// Errors are oer::Error: InvalidInput for a bad size, a buffer that does not match it, a JPEG
// quality outside 1..100 or bytes that do not decode; LimitExceeded for a JPEG over 65535
// pixels per side or a decoded image over 64 Mpixel; Internal if a codec library fails.
#include <cstdint>
#include <string>
#include <vector>

#include "oer/core/image.hpp"

namespace oer {

// Baseline JPEG, alpha ignored; chroma 4:2:0 below quality 90, 4:4:4 with the accurate DCT
// from 90 on.
std::vector<std::uint8_t> encode_jpeg(const Rgba8Image& image, int quality);  // quality 1..100
std::vector<std::uint8_t> encode_png(const Rgba8Image& image);                // keeps alpha
// RGBA linear float, row 0 at the top, alpha as given; 32-bit float channels R, G, B, A,
// zip compression.
std::vector<std::uint8_t> encode_exr(int width, int height, const std::vector<float>& rgba);

// Decoding, for tests and clients: JPEG and PNG (chosen by their signature) to RGBA8. PNG:
// grey is replicated, missing alpha is 255, 16-bit is scaled to 8. JPEG: alpha 255; a
// truncated or corrupt JPEG is an error.
Rgba8Image decode_8bit(const std::vector<std::uint8_t>& bytes);

}  // namespace oer
