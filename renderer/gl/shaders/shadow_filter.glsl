// Shadow tests of the lights that are on, shared by the deferred shading pass and the
// ground-visibility bake. Shadow maps of the lights that are on are the layers of one depth
// array (texture unit 4), so that any number of lights needs two texture units, not one per
// light. SHADOWS 0: every light reaches every point; PCF 0: the thesis's hard test, 1: soft
// shadows whose penumbra grows with the distance from the blockers (PCSS).
#include "math_constants.glsl"

#if LIGHTS_ON > 0
uniform mat4 u_light_matrix[LIGHTS_ON];
uniform int u_light_layer[LIGHTS_ON];      // the light's layer in the shadow arrays
// tan of the light's energy angular radius: a blocker's penumbra radius, in shadow-map uv, per
// unit of depth between it and the receiver (the light's orthographic view is as deep as it is
// wide, frame_context.cpp's light_matrix, so uv and depth share their unit).
uniform float u_light_spread[LIGHTS_ON];
uniform float u_normal_offset[LIGHTS_ON];  // receiver offset against acne, world units
#if SHADOWS
layout(binding = 4) uniform sampler2DArrayShadow u_shadow_maps;
#if PCF
layout(binding = 6) uniform sampler2DArray u_shadow_depths;  // the same layers, as depths
uniform float u_shadow_texel;                                // one texel, in uv
#endif
#endif

// 16 points of a Poisson disc of radius 1.
const vec2 POISSON[16] = vec2[](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725), vec2(-0.09418410, -0.92938870),
    vec2(0.34495938, 0.29387760), vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379), vec2(0.44323325, -0.97511554),
    vec2(0.53742981, -0.47373420), vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590), vec2(0.19984126, 0.78641367),
    vec2(0.14383161, -0.14100790));

// Fraction of light k that reaches the point: 0 in its shadow, 1 outside. Points outside the
// shadow map's square are lit (every caster is inside it); depths beyond its far plane are
// clamped so that they compare as "behind every caster". rotation turns the PCF disc.
float visibility(int k, vec3 position, vec3 normal, mat2 rotation) {
#if !SHADOWS
    return 1.0;
#else
    vec4 p = u_light_matrix[k] * vec4(position + normal * u_normal_offset[k], 1.0);
    vec3 uvz = p.xyz / p.w * 0.5 + 0.5;
    if (any(lessThan(uvz.xy, vec2(0.0))) || any(greaterThan(uvz.xy, vec2(1.0)))) {
        return 1.0;
    }
    float reference = clamp(uvz.z, 0.0, 1.0);
#if PCF
    // Percentage-closer soft shadows (R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH
    // 2005 sketch): the blockers' mean depth, searched over the widest penumbra a blocker could
    // cast here (one at the light's near plane), sizes the filter, so that a contact shadow or
    // a self-shadow stays sharp while a shadow far from its caster spreads as the light's size
    // says. Eight taps of the disc for the search.
    float layer = float(u_light_layer[k]);
    float search = max(u_shadow_texel, reference * u_light_spread[k]);
    float blocker_depth = 0.0;
    float blockers = 0.0;
    for (int i = 0; i < 16; i += 2) {
        float depth = texture(u_shadow_depths, vec3(uvz.xy + rotation * POISSON[i] * search,
                                                     layer)).r;
        if (depth < reference) {
            blocker_depth += depth;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0) {
        return 1.0;
    }
    float kernel = clamp((reference - blocker_depth / blockers) * u_light_spread[k],
                         u_shadow_texel, search);
    // One bilinear comparison per tap (2x2 texels). Four spread taps first: where they agree
    // the point is fully lit or fully in shadow, as nearly every point is; only penumbrae pay
    // for the other twelve.
    const int EARLY[4] = int[](0, 1, 5, 7);
    float sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        vec2 uv = uvz.xy + rotation * POISSON[EARLY[i]] * kernel;
        sum += texture(u_shadow_maps, vec4(uv, float(u_light_layer[k]), reference));
    }
    if (sum == 0.0 || sum == 4.0) {
        return sum / 4.0;
    }
    for (int i = 0; i < 16; ++i) {
        if (i == 0 || i == 1 || i == 5 || i == 7) {
            continue;
        }
        vec2 uv = uvz.xy + rotation * POISSON[i] * kernel;
        sum += texture(u_shadow_maps, vec4(uv, float(u_light_layer[k]), reference));
    }
    return sum / 16.0;
#else
    return texture(u_shadow_maps, vec4(uvz.xy, float(u_light_layer[k]), reference));
#endif
#endif
}
#endif

// The PCF disc turned per pixel (interleaved gradient noise, Jimenez 2014), so that its
// pattern becomes fine noise, not bands.
mat2 disc_rotation(vec2 pixel) {
    float angle = 2.0 * PI * fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
    return mat2(cos(angle), sin(angle), -sin(angle), cos(angle));
}
