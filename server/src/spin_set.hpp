#pragma once
// A turntable's views as one file (GET /v1/jobs/{id}/sequences/{name}): an animated WebP that
// loops (libwebpmux's WebPAnimEncoder, from Debian's libwebp, the library that already decodes
// glTF's WebP textures), or a sprite sheet, the views in rows, left to right, as one PNG or
// JPEG through the frames' own encoders; what viewers without WebP animation (a CSS
// background-position spin, a <canvas>) take.
#include <string>
#include <vector>

#include "oer/core/image.hpp"

namespace oer::server {

// frame_ms: how long each view shows (1 to 65535); quality 1..100 (lossy; 100 with alpha
// kept). Throws oer::Error (InvalidInput) for frames of different sizes, Internal when the
// encoder fails.
std::string animated_webp(const std::vector<Rgba8Image>& views, int frame_ms, int quality);

// The views in rows of `columns` (the last row may be short, its rest transparent).
Rgba8Image sprite_sheet(const std::vector<Rgba8Image>& views, int columns);

}  // namespace oer::server
