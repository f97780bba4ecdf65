#include "oer/lighting/tonemap.hpp"

#include <algorithm>
#include <cmath>

#include "oer/core/enum_names.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/light_location.hpp"

namespace oer {

namespace {
constexpr EnumNames<ToneMapper, 3> kToneMapperNames = {
    {{ToneMapper::Neutral, "neutral"}, {ToneMapper::Aces, "aces"}, {ToneMapper::None, "none"}}};
}  // namespace

std::string to_string(ToneMapper mapper) {
    return name_of(mapper, kToneMapperNames);
}

ToneMapper tone_mapper_from_string(const std::string& name) {
    return value_named(name, kToneMapperNames, "tone mapper");
}

namespace {

// Khronos PBR Neutral tone mapper (Khronos Group, "PBR Neutral Tone Mapper", 2024; E. Lalish),
// its reference GLSL: a toe offset below 0.08, then highlight compression above 0.76 towards a
// peak of 1, desaturated by 0.15.
glm::vec3 neutral(glm::vec3 color) {
    constexpr float start_compression = 0.8f - 0.04f;
    constexpr float desaturation = 0.15f;
    const float x = std::min(color.r, std::min(color.g, color.b));
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    color -= offset;
    const float peak = std::max(color.r, std::max(color.g, color.b));
    if (peak < start_compression) {
        return color;
    }
    constexpr float d = 1.0f - start_compression;
    const float new_peak = 1.0f - d * d / (peak + d - start_compression);
    color *= new_peak / peak;
    const float g = 1.0f - 1.0f / (desaturation * (peak - new_peak) + 1.0f);
    return color * (1.0f - g) + glm::vec3(new_peak) * g;
}

// The ACES reference rendering and output transforms (RRT + ODT, sRGB display) as fitted by
// Stephen Hill (BakingLab, ACES.hlsl, 2016): sRGB to the RRT's input space by a matrix, the
// rational fit (x (x + 0.0245786) - 0.000090537) / (x (0.983729 x + 0.432951) + 0.238081) per
// channel, and back by the output matrix. (Not Narkowicz's 2015 single-curve fit.)
glm::vec3 aces(glm::vec3 c) {
    const glm::vec3 v{0.59719f * c.r + 0.35458f * c.g + 0.04823f * c.b,
                      0.07600f * c.r + 0.90834f * c.g + 0.01566f * c.b,
                      0.02840f * c.r + 0.13383f * c.g + 0.83777f * c.b};
    const auto fit = [](float x) {
        const float a = x * (x + 0.0245786f) - 0.000090537f;
        const float b = x * (0.983729f * x + 0.4329510f) + 0.238081f;
        return a / b;
    };
    const glm::vec3 f{fit(v.r), fit(v.g), fit(v.b)};
    return {1.60475f * f.r - 0.53108f * f.g - 0.07367f * f.b,
            -0.10208f * f.r + 1.10813f * f.g - 0.00605f * f.b,
            -0.00327f * f.r - 0.07276f * f.g + 1.07602f * f.b};
}

}  // namespace

glm::vec3 tone_map(glm::vec3 linear, ToneMapper mapper) {
    // Capped at kToneMapInputCap: above it both mappers are white to within 1e-5 (neutral's
    // desaturation leaves 1 / (0.15 x)), while the ACES fit's x^2 overflows past 1.8e19 to
    // Inf / Inf = NaN and neutral's peak scaling is Inf * 0 = NaN at +Inf (a repaired +Inf is
    // the largest float, which exposure can push to +Inf). The shaders apply the same cap.
    linear = glm::clamp(linear, glm::vec3(0.0f), glm::vec3(kToneMapInputCap));
    glm::vec3 mapped = linear;
    if (mapper == ToneMapper::Neutral) {
        mapped = neutral(linear);
    } else if (mapper == ToneMapper::Aces) {
        mapped = aces(linear);
    }
    return glm::clamp(mapped, glm::vec3(0.0f), glm::vec3(1.0f));
}

float srgb_encode(float linear) {
    linear = std::clamp(linear, 0.0f, 1.0f);
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) {
    encoded = std::clamp(encoded, 0.0f, 1.0f);
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

HdrImage to_display(const HdrImage& linear, double exposure, ToneMapper mapper) {
    HdrImage out(linear.width, linear.height);
    const float scale = float(std::exp2(exposure));
    for (std::size_t i = 0; i < linear.pixel_count(); ++i) {
        const glm::vec3 mapped = tone_map(linear.rgb(i) * scale, mapper);
        out.set(i, {srgb_encode(mapped.r), srgb_encode(mapped.g), srgb_encode(mapped.b)});
    }
    return out;
}

HdrImage thesis_tone_map(const HdrImage& linear) {
    // E. Reinhard, M. Stark, P. Shirley, J. Ferwerda, "Photographic Tone Reproduction for
    // Digital Images", SIGGRAPH 2002, eq. 1-3: key a = 0.18 over the log-average luminance
    // exp(mean log(delta + L_w)) (delta avoids log 0 on black pixels), then L / (1 + L). L_w
    // is the thesis's luminance (eq. 3.1) divided by its 179 lm/W: in the pixels' own units,
    // since the scale key / log-average multiplies the pixel values.
    constexpr double key = 0.18;
    constexpr double delta = 1e-6;
    double log_sum = 0.0;
    for (std::size_t i = 0; i < linear.pixel_count(); ++i) {
        log_sum += std::log(delta + luminance(glm::dvec3(linear.rgb(i))) / 179.0);
    }
    const double log_average =
        std::exp(log_sum / double(std::max<std::size_t>(1, linear.pixel_count())));
    const double scale = key / log_average;
    HdrImage out(linear.width, linear.height);
    float largest = 0.0f;
    for (std::size_t i = 0; i < linear.pixel_count(); ++i) {
        const glm::dvec3 scaled = glm::dvec3(linear.rgb(i)) * scale;
        const glm::vec3 mapped(scaled / (1.0 + scaled));
        out.set(i, mapped);
        largest = std::max({largest, mapped.r, mapped.g, mapped.b});
    }
    if (largest > 0.0f) {
        for (float& value : out.pixels) {
            value /= largest;
        }
    }
    return out;
}

}  // namespace oer
