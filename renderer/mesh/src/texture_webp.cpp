// WebP textures (EXT_texture_webp) through Debian's libwebp (see texture_formats.hpp).
#include <webp/decode.h>

#include <cstring>
#include <string>

#include "oer/core/error.hpp"
#include "texture_formats.hpp"

namespace oer::mesh_detail {

namespace {

const std::uint8_t* as_uint8(std::span<const std::byte> bytes) {
    return reinterpret_cast<const std::uint8_t*>(bytes.data());
}

// libwebp's status as the reason an image is refused.
std::string webp_status_text(VP8StatusCode status) {
    switch (status) {
        case VP8_STATUS_NOT_ENOUGH_DATA:
            return "truncated WebP: the bitstream ends early";
        case VP8_STATUS_BITSTREAM_ERROR:
            return "corrupt WebP bitstream";
        case VP8_STATUS_UNSUPPORTED_FEATURE:
            return "WebP feature libwebp does not support";
        case VP8_STATUS_INVALID_PARAM:
            return "WebP decoding refused its parameters";
        case VP8_STATUS_OUT_OF_MEMORY:
            return "out of memory decoding the WebP";
        default:
            return "WebP decoding failed (libwebp status " + std::to_string(int(status)) + ")";
    }
}

}  // namespace

bool is_webp(std::span<const std::byte> bytes) {
    // A RIFF container of form type "WEBP" (RIFF's length at 4..7).
    return bytes.size() >= 12 && std::memcmp(bytes.data(), "RIFF", 4) == 0 &&
           std::memcmp(bytes.data() + 8, "WEBP", 4) == 0;
}

ImageHeader webp_header(std::span<const std::byte> bytes, std::uint64_t max_pixels,
                        const std::string& what) {
    // WebPGetFeatures reads the RIFF, VP8X and the first frame's headers only, not the
    // pixels: a "WebP bomb" (up to 16383x16383 declared in a few bytes) is refused here, before
    // libwebp or we allocate anything for it.
    WebPBitstreamFeatures features;
    const VP8StatusCode status = WebPGetFeatures(as_uint8(bytes), bytes.size(), &features);
    if (status == VP8_STATUS_NOT_ENOUGH_DATA) {
        throw Error(ErrorKind::InvalidInput, what + ": truncated WebP: its header is incomplete");
    }
    if (status != VP8_STATUS_OK) {
        throw Error(ErrorKind::InvalidInput,
                    what + ": damaged WebP header (" + webp_status_text(status) + ")");
    }
    if (features.has_animation != 0) {
        throw Error(ErrorKind::Unsupported,
                    what + ": animated WebP is not supported (a texture is one image)");
    }
    check_pixel_count(std::uint64_t(features.width), std::uint64_t(features.height), max_pixels,
                      what);
    return ImageHeader{ImageFormat::Webp, features.width, features.height};
}

void decode_webp(std::span<const std::byte> bytes, const ImageHeader& header,
                 std::span<unsigned char> rgba, const std::string& what) {
    WebPDecoderConfig config;
    if (WebPInitDecoderConfig(&config) == 0) {
        throw Error(ErrorKind::Internal, what + ": libwebp's ABI differs from its header's");
    }
    // Straight (not premultiplied) RGBA, as PNG stores it and the renderer uploads it, into
    // our buffer (WebPDecBuffer's external memory).
    config.output.colorspace = MODE_RGBA;
    config.output.is_external_memory = 1;
    config.output.u.RGBA.rgba = rgba.data();
    config.output.u.RGBA.stride = header.width * 4;
    config.output.u.RGBA.size = rgba.size();
    const VP8StatusCode status = WebPDecode(as_uint8(bytes), bytes.size(), &config);
    // Frees nothing of ours (external memory), only what libwebp may have kept on failure.
    WebPFreeDecBuffer(&config.output);
    if (status != VP8_STATUS_OK) {
        throw Error(ErrorKind::InvalidInput,
                    what + ": the image cannot be decoded (" + webp_status_text(status) + ")");
    }
    if (config.output.width != header.width || config.output.height != header.height) {
        throw Error(ErrorKind::InvalidInput,
                    what + ": the WebP decoded to another size than its header says");
    }
}

}  // namespace oer::mesh_detail
