// Shadow tests of the lights that are on, shared by the deferred shading pass and the
// ground-visibility bake. Shadow maps of the lights that are on are the layers of one depth
// array (SHADOW_MAPS_UNIT), so that any number of lights needs two texture units, not one per
// light. SHADOWS 0: every light reaches every point; PCF 0: the thesis's hard test, 1: soft
// shadows whose penumbra grows with the distance from the blockers (PCSS) on Vogel spirals,
// per pixel for objects (visibility) and once per cached map for the ground (baked_visibility).
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

// The golden angle, pi (3 - sqrt 5): successive points of a Vogel spiral turn by it.
const float GOLDEN_ANGLE = 2.39996323;

// The share of the light's glow that reaches the point (uvz: its place in the light's view),
// from search_taps taps of the blocker search and filter_taps of the filter, both Vogel spirals
// (H. Vogel, "A better way to construct the sunflower head", 1979): point i of n at radius
// sqrt((i + 0.5) / n), turned by i golden angles, covers the disc evenly at any n, with no
// cluster or gap for a tap count to expose (J. Jimenez, "Next Generation Post Processing in
// Call of Duty: Advanced Warfare", SIGGRAPH 2014, whose shadows turn it per pixel by
// interleaved gradient noise, as disc_rotation does here).
float soft_visibility(int k, vec3 uvz, vec3 normal, mat2 rotation, float layer, int search_taps,
                      int filter_taps) {
    // Percentage-closer soft shadows (R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH
    // 2005 sketch): the blockers' mean depth, searched over the widest penumbra a blocker could
    // cast here (one at the light's near plane), sizes the filter, so that a contact shadow or
    // a self-shadow stays sharp while a shadow far from its caster spreads as the light's size
    // says. The point itself is searched too: without it, a thin blocker between the taps left
    // it lit where the hard test shades it (the bunny's creases under sunrise, 10.7 % from the
    // reference against 8.7 %).
    vec2 slope = receiver_slope(k, normal);
    float search = max(u_shadow_texel, uvz.z * u_light_spread[k]);
    float centre = texture(u_shadow_depths, vec3(uvz.xy, layer)).r;
    float blocker_depth = centre < uvz.z ? centre : 0.0;
    float blockers = centre < uvz.z ? 1.0 : 0.0;
    const mat2 TURN = mat2(cos(GOLDEN_ANGLE), sin(GOLDEN_ANGLE), -sin(GOLDEN_ANGLE),
                           cos(GOLDEN_ANGLE));
    vec2 direction = rotation[0];
    for (int i = 0; i < search_taps; ++i) {
        vec2 offset = direction * (sqrt((float(i) + 0.5) / float(search_taps)) * search);
        direction = TURN * direction;
        float depth = texture(u_shadow_depths, vec3(uvz.xy + offset, layer)).r;
        // A blocker counts only where its own penumbra reaches the point: the search disc is
        // sized for a blocker at the near plane, and a caster's parts near the receiver (a
        // pole's foot, in the disc of a point near its tip's shadow) would otherwise pull the
        // mean depth towards the receiver and shrink the kernel into a hard edge.
        if (depth < uvz.z + dot(slope, offset) &&
            length(offset) <= (uvz.z - depth) * u_light_spread[k]) {
            blocker_depth += depth;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0) {
        return 1.0;
    }
    float kernel = clamp((uvz.z - blocker_depth / blockers) * u_light_spread[k],
                         u_shadow_texel, search);
    // One bilinear comparison per tap (2x2 texels), every tap: an early exit on a few taps
    // that agree makes a step wherever they stop agreeing, inside the penumbra.
    float sum = 0.0;
    direction = rotation[0];
    for (int i = 0; i < filter_taps; ++i) {
        vec2 offset = direction * (sqrt((float(i) + 0.5) / float(filter_taps)) * kernel);
        direction = TURN * direction;
        sum += receiver_test(uvz, offset, slope, layer);
    }
    return sum / float(filter_taps);
}
#endif

// Fraction of light k that reaches the point: 0 in its shadow, 1 outside. Points outside the
// shadow map's square are lit (every caster is inside it); depths beyond its far plane are
// clamped so that they compare as "behind every caster". rotation turns the filter's spiral;
// search_taps and filter_taps are the PCSS's (soft_visibility).
float filtered_visibility(int k, vec3 position, vec3 normal, mat2 rotation, int search_taps,
                          int filter_taps) {
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
    return core * hard + (1.0 - core) * soft_visibility(k, receiver, normal, rotation, layer,
                                                        search_taps, filter_taps);
#else
    return hard;
#endif
#endif
}

// Per shaded sample (objects): 8 search taps and 16 filter taps, the spiral turned per pixel
// (disc_rotation), so that what 16 taps cannot resolve is fine noise that the pixel's
// supersamples average, not a pattern.
float visibility(int k, vec3 position, vec3 normal, mat2 rotation) {
    return filtered_visibility(k, position, normal, rotation, 8, 16);
}

// The ground's bake (ground_visibility.frag), once per cached shadow map: it can afford 32
// search taps and 64 filter taps, so that the unturned spiral's steps are a 64th of the light.
float baked_visibility(int k, vec3 position, vec3 normal) {
    return filtered_visibility(k, position, normal, mat2(1.0), 32, 64);
}
#endif

// The PCF disc turned per pixel (interleaved gradient noise, Jimenez 2014), so that its
// pattern becomes fine noise, not bands.
mat2 disc_rotation(vec2 pixel) {
    float angle = 2.0 * PI * fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
    return mat2(cos(angle), sin(angle), -sin(angle), cos(angle));
}
