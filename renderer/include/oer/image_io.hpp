#pragma once
// Reading environment maps (equirect .hdr / .exr, grey, RGB or RGBA, half or float) through
// OpenImageIO with validation, and writing images. Every failure is an oer::Error that names
// the file (or "<memory>") and the problem.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "oer/image.hpp"

namespace oer {

struct ImageLimits {
    std::uint64_t max_pixels =
        64ull * 1024 * 1024;  // checked against the header, before allocating
    int max_dimension = 32768;
};

// Pixels that were not finite non-negative radiance, and what they became:
// NaN and negative -> 0, +Inf -> the largest finite float.
struct RepairCounts {
    std::uint64_t nan = 0;
    std::uint64_t inf = 0;
    std::uint64_t negative = 0;
};

struct LoadedImage {
    HdrImage image;
    RepairCounts repaired;
};

// Repairs in place and counts (also used for generated or resampled maps).
RepairCounts repair_radiance(HdrImage& image);

LoadedImage load_image_file(const std::string& path, const ImageLimits& limits = {});
// name is used in error messages; format is detected from the bytes.
LoadedImage load_image_memory(std::span<const std::byte> bytes, const std::string& name,
                              const ImageLimits& limits = {});

// Writes linear float data (.exr, .hdr) as is; for 8-bit formats (.png, .jpg) the pixels must
// already be display-referred values in [0, 1] (sRGB-encoded), they are quantised.
void write_image_file(const HdrImage& image, const std::string& path);

}  // namespace oer
