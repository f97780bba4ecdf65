#pragma once
// The preview of an environment (GET /v1/environments/{id}/preview.jpg): the map tone-mapped
// (exposure 0, neutral) at 512 x 256 with each light outlined and numbered, as `oer masks`
// draws it. The map is reduced first and the lights' masks mapped onto the reduced grid, so
// the outlines stay one preview pixel wide however large the map is.
#include <string>

#include "oer/core/image.hpp"
#include "oer/lighting/rig.hpp"

namespace oer::server {

inline constexpr int kPreviewWidth = 512;
inline constexpr int kPreviewHeight = 256;

// map: the image the rig's lights were found in (rig.source_width x rig.source_height).
std::string preview_jpeg(const HdrImage& map, const Rig& rig);

}  // namespace oer::server
