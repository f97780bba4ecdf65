// Specular image-based lighting (renderer/lighting/include/oer/lighting/specular_environment.hpp):
// the prefiltered radiance P(r) = P(residual) + sum_k w_k v_k P(k), the residual map's from a
// cube map read at lod roughness * (levels - 1), each light's in closed form, its core and its
// glow as normalised spherical Gaussians convolved with the GGX lobe (J. Wang, P. Ren, M. Gong,
// J. Snyder and B. Guo, "All-Frequency Rendering of Dynamic, Spatially-Varying Reflectance",
// SIGGRAPH Asia 2009; renderer/lighting/src/light_lobe.cpp computes the same); and the split
// sum's DFG table. SPECULAR 0: none of it (a scene without glossy materials).
#if SPECULAR
#include "math_constants.glsl"
// The cube is seamless, mipmapped per roughness; the table holds (A, B) at (n.v, roughness).
layout(binding = SPECULAR_CUBE_UNIT) uniform samplerCube u_specular_cube;
layout(binding = DFG_TABLE_UNIT) uniform sampler2D u_dfg;
uniform float u_specular_max_lod;  // the cube's levels - 1
#if LIGHTS_ON > 0
uniform vec2 u_lobe_sharpness[LIGHTS_ON];  // the light's core and glow
uniform vec3 u_core_energy[LIGHTS_ON];     // times the light's weight w_k
uniform vec3 u_glow_energy[LIGHTS_ON];
#endif

// A normalised SG of this sharpness and energy about axis, convolved with GGX of alpha:
// sharpness lambda / (1 + 2 alpha^2 (Z / 4) lambda), the product form of lambda lambda_D /
// (lambda + lambda_D) with lambda_D = 1 / (2 alpha^2 (Z / 4)), Z the GGX lobe's normalisation
// over the hemisphere by its fit (renderer/lighting/include/oer/lighting/light_lobe.hpp);
// d.a - 1 as -|d - a|^2 / 2, which keeps the precision that 1 - d.a loses for sharp lobes.
vec3 prefiltered_lobe(vec3 axis, float sharpness, vec3 energy, vec3 r, float alpha) {
    float quarter_z = 1.0 / (1.0 + 0.6247 * alpha + 2.4241 * alpha * alpha);
    float lambda = sharpness / (1.0 + 2.0 * alpha * alpha * quarter_z * sharpness);
    vec3 offset = r - axis;
    float normalisation = lambda / (2.0 * PI * (1.0 - exp(-2.0 * lambda)));
    return energy * (normalisation * exp(-0.5 * lambda * dot(offset, offset)));
}

#if LIGHTS_ON > 0
// P(k) towards r, light k's direction being axis, without its weight's visibility.
vec3 light_reflection(int k, vec3 axis, vec3 r, float alpha) {
    return prefiltered_lobe(axis, u_lobe_sharpness[k].x, u_core_energy[k], r, alpha) +
           prefiltered_lobe(axis, u_lobe_sharpness[k].y, u_glow_energy[k], r, alpha);
}
#endif

// P(residual) towards r_map (r in the map's own frame, turned back by the yaw).
vec3 residual_reflection(vec3 r_map, float roughness) {
    return textureLod(u_specular_cube, r_map, roughness * u_specular_max_lod).rgb;
}

// (A, B) of the split sum (renderer/lighting/include/oer/lighting/split_sum.hpp).
vec2 split_sum_dfg(float n_dot_v, float roughness) {
    return texture(u_dfg, vec2(n_dot_v, roughness)).rg;
}
#endif
