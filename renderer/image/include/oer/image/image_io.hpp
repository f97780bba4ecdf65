#pragma once
// Reading environment maps (equirect .hdr / .exr, grey, RGB or RGBA, half or float) through
// OpenImageIO with validation, and writing images. Every failure is an oer::Error that names
// the file (or "<memory>") and the problem.
//
// Loading:
// - any format OpenImageIO reads; the format is chosen from the bytes' signature first, then
//   the name's extension (so a mis-named file still loads);
// - subimage 0, MIP level 0; the data window's size (any aspect: the loader does not require
//   2:1);
// - channels: 1 (grey) is replicated to RGB, 2 (grey + alpha) uses the first, 3 or more use the
//   first three (R, G, B); alpha is ignored (color is taken as stored, not multiplied by it);
// - half, float and double data is linear radiance as is; integer data (8-bit PNG / JPEG,
//   16-bit PNG / TIFF) is taken as sRGB-encoded and decoded to linear, unless the file declares
//   a linear color space;
// - the header is validated before any pixel memory is allocated: the size against the limits,
//   then, for Radiance RGBE, OpenEXR, PNG and JPEG, against the bytes: a file smaller than the
//   fewest bytes that can encode the pixels it claims is refused (image_claims.cpp derives each
//   format's minimum from its specification), before any reader allocates for it;
// - every load runs repair_radiance and returns its counts.
// Errors: ErrorKind::Io (missing or unreadable file), InvalidInput (not an image, truncated,
// corrupt, zero size, a size its bytes cannot hold: "claims 8192x8192 pixels but 155 bytes
// cannot hold them (RLE needs at least ...)"), LimitExceeded (over ImageLimits), Unsupported
// (deep or volume images).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "oer/core/image.hpp"

namespace oer {

// Checked against the header, before any pixel memory is allocated.
struct ImageLimits {
    std::uint64_t max_pixels = 64ull * 1024 * 1024;  // width * height, in 64-bit arithmetic
    int max_dimension = 32768;                       // per side
};

// Pixel components (one R, G or B value each: a pixel with NaN in two channels counts 2) that
// were not finite non-negative radiance, and what they became:
// NaN -> 0, negative (including -Inf) -> 0, +Inf -> the largest finite float. -0 is left as is.
struct RepairCounts {
    std::uint64_t nan = 0;
    std::uint64_t inf = 0;
    std::uint64_t negative = 0;
};

// What a source's values are: scene-referred radiance (High: float formats such as EXR and
// Radiance RGBE) or display-referred values decoded from sRGB and clipped at white (Low: the
// integer formats, such as the JPEG and PNG panoramas phones make), whose lights are as bright
// as the white the camera clipped them to.
enum class DynamicRange : std::uint8_t { High, Low };
std::string to_string(DynamicRange range);                        // "hdr", "ldr"
DynamicRange dynamic_range_from_string(const std::string& name);  // throws oer::Error

struct LoadedImage {
    HdrImage image;
    RepairCounts repaired;
    DynamicRange range = DynamicRange::High;
};

// Repairs in place and counts (also used for generated or resampled maps).
RepairCounts repair_radiance(HdrImage& image);

// The image format the bytes' signature names: "hdr" (Radiance RGBE, "#?"), "openexr", "png",
// "jpeg" or "tiff"; empty when they start with none of these. Looks at the first 4 bytes only:
// the loaders try this format first, and the service checks an upload's declared media type
// against it.
std::string image_format_of(std::span<const std::byte> bytes);

// What a load would read and allocate, known from the header alone.
struct ImageHeader {
    std::string format;  // OpenImageIO's reader: "hdr", "openexr", "png", "jpeg", "tiff", ...
    int width = 0;
    int height = 0;
    int channels = 0;  // in the file
    // The most memory a full load of these bytes allocates at once: the loaded image (12 bytes
    // a pixel), the 8- or 16-bit buffer integer pixels are read into first, OpenImageIO's
    // buffer for converting a chunk of scanlines or a row of tiles, and a reader's buffer of
    // the whole image (PNG's decoded rows, a progressive JPEG's coefficients); the reader's
    // buffers of a few rows are left out.
    std::uint64_t decode_bytes = 0;
};

// Every check load_image_memory makes before it reads pixels (the header against the limits
// and against the bytes), without reading pixels; throws what load_image_memory would throw
// for them.
ImageHeader probe_image_memory(std::span<const std::byte> bytes, const std::string& name,
                               const ImageLimits& limits = {});

LoadedImage load_image_file(const std::string& path, const ImageLimits& limits = {});
// name is used in error messages (and its extension as a format hint); the format is
// detected from the bytes.
LoadedImage load_image_memory(std::span<const std::byte> bytes, const std::string& name,
                              const ImageLimits& limits = {});

// Chosen by the path's extension (case-insensitive):
// - .exr: 32-bit float RGB, zip compression; .hdr: Radiance RGBE. Linear data is written as is
//   (RGBE keeps ~1 % relative precision and cannot hold negative values).
// - .png, .jpg / .jpeg: 8-bit; the pixels must already be display-referred values in [0, 1]
//   (sRGB-encoded): they are clamped to [0, 1] and rounded to 1/255 (NaN -> 0).
// Not atomic: a failed write may leave a partial file. Errors name the path: Unsupported
// (other extensions), Io (cannot create or write), InvalidInput (inconsistent image).
void write_image_file(const HdrImage& image, const std::string& path);

}  // namespace oer
