#pragma once
// Display transforms: exposure, tone mapping and the sRGB transfer function, for images that
// leave the service as 8-bit (docs/design.md section 3); and the thesis model's tone map.
#include <string>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "oer/core/image.hpp"

namespace oer {

enum class ToneMapper {
    Neutral,  // Khronos PBR Neutral Tone Mapper (Khronos Group, 2024), the product-viewer standard
    Aces,     // ACES RRT + ODT, Stephen Hill's fit (BakingLab ACES.hlsl, 2016)
    None,     // clamp only
};
std::string to_string(ToneMapper mapper);
ToneMapper tone_mapper_from_string(const std::string& name);  // throws oer::Error

// Linear radiance (after exposure) above this maps to white whatever the mapper; tone_map and
// the shaders clamp their input to it, so that no finite or infinite radiance gives NaN.
constexpr float kToneMapInputCap = 1e6f;

glm::vec3 tone_map(glm::vec3 linear, ToneMapper mapper);

// sRGB transfer function (IEC 61966-2-1) of a value in [0, 1].
float srgb_encode(float linear);
float srgb_decode(float encoded);

// Linear radiance -> display-referred sRGB values in [0, 1]: scale by 2^exposure,
// tone map, encode.
HdrImage to_display(const HdrImage& linear, double exposure, ToneMapper mapper);

// The thesis model's tone map (docs/design.md section 2, lighting model "thesis"): the global
// operator of Reinhard, Stark, Shirley and Ferwerda, "Photographic Tone Reproduction for Digital
// Images", 2002 (key 0.18 over the log-average luminance, L / (1 + L) per channel),
// then normalised so that the largest value is 1. Our reading of "tone map and normalise to
// [0, 1] before projection"; a black map stays black.
HdrImage thesis_tone_map(const HdrImage& linear);

}  // namespace oer
