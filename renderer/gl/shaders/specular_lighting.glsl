// Specular image-based lighting (renderer/lighting/include/oer/lighting/specular_environment.hpp):
// the prefiltered radiance P(r) = P(residual) + sum_k w_k v_k P(k), the residual map's from a
// cube map and each light's from its own layer of a cube-map array, both read at the lod of
// specular_lod; and the split sum's DFG table. SPECULAR 0: none of it (a scene
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

// w_k P(k) towards r_map (r in the map's own frame), without the light's visibility.
vec3 light_reflection(int k, vec3 r_map, float roughness) {
    return u_light_weight[k] *
           textureLod(u_light_cubes, vec4(r_map, float(u_light_cube_layer[k])),
                      specular_lod(roughness))
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
