// Specular image-based lighting (renderer/lighting/include/oer/lighting/specular_environment.hpp):
// the prefiltered radiance P(r) = P(residual) + sum_k w_k v_k P(k), the residual map's from a
// cube map at the lod of specular_lod and each light's from its own layer of a cube-map array
// at light_lod; and the split sum's DFG table. SPECULAR 0: none of it (a scene
// without glossy materials).
#if SPECULAR
#include "math_constants.glsl"
#include "brdf.glsl"
// The cubes are seamless, mipmapped per roughness; the table holds (A, B) at (n.v, roughness).
layout(binding = SPECULAR_CUBE_UNIT) uniform samplerCube u_specular_cube;
layout(binding = LIGHT_CUBES_UNIT) uniform samplerCubeArray u_light_cubes;
layout(binding = DFG_TABLE_UNIT) uniform sampler2D u_dfg;
uniform float u_specular_max_lod;  // the cubes' levels - 1

// The cubes' level for a perceptual roughness: lod_of_roughness (specular_environment.hpp).
float specular_lod(float roughness) {
    return u_specular_max_lod * roughness * (2.0 - roughness);
}
#if LIGHTS_ON > 0
uniform int u_light_cube_layer[LIGHTS_ON];  // the light's layer in u_light_cubes: its rig index
uniform float u_light_weight[LIGHTS_ON];  // w_k
// LightSpread (specular_environment.hpp): the core's share of the light's energy, and
// tan^2(radius / 2) of its core and of its glow.
uniform vec3 u_light_reflection_spread[LIGHTS_ON];
// The energy of the light's core in the layer read (its core share times sum L dOmega; 0 where
// a floor hides it) and its direction in the map's frame.
uniform vec3 u_light_core_energy[LIGHTS_ON];
uniform vec3 u_light_map_direction[LIGHTS_ON];
// compact_light_factor's bound: where the split sum's lobe has all but left the light's point
// while the BRDF's still sees it (grazing view), the ratio of two vanishing lobes says little.
const float kCompactLightFactorMax = 8.0;

// The perceptual roughness level `level` holds: roughness_of_level (specular_environment.hpp).
float roughness_of_level(float level) {
    return 1.0 - sqrt(1.0 - level / u_specular_max_lod);
}

// A light's reflection's peak over its energy, up to 1 / (4 pi), at GGX's alpha^2 = a2:
// (1 + T) / (a2 + T) for a disc of T = tan^2(radius / 2), its core's and glow's by their shares
// (light_lod, specular_environment.hpp).
float light_peak(vec3 spread, float a2) {
    return spread.x * (1.0 + spread.y) / (a2 + spread.y) +
           (1.0 - spread.x) * (1.0 + spread.z) / (a2 + spread.z);
}

// The level a light of that spread is read at: light_lod (specular_environment.hpp), whose
// blend of two levels keeps the light's peak where the lod's fraction would be the sharp
// level's peak diluted once.
float light_lod(float roughness, vec3 spread) {
    float lod = specular_lod(roughness);
    float below = floor(lod);
    if (below >= u_specular_max_lod) {
        return u_specular_max_lod;
    }
    float sharp = light_peak(spread, pow(roughness_of_level(below), 4.0));
    float span = light_peak(spread, pow(roughness_of_level(below + 1.0), 4.0)) - sharp;
    if (abs(span) < 1e-4 * sharp) {
        return lod;
    }
    float r = clamp(roughness, 0.0, 1.0);
    return below + clamp((light_peak(spread, pow(r, 4.0)) - sharp) / span, 0.0, 1.0);
}

// K(r, l) / Z(alpha) at r.l = r_dot_l: prefilter_kernel (specular_environment.hpp).
float prefilter_kernel(float alpha, float r_dot_l) {
    return r_dot_l > 0.0 ? ggx_distribution(alpha, 0.5 * (1.0 + r_dot_l)) * r_dot_l /
                               prefilter_kernel_integral(alpha)
                         : 0.0;
}

// What the layer read at `lod` (light_lod) lacks of a point core's reflection at `roughness`,
// per unit of its energy: light_core_correction (specular_environment.hpp), given the lod; 0
// below the second level, whose kernels hold a core as a texel.
float light_core_correction(float roughness, float lod, float r_dot_l) {
    float below = floor(lod);
    if (below < 2.0 || below >= u_specular_max_lod) {
        return 0.0;
    }
    float w = lod - below;
    float r = clamp(roughness, 0.0, 1.0);
    float sharp = roughness_of_level(below), wide = roughness_of_level(below + 1.0);
    float blend = (1.0 - w) * prefilter_kernel(sharp * sharp, r_dot_l) +
                  w * prefilter_kernel(wide * wide, r_dot_l);
    return prefilter_kernel(r * r, r_dot_l) - blend;
}

