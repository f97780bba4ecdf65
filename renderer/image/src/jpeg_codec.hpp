#pragma once
// Private to image_encoding.cpp: JPEG through TurboJPEG (libjpeg-turbo), RGBA8 in and out.
// The callers validate sizes and quality first.
#include <cstdint>
#include <span>
#include <vector>

#include "oer/image/image_encoding.hpp"

namespace oer::jpeg_detail {

// Baseline JPEG; chroma 4:2:0 below quality 90, 4:4:4 (and the accurate DCT) from 90 on.
// Alpha is ignored. Throws oer::Error (Internal) if libjpeg-turbo fails.
std::vector<std::uint8_t> encode(const Rgba8Image& image, int quality);

// RGBA8 with alpha 255. Throws oer::Error: InvalidInput for a corrupt or truncated JPEG (a
// warning is an error here), LimitExceeded over max_pixels.
Rgba8Image decode(std::span<const std::uint8_t> bytes, std::uint64_t max_pixels);

}  // namespace oer::jpeg_detail
