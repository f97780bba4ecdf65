// Exposure, tone mapping, sRGB and compositing over the background color, applied to
// premultiplied linear radiance (alpha = coverage) when DISPLAY_OUTPUT is 1; linear output
// (EXR) keeps the radiance as it is.
#if DISPLAY_OUTPUT
uniform float u_exposure_scale;
uniform int u_tonemap;     // 0 neutral, 1 aces, 2 none: as renderer/lighting/src/tonemap.cpp
uniform vec4 u_background;     // sRGB color; alpha 1 to composite over it, 0 for transparency

vec3 neutral(vec3 color) {  // Khronos PBR Neutral
    const float start_compression = 0.8 - 0.04;
    const float desaturation = 0.15;
    float x = min(color.r, min(color.g, color.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;
    float peak = max(color.r, max(color.g, color.b));
    if (peak < start_compression) return color;
    const float d = 1.0 - start_compression;
    float new_peak = 1.0 - d * d / (peak + d - start_compression);
    color *= new_peak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(color, vec3(new_peak), g);
}

vec3 aces(vec3 c) {  // Stephen Hill's fit
    vec3 v = vec3(dot(vec3(0.59719, 0.35458, 0.04823), c), dot(vec3(0.07600, 0.90834, 0.01566), c),
                  dot(vec3(0.02840, 0.13383, 0.83777), c));
    vec3 f = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081);
    return vec3(dot(vec3(1.60475, -0.53108, -0.07367), f), dot(vec3(-0.10208, 1.10813, -0.00605), f),
                dot(vec3(-0.00327, -0.07276, 1.07602), f));
}

vec3 srgb_encode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec4 output_color(vec4 radiance) {
    float alpha = clamp(radiance.a, 0.0, 1.0);
    vec3 linear = alpha > 0.0 ? max(radiance.rgb / alpha, 0.0) * u_exposure_scale : vec3(0.0);
    // kToneMapInputCap of oer/lighting/tonemap.hpp: white in every mapper, and no NaN from an
    // overflowing ACES fit or neutral's Inf * 0 (tonemap.cpp).
    linear = min(linear, vec3(1e6));
    vec3 mapped = linear;
    if (u_tonemap == 0) mapped = neutral(linear);
    else if (u_tonemap == 1) mapped = aces(linear);
    vec3 display = srgb_encode(clamp(mapped, 0.0, 1.0));
    if (u_background.a > 0.0) {
        return vec4(mix(u_background.rgb, display, alpha), 1.0);
    }
    return vec4(display, alpha);
}
#else
vec4 output_color(vec4 radiance) { return radiance; }
#endif
