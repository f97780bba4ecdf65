// Writing images through OpenImageIO (see oer/image_io.hpp): linear float to .exr and .hdr,
// display-referred values quantised to 8 bits for .png and .jpg.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "image_io_errors.hpp"
#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"

namespace oer {

namespace {

using image_io_detail::fail;
using image_io_detail::one_line;

enum class Encoding { LinearFloat, Display8 };

std::uint8_t quantise(float value) {
    // NaN compares false and becomes 0; the rest is clamped to [0, 1] and rounded.
    const float clamped = value > 0.0f ? std::min(value, 1.0f) : 0.0f;
    return std::uint8_t(clamped * 255.0f + 0.5f);
}

}  // namespace

void write_image_file(const HdrImage& image, const std::string& path) {
    if (image.width <= 0 || image.height <= 0 || image.pixels.size() != image.pixel_count() * 3) {
        fail(ErrorKind::InvalidInput, path,
             "cannot write an image of " + std::to_string(image.width) + "x" +
                 std::to_string(image.height) + " with " + std::to_string(image.pixels.size()) +
                 " values");
    }
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    Encoding encoding;
    if (extension == ".exr" || extension == ".hdr") {
        encoding = Encoding::LinearFloat;
    } else if (extension == ".png" || extension == ".jpg" || extension == ".jpeg") {
        encoding = Encoding::Display8;
    } else {
        fail(ErrorKind::Unsupported, path,
             "unsupported output format '" + extension + "' (use .exr, .hdr, .png or .jpg)");
    }

    OIIO::geterror();  // start from a clean global error
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
    if (!out) {
        fail(ErrorKind::Unsupported, path,
             "no image writer (OpenImageIO: " + one_line(OIIO::geterror()) + ")");
    }
    const bool linear = encoding == Encoding::LinearFloat;
    OIIO::ImageSpec spec(image.width, image.height, 3,
                         linear ? OIIO::TypeFloat : OIIO::TypeDesc(OIIO::TypeDesc::UINT8));
    spec.attribute("oiio:ColorSpace", linear ? "Linear" : "sRGB");
    if (extension == ".exr") {
        spec.attribute("compression", "zip");
    } else if (extension == ".jpg" || extension == ".jpeg") {
        spec.attribute("Compression", "jpeg:95");
    }
    if (!out->open(path, spec)) {
        fail(ErrorKind::Io, path, "cannot create the file (" + one_line(out->geterror()) + ")");
    }
    bool ok;
    if (linear) {
        ok = out->write_image(OIIO::TypeFloat, image.pixels.data());
    } else {
        std::vector<std::uint8_t> bytes(image.pixels.size());
        std::transform(image.pixels.begin(), image.pixels.end(), bytes.begin(), quantise);
        ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    ok = out->close() && ok;
    if (!ok) {
        fail(ErrorKind::Io, path, "cannot write the image (" + one_line(out->geterror()) + ")");
    }
}

}  // namespace oer
