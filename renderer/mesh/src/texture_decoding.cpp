// Textures: PNG and JPEG through stb_image, size-checked on the header first
// (see texture_decoding.hpp).
#include "texture_decoding.hpp"

#include <stb_image.h>

#include <array>
#include <climits>
#include <cstring>
#include <memory>

#include "mesh_errors.hpp"
#include "oer/core/error.hpp"

namespace oer::mesh_detail {

namespace {

constexpr std::array<unsigned char, 8> png_signature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

bool is_png(std::span<const std::byte> bytes) {
    return bytes.size() >= png_signature.size() &&
           std::memcmp(bytes.data(), png_signature.data(), png_signature.size()) == 0;
}

bool is_jpeg(std::span<const std::byte> bytes) {
    return bytes.size() >= 3 && bytes[0] == std::byte{0xff} && bytes[1] == std::byte{0xd8} &&
           bytes[2] == std::byte{0xff};
}

std::uint32_t big_endian_u32(std::span<const std::byte> bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        value = (value << 8) | std::uint32_t(bytes[at + i]);
    }
    return value;
}

const unsigned char* as_uchar(std::span<const std::byte> bytes) {
    return reinterpret_cast<const unsigned char*>(bytes.data());
}

}  // namespace

ImageHeader check_image_header(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                               const std::string& what) {
    if (encoded.size() > std::size_t(INT_MAX)) {
        throw Error(ErrorKind::LimitExceeded, what + ": the encoded image is larger than 2 GiB");
    }
    std::uint64_t width = 0;
    std::uint64_t height = 0;
    if (is_png(encoded)) {
        // The signature, then the IHDR chunk: length 13, "IHDR", width, height (big-endian).
        constexpr std::size_t ihdr = 8;
        if (encoded.size() < ihdr + 16 || big_endian_u32(encoded, ihdr) != 13 ||
            std::memcmp(encoded.data() + ihdr + 4, "IHDR", 4) != 0) {
            throw Error(ErrorKind::InvalidInput, what + ": damaged PNG (no IHDR chunk first)");
        }
        width = big_endian_u32(encoded, ihdr + 8);
        height = big_endian_u32(encoded, ihdr + 12);
    } else if (is_jpeg(encoded)) {
        int w = 0;
        int h = 0;
        int components = 0;
        if (stbi_info_from_memory(as_uchar(encoded), int(encoded.size()), &w, &h, &components) ==
            0) {
            const char* reason = stbi_failure_reason();
            throw Error(ErrorKind::InvalidInput,
                        what + ": damaged JPEG header" +
                            (reason != nullptr ? " (" + one_line(reason) + ")" : ""));
        }
        width = std::uint64_t(w);
        height = std::uint64_t(h);
    } else {
        throw Error(ErrorKind::Unsupported, what + ": only PNG and JPEG images are supported");
    }
    if (width == 0 || height == 0) {
        throw Error(ErrorKind::InvalidInput, what + ": the image header says it is " +
                                                 std::to_string(width) + "x" +
                                                 std::to_string(height) + " pixels");
    }
    if (width * height > max_pixels) {  // both < 2^32: no overflow
        throw Error(ErrorKind::LimitExceeded, what + ": the image is " + std::to_string(width) +
                                                  "x" + std::to_string(height) +
                                                  " pixels, more than the limit of " +
                                                  std::to_string(max_pixels) + " pixels");
    }
    if (width > std::uint64_t(INT_MAX) || height > std::uint64_t(INT_MAX)) {
        throw Error(ErrorKind::LimitExceeded, what + ": the image is too large");
    }
    return ImageHeader{int(width), int(height)};
}

Texture decode_texture(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                       const std::string& what) {
    const ImageHeader header = check_image_header(encoded, max_pixels, what);
    int width = 0;
    int height = 0;
    int components = 0;
    const std::unique_ptr<unsigned char, void (*)(void*)> pixels(
        stbi_load_from_memory(as_uchar(encoded), int(encoded.size()), &width, &height, &components,
                              4),
        stbi_image_free);
    if (pixels == nullptr) {
        const char* reason = stbi_failure_reason();
        throw Error(ErrorKind::InvalidInput,
                    what + ": the image cannot be decoded" +
                        (reason != nullptr ? " (" + one_line(reason) + ")" : ""));
    }
    if (width != header.width || height != header.height) {
        throw Error(ErrorKind::InvalidInput, what +
                                                 ": the image decoded to another size than "
                                                 "its header says");
    }
    Texture texture;
    texture.width = width;
    texture.height = height;
    const std::size_t bytes = std::size_t(width) * std::size_t(height) * 4;
    texture.rgba.assign(pixels.get(), pixels.get() + bytes);
    return texture;
}

}  // namespace oer::mesh_detail
