// Environment map uploads: oer::probe_image_memory and oer::load_image_memory
// (renderer/image/include/oer/image/image_io.hpp), as the service reads a map's bytes
// (server/src/routes_environments.cpp, environment_registry.cpp): bytes whose signature names
// another format than the declared one are refused (415) before any decoding, so the declared
// type is the signature's, or, for bytes of no known signature, one of the four map types
// chosen by the input's size; then the header is probed, its decode cost held to the upload's
// expansion bound (server/src/upload_budget.hpp), and the map loaded at the service's default
// limits. Bytes of no known signature reach the declared type's reader, then every reader
// OpenImageIO has behind a signature.
//
// Checked beyond the documented refusals: a load agrees with its probe (format, size), its
// pixels are finite and non-negative (repair_radiance), and the resident set grows while loading
// by at most the probe's figure (decode_bytes) plus a quarter and 16 MiB (the readers' row
// buffers and tables, and AddressSanitizer's shadow of what the load touches; the margin of
// tests/image/image_io_test.cpp is 5 % and 4 MiB without the sanitizer).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "oer/image/image_io.hpp"

namespace {

// The formats an environment may be uploaded as (routes_environments.cpp's kImageMediaTypes),
// by image_format_of's name, with the extension the service names the upload with.
struct MapFormat {
    std::string_view format;
    std::string_view extension;
};
constexpr std::array<MapFormat, 4> kMapFormats = {
    {{"hdr", "hdr"}, {"openexr", "exr"}, {"jpeg", "jpg"}, {"png", "png"}}};

void load(std::span<const std::byte> bytes) {
    const std::string signature = oer::image_format_of(bytes);
    std::string_view extension = kMapFormats[bytes.size() % kMapFormats.size()].extension;
    if (!signature.empty()) {
        const auto declared =
            std::find_if(kMapFormats.begin(), kMapFormats.end(),
                         [&](const MapFormat& map) { return map.format == signature; });
        if (declared == kMapFormats.end()) {
            return;  // a TIFF: no map type, refused before decoding (415)
        }
        extension = declared->extension;
    }
    const std::string name = "upload." + std::string(extension);
    const oer::ImageLimits limits = oer::fuzz::service_image_limits();
    const oer::ImageHeader header = oer::probe_image_memory(bytes, name, limits);
    if (header.decode_bytes > oer::fuzz::upload_expansion_bound(bytes.size())) {
        return;  // refused by the service before decoding (413)
    }
    oer::fuzz::ResidentGrowth growth;
    const oer::LoadedImage loaded = oer::load_image_memory(bytes, name, limits);
    const std::uint64_t grown = growth.bytes();
    const oer::HdrImage& image = loaded.image;
    if (image.width != header.width || image.height != header.height) {
        oer::fuzz::finding("the probe said " + std::to_string(header.width) + "x" +
                           std::to_string(header.height) + ", the load gave " +
                           std::to_string(image.width) + "x" + std::to_string(image.height));
    }
    if (image.pixels.size() != std::size_t(image.width) * std::size_t(image.height) * 3) {
        oer::fuzz::finding("the loaded image holds " + std::to_string(image.pixels.size()) +
                           " values for its size");
    }
    for (const float value : image.pixels) {
        if (!(std::isfinite(value) && value >= 0.0f)) {
            oer::fuzz::finding("a loaded pixel is " + std::to_string(value) + " after repair");
        }
    }
    const std::uint64_t allowed = header.decode_bytes + header.decode_bytes / 4 + (16u << 20);
    if (grown > allowed) {
        oer::fuzz::finding(header.format + " " + std::to_string(header.width) + "x" +
                           std::to_string(header.height) + ": the load grew the resident set by " +
                           std::to_string(grown) + " bytes, the probe said " +
                           std::to_string(header.decode_bytes));
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    oer::fuzz::parse_or_refuse([&] { load(oer::fuzz::as_bytes(data, size)); });
    return 0;
}
