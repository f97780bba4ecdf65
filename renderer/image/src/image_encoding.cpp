// Encoders for the wire (see oer/image_encoding.hpp): JPEG through TurboJPEG (jpeg_codec.cpp),
// PNG and EXR through OpenImageIO, written to memory through an IOProxy (OpenImageIO 2.4's
// PNG and OpenEXR writers both support one: no temporary file).
#include "oer/image/image_encoding.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <string>

#include "jpeg_codec.hpp"
#include "oer/core/error.hpp"
#include "oer/core/one_line.hpp"
#include "oer/core/size_text.hpp"
#include "png_structure.hpp"

namespace oer {

namespace {

// The decoders' pixel limit (the defaults of oer::ImageLimits).
constexpr std::uint64_t max_decoded_pixels = 64ull * 1024 * 1024;
// JPEG's own limit, per side.
constexpr int max_jpeg_side = 65535;

// Checks width, height and the number of values (channels per pixel) before any encoder
// touches the buffer.
void validate(const char* what, int width, int height, std::size_t values, int channels) {
    if (width <= 0 || height <= 0) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": image size " +
                                                 size_text(width, height) +
                                                 " (width and height must be positive)");
    }
    const std::uint64_t expected =
        std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(channels);
    if (values != expected) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": " + size_text(width, height) +
                                                 " RGBA needs " + std::to_string(expected) +
                                                 " values, the buffer has " +
                                                 std::to_string(values));
    }
}

// Writes one image through OpenImageIO's `format` writer into memory.
std::vector<std::uint8_t> write_to_memory(const char* format, const OIIO::ImageSpec& spec,
                                          const void* pixels) {
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(format);
    if (!out) {
        throw Error(ErrorKind::Internal, std::string("OpenImageIO has no ") + format +
                                             " writer: " + detail::one_line(OIIO::geterror()));
    }
    if (!out->supports("ioproxy")) {
        throw Error(ErrorKind::Internal,
                    std::string("OpenImageIO's ") + format + " writer cannot write to memory");
    }
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    const std::string name = std::string("<memory>.") + format;
    if (!out->set_ioproxy(&proxy) || !out->open(name, spec) ||
        !out->write_image(spec.format, pixels) || !out->close()) {
        throw Error(ErrorKind::Internal,
                    std::string(format) + " encoding failed: " + detail::one_line(out->geterror()));
    }
    return bytes;
}

// The alpha convention of Rgba8Image (straight, as PNG stores it), for writing and reading.
constexpr const char* unassociated_alpha = "oiio:UnassociatedAlpha";

Rgba8Image decode_png(const std::vector<std::uint8_t>& bytes) {
    if (const png_detail::PngLayout layout = png_detail::read_layout(bytes);
        !layout.error.empty()) {
        throw Error(ErrorKind::InvalidInput, layout.error);
    }
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create("png");
    if (!in || !in->supports("ioproxy")) {
        throw Error(ErrorKind::Internal, "OpenImageIO has no PNG reader that reads memory");
    }
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    OIIO::ImageSpec config;
    config.attribute(unassociated_alpha, 1);  // keep color as stored, not times alpha
    OIIO::ImageSpec spec;
    if (!in->set_ioproxy(&proxy) || !in->open("<memory>.png", spec, config)) {
        throw Error(ErrorKind::InvalidInput,
                    "not a readable PNG: " + detail::one_line(in->geterror()));
    }
    const int channels = spec.nchannels;
    if (spec.width <= 0 || spec.height <= 0 || channels < 1 || channels > 4) {
        throw Error(ErrorKind::InvalidInput, "PNG of " + size_text(spec.width, spec.height) +
                                                 " with " + std::to_string(channels) + " channels");
    }
    if (std::uint64_t(spec.width) * std::uint64_t(spec.height) > max_decoded_pixels) {
        throw Error(ErrorKind::LimitExceeded, "PNG of " + size_text(spec.width, spec.height) +
                                                  " pixels is over the limit of " +
                                                  std::to_string(max_decoded_pixels) + " pixels");
    }
    const std::size_t count = std::size_t(spec.width) * std::size_t(spec.height);
    std::vector<std::uint8_t> stored(count * std::size_t(channels));
    // 16-bit PNGs are scaled to 8 bits by OpenImageIO.
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, stored.data())) {
        throw Error(ErrorKind::InvalidInput, "corrupt PNG (" + size_text(spec.width, spec.height) +
                                                 "): " + detail::one_line(in->geterror()));
    }
    Rgba8Image image;
    image.width = spec.width;
    image.height = spec.height;
    image.pixels.resize(count * 4);
    // Grey, grey + alpha, RGB or RGBA to RGBA.
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint8_t* source = &stored[i * std::size_t(channels)];
        std::uint8_t* target = &image.pixels[i * 4];
        const bool grey = channels <= 2;
        target[0] = source[0];
        target[1] = grey ? source[0] : source[1];
        target[2] = grey ? source[0] : source[2];
        target[3] = channels == 2 ? source[1] : channels == 4 ? source[3] : 255;
    }
    return image;
}

bool starts_with(const std::vector<std::uint8_t>& bytes, std::initializer_list<int> prefix) {
    return bytes.size() >= prefix.size() &&
           std::equal(prefix.begin(), prefix.end(), bytes.begin(),
                      [](int expected, std::uint8_t actual) { return expected == actual; });
}

}  // namespace

std::vector<std::uint8_t> encode_jpeg(const Rgba8Image& image, int quality) {
    if (quality < 1 || quality > 100) {
        throw Error(ErrorKind::InvalidInput,
                    "JPEG quality " + std::to_string(quality) + " is outside 1..100");
    }
    validate("JPEG", image.width, image.height, image.pixels.size(), 4);
    if (image.width > max_jpeg_side || image.height > max_jpeg_side) {
        throw Error(ErrorKind::LimitExceeded, "JPEG: image size " +
                                                  size_text(image.width, image.height) +
                                                  " is over JPEG's 65535 pixels per side");
    }
    return jpeg_detail::encode(image, quality);
}

std::vector<std::uint8_t> encode_png(const Rgba8Image& image) {
    validate("PNG", image.width, image.height, image.pixels.size(), 4);
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
    spec.attribute(unassociated_alpha, 1);  // color is not multiplied by alpha: keep it
    // zlib level 6 (the default) took twice the time of level 3 (24 ms against 13 ms) for a
    // fifth fewer bytes on a 512x512 test frame; a frame is sent once, soon: favour time.
    spec.attribute("png:compressionLevel", 3);
    return write_to_memory("png", spec, image.pixels.data());
}

std::vector<std::uint8_t> encode_exr(int width, int height, const std::vector<float>& rgba) {
    validate("EXR", width, height, rgba.size(), 4);
    OIIO::ImageSpec spec(width, height, 4, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    return write_to_memory("openexr", spec, rgba.data());
}

Rgba8Image decode_8bit(const std::vector<std::uint8_t>& bytes) {
    if (starts_with(bytes, {0xff, 0xd8, 0xff})) {
        return jpeg_detail::decode(bytes, max_decoded_pixels);
    }
    if (starts_with(bytes, {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) {
        return decode_png(bytes);
    }
    throw Error(ErrorKind::InvalidInput, "not a JPEG or PNG image (" +
                                             std::to_string(bytes.size()) +
                                             " bytes with neither signature)");
}

}  // namespace oer
