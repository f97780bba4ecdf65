// AVIF textures (EXT_texture_avif) through Debian's libavif (see texture_formats.hpp).
#include <avif/avif.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "mesh_errors.hpp"
#include "oer/core/error.hpp"
#include "texture_formats.hpp"

namespace oer::mesh_detail {

namespace {

struct DecoderDeleter {
    void operator()(avifDecoder* decoder) const { avifDecoderDestroy(decoder); }
};
using Decoder = std::unique_ptr<avifDecoder, DecoderDeleter>;

// libavif's result and its diagnostic ("ispe box is missing", ...), for messages.
std::string avif_failure_text(avifResult result, const avifDecoder& decoder) {
    std::string text = avifResultToString(result);
    if (decoder.diag.error[0] != '\0') {
        text += ": " + one_line(decoder.diag.error);
    }
    return text;
}

// A decoder over `bytes` (not copied: they outlive it) whose container has been parsed: the
// image's size and count are known, no AV1 data has been decoded. `size_limit`: the pixels
// libavif and the AV1 decoder may decode, or 0 for libavif's default (16384 x 16384).
Decoder parsed(std::span<const std::byte> bytes, std::uint32_t size_limit,
               const std::string& what) {
    Decoder decoder(avifDecoderCreate());
    if (decoder == nullptr) {
        throw Error(ErrorKind::LimitExceeded, what + ": out of memory creating the AVIF decoder");
    }
    // One thread, as every other texture decode: the service decodes meshes on its own workers.
    // One image: EXT_texture_avif textures are still images, and libavif's default would let
    // a sequence claim thousands of frames.
    decoder->maxThreads = 1;
    decoder->imageCountLimit = 1;
    if (size_limit != 0) {
        decoder->imageSizeLimit = size_limit;
    }
    decoder->ignoreExif = AVIF_TRUE;
    decoder->ignoreXMP = AVIF_TRUE;
    avifResult result = avifDecoderSetIOMemory(
        decoder.get(), reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    if (result == AVIF_RESULT_OK) {
        result = avifDecoderParse(decoder.get());
    }
    if (result == AVIF_RESULT_TRUNCATED_DATA) {
        throw Error(ErrorKind::InvalidInput, what + ": truncated AVIF: its container ends early (" +
                                                 avif_failure_text(result, *decoder) + ")");
    }
    if (result != AVIF_RESULT_OK) {
        throw Error(ErrorKind::InvalidInput, what + ": damaged AVIF container (" +
                                                 avif_failure_text(result, *decoder) + ")");
    }
    return decoder;
}

}  // namespace

bool is_avif(std::span<const std::byte> bytes) {
    // An ISO BMFF file (ISO/IEC 14496-12) whose first box, "ftyp", names the AV1 Image File
    // Format's brand "avif" (still image) or "avis" (sequence), as its major brand or among its
    // compatible ones.
    if (bytes.size() < 16 || std::memcmp(bytes.data() + 4, "ftyp", 4) != 0) {
        return false;
    }
    std::size_t box = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        box = (box << 8) | std::size_t(bytes[i]);
    }
    box = std::min({box, bytes.size(), std::size_t(256)});
    for (std::size_t at = 8; at + 4 <= box; at += 4) {
        if (at != 12 && (std::memcmp(bytes.data() + at, "avif", 4) == 0 ||
                         std::memcmp(bytes.data() + at, "avis", 4) == 0)) {
            return true;  // at 12: the minor version, not a brand
        }
    }
    return false;
}

ImageHeader avif_header(std::span<const std::byte> bytes, std::uint64_t max_pixels,
                        const std::string& what) {
    // The container's image spatial extents ("ispe") give the size before any AV1 data is
    // decoded: a claim over the limit is refused before the AV1 decoder allocates a frame.
    // libavif's own default limit, larger than ours, leaves that refusal (LimitExceeded) to us.
    const Decoder decoder = parsed(bytes, 0, what);
    check_pixel_count(decoder->image->width, decoder->image->height, max_pixels, what);
    return ImageHeader{ImageFormat::Avif, int(decoder->image->width), int(decoder->image->height)};
}

void decode_avif(std::span<const std::byte> bytes, const ImageHeader& header,
                 std::span<unsigned char> rgba, const std::string& what) {
    // libavif bounds what the AV1 decoder (dav1d) may allocate by the size the header passed
    // the limit with: AV1 data claiming a larger frame than its container is not decoded.
    const Decoder decoder =
        parsed(bytes, std::uint32_t(std::uint64_t(header.width) * header.height), what);
    const avifResult result = avifDecoderNextImage(decoder.get());
    if (result != AVIF_RESULT_OK) {
        throw Error(
            ErrorKind::InvalidInput,
            what + ": the image cannot be decoded (" +
                (result == AVIF_RESULT_TRUNCATED_DATA ? "truncated AVIF: " : "corrupt AVIF: ") +
                avif_failure_text(result, *decoder) + ")");
    }
    const avifImage& image = *decoder->image;
    if (int(image.width) != header.width || int(image.height) != header.height) {
        throw Error(ErrorKind::InvalidInput,
                    what + ": the AVIF decoded to another size than its container says");
    }
    // 8-bit straight RGBA into our buffer; a 10- or 12-bit image is scaled down, full range.
    avifRGBImage rgb;
    avifRGBImageSetDefaults(&rgb, &image);
    rgb.format = AVIF_RGB_FORMAT_RGBA;
    rgb.depth = 8;
    rgb.pixels = rgba.data();
    rgb.rowBytes = std::uint32_t(header.width) * 4;
    const avifResult converted = avifImageYUVToRGB(&image, &rgb);
    if (converted != AVIF_RESULT_OK) {
        throw Error(ErrorKind::InvalidInput, what + ": the AVIF's colours cannot be converted (" +
                                                 avif_failure_text(converted, *decoder) + ")");
    }
}

}  // namespace oer::mesh_detail
