#pragma once
// Encoding frames for the wire: 8-bit sRGB JPEG (libjpeg-turbo) and PNG (with alpha), and
// linear float EXR, all in memory.
#include <cstdint>
#include <string>
#include <vector>

#include "oer/image.hpp"

namespace oer {

// An 8-bit display image, row 0 at the top, RGBA (alpha 255 where opaque).
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;  // width * height * 4
};

std::vector<std::uint8_t> encode_jpeg(const Rgba8Image& image, int quality);  // quality 1..100
std::vector<std::uint8_t> encode_png(const Rgba8Image& image);                // keeps alpha
// RGBA linear float, row 0 at the top, alpha as given.
std::vector<std::uint8_t> encode_exr(int width, int height, const std::vector<float>& rgba);

// Decoding, for tests and clients: JPEG and PNG to RGBA8.
Rgba8Image decode_8bit(const std::vector<std::uint8_t>& bytes);

}  // namespace oer