// w_k P(k) towards r_map (r in the map's own frame), without the light's visibility: the layer
// read at light_lod, its core's reflection made the exact kernel's (light_core_correction).
vec3 light_reflection(int k, vec3 r_map, float roughness) {
    float lod = light_lod(roughness, u_light_reflection_spread[k]);
    vec3 layer = textureLod(u_light_cubes, vec4(r_map, float(u_light_cube_layer[k])), lod).rgb;
    vec3 core = u_light_core_energy[k] *
                light_core_correction(roughness, lod, dot(r_map, u_light_map_direction[k]));
    return u_light_weight[k] * max(layer + core, vec3(0.0));
}

// The factor that turns the split sum's reflection of a compact light, single_scattering P(k),
// into the BRDF's own. Of a light small against the lobe the split sum keeps the energy over
// all directions but not where it goes: its lobe is the prefiltering kernel about r with
// n = v = r, where the BRDF's, F D G2 / (4 n.l n.v) n.l, leans to the normal and rises at
// grazing view. For a point light at l the two are Phi F D G2 / (4 n.v) and
// single_scattering Phi K(r, l) / Z(alpha), so the factor is their ratio at the light's point
// nearest r, for its core and for its glow by their shares. It applies by the share of the
// lobe outside the light, 1 - T / (alpha^2 + T) per disc (GGX's cumulative distribution, as
// light_lod takes it): a light wider than the lobe (a soft box in chrome) keeps its shape and
// the split sum, whose lobe then draws the light's own picture. Against the reference renderer
// (bench/material_gallery.cpp, a metal sphere under Blender's studio) this took the error of
// roughness 0.3 from 0.19 to 0.13 and of 0.5 from 0.17 to 0.11.
vec3 point_light_ratio(vec3 toward_light, float cap_tan2, vec3 n, vec3 view, vec3 r,
                       float n_dot_v, float alpha, vec3 f0, float f90, vec3 single_scattering,
                       bool floor_below) {
    // The light's point nearest r: its direction turned towards r by at most its radius.
    float radius = 2.0 * atan(sqrt(cap_tan2));
    float cos_to_r = clamp(dot(toward_light, r), -1.0, 1.0);
    vec3 across = r - cos_to_r * toward_light;
    float across_length = length(across);
    float turn = min(acos(cos_to_r), radius);
    vec3 l = across_length > 1e-5
                 ? cos(turn) * toward_light + sin(turn) * (across / across_length)
                 : r;
    // With an opaque floor, the light's part below the horizon is hidden: its point nearest r
    // is then on the horizon.
    if (floor_below && l.y < 0.0) {
        l = normalize(vec3(l.x, 1e-4, l.z));
    }
    float n_dot_l = dot(n, l);
    float r_dot_l = dot(r, l);
    vec3 brdf = vec3(0.0);
    if (n_dot_l > 0.0) {
        vec3 h = normalize(l + view);
        float n_dot_h = dot(n, h);
        brdf = schlick_fresnel(f0, f90, dot(view, h)) * ggx_distribution(alpha, n_dot_h * n_dot_h) *
               smith_visibility(n_dot_v, n_dot_l, alpha) * n_dot_l;
    }
    float kernel = prefilter_kernel(alpha, r_dot_l);
    return clamp(brdf / max(single_scattering * kernel, vec3(1e-8)), vec3(0.0),
                 vec3(kCompactLightFactorMax));
}

vec3 compact_light_factor(int k, vec3 toward_light, vec3 n, vec3 view, vec3 r, float n_dot_v,
                          float alpha, vec3 f0, float f90, vec3 single_scattering,
                          bool floor_below) {
    vec3 spread = u_light_reflection_spread[k];
    float a2 = alpha * alpha;
    float core_outside = a2 / (a2 + spread.y);
    float glow_outside = a2 / (a2 + spread.z);
    vec3 factor = vec3(1.0);
    if (core_outside > 1e-3) {
        factor += spread.x * core_outside *
                  (point_light_ratio(toward_light, spread.y, n, view, r, n_dot_v, alpha, f0, f90,
                                     single_scattering, floor_below) -
                   1.0);
    }
    if (glow_outside > 1e-3) {
        factor += (1.0 - spread.x) * glow_outside *
                  (point_light_ratio(toward_light, spread.z, n, view, r, n_dot_v, alpha, f0, f90,
                                     single_scattering, floor_below) -
                   1.0);
    }
    return factor;
}
#endif

// P(residual) towards r_map (r in the map's own frame, turned back by the yaw).
vec3 residual_reflection(vec3 r_map, float roughness) {
    return textureLod(u_specular_cube, r_map, specular_lod(roughness)).rgb;
}

// (A, B) of the split sum (renderer/lighting/include/oer/lighting/split_sum.hpp).
vec2 split_sum_dfg(float n_dot_v, float roughness) {
    return texture(u_dfg, vec2(n_dot_v, roughness)).rg;
}
#endif
