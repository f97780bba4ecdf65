// Textures: PNG and JPEG through stb_image, WebP, AVIF and KTX2 in texture_webp.cpp,
// texture_avif.cpp and texture_ktx2.cpp, each size-checked on its header first (see
// texture_decoding.hpp).
#include "texture_decoding.hpp"

#include <stb_image.h>

#include <array>
#include <climits>
#include <cstring>
#include <memory>
#include <string_view>

#include "mesh_errors.hpp"
#include "oer/core/error.hpp"
#include "texture_formats.hpp"

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

bool starts_with(std::span<const std::byte> bytes, std::size_t at, std::string_view text) {
    return bytes.size() >= at + text.size() &&
           std::memcmp(bytes.data() + at, text.data(), text.size()) == 0;
}

// The name of an image format the loader does not read, from its signature, or empty.
std::string unsupported_format(std::span<const std::byte> bytes) {
    using namespace std::string_view_literals;  // signatures holding NUL bytes
    if (starts_with(bytes, 4, "ftypheic") || starts_with(bytes, 4, "ftypmif1")) {
        return "HEIF";
    }
    if (starts_with(bytes, 0, "GIF87a") || starts_with(bytes, 0, "GIF89a")) {
        return "GIF";
    }
    if (starts_with(bytes, 0, "BM")) {
        return "BMP";
    }
    if (starts_with(bytes, 0, "II*\0"sv) || starts_with(bytes, 0, "MM\0*"sv)) {
        return "TIFF";
    }
    if (starts_with(bytes, 0, "\xabKTX 11\xbb")) {
        return "KTX 1";
    }
    if (starts_with(bytes, 0, "DDS ")) {
        return "DDS";
    }
    return "";
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

ImageHeader png_or_jpeg_header(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                               const std::string& what) {
    std::uint64_t width = 0;
    std::uint64_t height = 0;
    ImageFormat format = ImageFormat::Png;
    if (is_png(encoded)) {
        // The signature, then the IHDR chunk: length 13, "IHDR", width, height (big-endian).
        constexpr std::size_t ihdr = 8;
        if (encoded.size() < ihdr + 16 || big_endian_u32(encoded, ihdr) != 13 ||
            std::memcmp(encoded.data() + ihdr + 4, "IHDR", 4) != 0) {
            throw Error(ErrorKind::InvalidInput, what + ": damaged PNG (no IHDR chunk first)");
        }
        width = big_endian_u32(encoded, ihdr + 8);
        height = big_endian_u32(encoded, ihdr + 12);
    } else {
        format = ImageFormat::Jpeg;
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
    }
    check_pixel_count(width, height, max_pixels, what);
    return ImageHeader{format, int(width), int(height)};
}

void decode_png_or_jpeg(std::span<const std::byte> encoded, const ImageHeader& header,
                        Texture& texture, const std::string& what) {
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
    const std::size_t bytes = std::size_t(width) * std::size_t(height) * 4;
    texture.rgba.assign(pixels.get(), pixels.get() + bytes);
}

}  // namespace

void check_pixel_count(std::uint64_t width, std::uint64_t height, std::uint64_t max_pixels,
                       const std::string& what) {
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
}

ImageHeader check_image_header(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                               const std::string& what) {
    if (encoded.size() > std::size_t(INT_MAX)) {
        throw Error(ErrorKind::LimitExceeded, what + ": the encoded image is larger than 2 GiB");
    }
    if (is_png(encoded) || is_jpeg(encoded)) {
        return png_or_jpeg_header(encoded, max_pixels, what);
    }
    if (is_webp(encoded)) {
        return webp_header(encoded, max_pixels, what);
    }
    if (is_avif(encoded)) {
        return avif_header(encoded, max_pixels, what);
    }
    if (is_ktx2(encoded)) {
        return ktx2_header(encoded, max_pixels, what);
    }
    const std::string format = unsupported_format(encoded);
    throw Error(ErrorKind::Unsupported,
                what + ": " +
                    (format.empty() ? "the image's format is not recognised (no PNG, JPEG, WebP "
                                      "or KTX2 signature)"
                                    : format + " images are not supported") +
                    "; textures are PNG, JPEG, WebP (EXT_texture_webp) or AVIF "
                    "(EXT_texture_avif)");
}

Texture decode_texture(std::span<const std::byte> encoded, std::uint64_t max_pixels,
                       const std::string& what) {
    const ImageHeader header = check_image_header(encoded, max_pixels, what);
    Texture texture;
    texture.width = header.width;
    texture.height = header.height;
    switch (header.format) {
        case ImageFormat::Png:
        case ImageFormat::Jpeg:
            decode_png_or_jpeg(encoded, header, texture, what);
            break;
        case ImageFormat::Webp:
            texture.rgba.resize(std::size_t(header.width) * std::size_t(header.height) * 4);
            decode_webp(encoded, header, texture.rgba, what);
            break;
        case ImageFormat::Avif:
            texture.rgba.resize(std::size_t(header.width) * std::size_t(header.height) * 4);
            decode_avif(encoded, header, texture.rgba, what);
            break;
        case ImageFormat::Ktx2:
            refuse_ktx2_decoding(encoded, what);
    }
    return texture;
}

}  // namespace oer::mesh_detail
