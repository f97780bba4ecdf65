// Specular image-based lighting (renderer/lighting/include/oer/lighting/specular_environment.hpp):
// the prefiltered radiance P(r) = P(residual) + sum_k w_k v_k P(k), the residual map's from a
// cube map at the lod of specular_lod and each light's from its own layer of a cube-map array
// at light_lod; and the split sum's DFG table. SPECULAR 0: none of it (a scene
// without glossy materials).
#if SPECULAR
#include "math_constants.glsl"
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
uniform float u_light_cap_tan2[LIGHTS_ON];  // light_cap_tan2 of its angular radius: tan^2(rho / 2)

// The perceptual roughness level `level` holds: roughness_of_level (specular_environment.hpp).
float roughness_of_level(float level) {
    return 1.0 - sqrt(1.0 - level / u_specular_max_lod);
}

// The level a light of cap_tan2 T is read at: light_lod (specular_environment.hpp), whose blend
// of two levels keeps a compact light's peak where the lod's fraction would be the sharp
// level's peak diluted once.
float light_lod(float roughness, float cap_tan2) {
    float lod = specular_lod(roughness);
    float below = floor(lod);
    if (below >= u_specular_max_lod) {
        return u_specular_max_lod;
    }
    float r_sharp = roughness_of_level(below), r_wide = roughness_of_level(below + 1.0);
    float sharp = cap_tan2 / (pow(r_sharp, 4.0) + cap_tan2);
    float span = cap_tan2 / (pow(r_wide, 4.0) + cap_tan2) - sharp;
    if (abs(span) < 1e-4 * sharp) {
        return lod;
    }
    float r = clamp(roughness, 0.0, 1.0);
    return below + clamp((cap_tan2 / (pow(r, 4.0) + cap_tan2) - sharp) / span, 0.0, 1.0);
}

// w_k P(k) towards r_map (r in the map's own frame), without the light's visibility.
vec3 light_reflection(int k, vec3 r_map, float roughness) {
    return u_light_weight[k] * textureLod(u_light_cubes, vec4(r_map, float(u_light_cube_layer[k])),
                                          light_lod(roughness, u_light_cap_tan2[k]))
                                   .rgb;
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
