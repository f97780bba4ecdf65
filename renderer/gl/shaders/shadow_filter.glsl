// Shadow tests of the lights that are on, shared by the deferred shading pass and the
// ground-visibility bake. Shadow maps of the lights that are on are the layers of one depth
// array (SHADOW_MAPS_UNIT), so that any number of lights needs two texture units, not one per
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
// the share of the light's energy in its core (light_profile), whose shadows are hard
uniform float u_light_core_share[LIGHTS_ON];
uniform float u_normal_offset[LIGHTS_ON];  // receiver offset against acne, world units
#if SHADOWS
layout(binding = SHADOW_MAPS_UNIT) uniform sampler2DArrayShadow u_shadow_maps;
#if PCF
// The same layers, as depths.
layout(binding = SHADOW_DEPTHS_UNIT) uniform sampler2DArray u_shadow_depths;
uniform float u_shadow_texel;  // one texel, in uv
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

#if SHADOWS && PCF
// The receiver's own depth slope in the light's view, d(depth)/d(uv), from its normal
// (receiver-plane depth bias: J. Isidoro, "Shadow Mapping: GPU-based Tips and Techniques",
// GDC 2006). A tap of the filter away from the point compares against the receiver's plane
// there, not against the point's own depth, or a lit surface that slopes away from the light
// shadows itself wherever the slope times the kernel exceeds the normal offset (the frame sweep
// measured that: the bunny's ground under city 8.6 % from the reference before, 7.2 % after).
// uv and depth share their unit (light_matrix's view is as deep as it is wide), so the
// matrix's linear part, a rotation times one scale, carries the normal into that space as it
// carries positions. Slopes steeper than 4 (the light within 14 degrees of grazing, where the
// surface receives almost none of it) are clamped: there the plane predicts nothing a kernel
// away.
vec2 receiver_slope(int k, vec3 normal) {
    vec3 n = mat3(u_light_matrix[k]) * normal;
    float facing = n.z < 0.0 ? min(n.z, -1e-4) : max(n.z, 1e-4);
    vec2 slope = -n.xy / facing;
    float steepness = length(slope);
    return steepness > 4.0 ? slope * (4.0 / steepness) : slope;
}

// One bilinear comparison (2x2 texels) at offset from the point, against the receiver's plane.
float receiver_test(vec3 uvz, vec2 offset, vec2 slope, float layer) {
    float reference = clamp(uvz.z + dot(slope, offset), 0.0, 1.0);
    return texture(u_shadow_maps, vec4(uvz.xy + offset, layer, reference));
}

// The share of the light's glow that reaches the point (uvz: its place in the light's view).
float soft_visibility(int k, vec3 uvz, vec3 normal, mat2 rotation, float layer) {
    // Percentage-closer soft shadows (R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH
    // 2005 sketch): the blockers' mean depth, searched over the widest penumbra a blocker could
    // cast here (one at the light's near plane), sizes the filter, so that a contact shadow or
    // a self-shadow stays sharp while a shadow far from its caster spreads as the light's size
    // says. The point itself and eight taps of the disc for the search: without the point, a
    // thin blocker between the taps left it lit where the hard test shades it (the bunny's
    // creases under sunrise, 10.7 % from the reference against 8.7 %).
    vec2 slope = receiver_slope(k, normal);
    float search = max(u_shadow_texel, uvz.z * u_light_spread[k]);
    float centre = texture(u_shadow_depths, vec3(uvz.xy, layer)).r;
    float blocker_depth = centre < uvz.z ? centre : 0.0;
    float blockers = centre < uvz.z ? 1.0 : 0.0;
    for (int i = 0; i < 16; i += 2) {
        vec2 offset = rotation * POISSON[i] * search;
        float depth = texture(u_shadow_depths, vec3(uvz.xy + offset, layer)).r;
        if (depth < uvz.z + dot(slope, offset)) {
            blocker_depth += depth;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0) {
        return 1.0;
    }
    float kernel = clamp((uvz.z - blocker_depth / blockers) * u_light_spread[k],
                         u_shadow_texel, search);
    // One bilinear comparison per tap (2x2 texels). Four spread taps first: where they agree
    // the point is fully lit or fully in shadow, as nearly every point is; only penumbrae pay
    // for the other twelve.
    const int EARLY[4] = int[](0, 1, 5, 7);
    float sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        sum += receiver_test(uvz, rotation * POISSON[EARLY[i]] * kernel, slope, layer);
    }
    if (sum == 0.0 || sum == 4.0) {
        return sum / 4.0;
    }
    for (int i = 0; i < 16; ++i) {
        if (i == 0 || i == 1 || i == 5 || i == 7) {
            continue;
        }
        sum += receiver_test(uvz, rotation * POISSON[i] * kernel, slope, layer);
    }
    return sum / 16.0;
}
#endif

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
    float layer = float(u_light_layer[k]);
    float hard = texture(u_shadow_maps, vec4(uvz.xy, layer, reference));
#if PCF
    // The light's core casts the hard test's shadow, its glow a soft one; a light that is all
    // core (a point) pays for no filter.
    float core = u_light_core_share[k];
    if (core >= 1.0) {
        return hard;
    }
    vec3 receiver = vec3(uvz.xy, reference);
    return core * hard + (1.0 - core) * soft_visibility(k, receiver, normal, rotation, layer);
#else
    return hard;
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
