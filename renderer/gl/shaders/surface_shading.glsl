// The radiance an object's surface point sends to the eye, shared by the deferred shading
// pass (shade.frag, SURFACE 1) and the transparent pass (transparent.frag), so that a blended
// surface is lit exactly as an opaque one.
//
// Diffuse: the SH irradiance E of the map with every light's weight and visibility
// (docs/design.md section 2), E = E(all) - sum_k (1 - w_k v_k) E(k); with occlusion
// (TRANSFER 1) E = T(x) . R + sum_k w_k v_k E(k), the transfer's irradiance of the residual map
// given per fragment and set 0 holding only the lights' part (with the ground, each light's
// part above the horizon: the plane hides the rest). A Lambertian material
// (metallic -1), and every material under the thesis's model (which has no specular BRDF,
// SPECULAR 0), reflects base E u_albedo_scale. A metallic-roughness material (glTF 2.0
// Appendix B, SPECULAR 1) reflects, by the split sum with multiple scattering (brdf.glsl),
//   FssEss P(r) so + (Fms Ems + c_diff (1 - FssEss - Fms Ems)) E / pi ao + emissive,
// P(r) being the prefiltered radiance of the residual map plus each light's lobes weighted by
// the same w_k v_k as its diffuse light (specular_lighting.glsl), so that switching, dimming or
// shadowing a light takes its reflection with it; so is the specular occlusion of ao. With
// an opaque floor, what a reflection sees below the horizon is the floor, not the map
// (floor_share).
#include "math_constants.glsl"
#include "sh_lighting.glsl"
#include "shadow_filter.glsl"
#include "brdf.glsl"
#include "specular_lighting.glsl"
uniform vec2 u_yaw;  // (cos, sin) of the environment's yaw
uniform vec3 u_eye;
uniform float u_albedo_scale;      // 1 / pi (hdr model) or 1 (thesis model)
uniform float u_attenuation_base;  // thesis: 1 - sum_k (1 - w_k) luminance_share_k
#if SPECULAR
// The opaque floor as reflections see it (surface_shading.cpp): its radiance and height, and
// its fade (the scene's centre x and z, the fade's start and end radius; end 0: no floor).
uniform vec4 u_floor;
uniform vec4 u_floor_fade;

// The share of a reflection along r from `position` that sees the floor instead of the map:
// where r goes down, the floor where the ray meets it, by the weight the floor is drawn with
// there (SceneBounds::ground_weight); blended across the horizon over the lobe's width (alpha,
// at least 0.01), since a rough lobe about a level r sees both.
float floor_share(vec3 position, vec3 r, float alpha) {
    if (u_floor_fade.w <= 0.0) {
        return 0.0;
    }
    float width = max(alpha, 0.01);
    float below = smoothstep(width, -width, r.y);
    float down = min(r.y, -1e-3);
    vec2 hit = position.xz + r.xz * ((position.y - u_floor.w) / -down);
    float t = clamp((distance(hit, u_floor_fade.xy) - u_floor_fade.z) /
                        (u_floor_fade.w - u_floor_fade.z),
                    0.0, 1.0);
    return below * (1.0 - t * t * (3.0 - 2.0 * t));
}
#endif
#if LIGHTS_ON > 0
uniform vec3 u_light_direction[LIGHTS_ON];  // world space: turned by the yaw
uniform float u_light_share[LIGHTS_ON];     // w_k luminance_share_k (thesis); 0 (hdr)
#endif

// A world direction in the map's own frame: the environment turned by the yaw lights
// direction d as the unturned one lights d turned back.
vec3 map_direction(vec3 d) {
    return vec3(u_yaw.x * d.x - u_yaw.y * d.z, d.y, u_yaw.y * d.x + u_yaw.x * d.z);
}

// n: the unit shading normal on the side seen; metallic -1 for a Lambertian material;
// transferred: the transfer's irradiance at the point (0 without occlusion).
vec3 shade_object(vec3 position, vec3 n, vec3 base, float metallic, float roughness, float ao,
                  vec3 emissive, vec3 transferred) {
    float Y[SH_COUNT];
    sh_basis(map_direction(n), Y);
    vec3 E = irradiance(0, Y) + transferred;
    float attenuation = u_attenuation_base;
#if SPECULAR
    bool glossy = metallic >= 0.0;
    vec3 view = normalize(u_eye - position);
    vec3 r = reflect(-view, n);
    float alpha = roughness * roughness;
    vec3 lights_reflected = vec3(0.0);
#endif
#if LIGHTS_ON > 0
    mat2 rotation = disc_rotation(gl_FragCoord.xy);
    for (int k = 0; k < LIGHTS_ON; ++k) {
        float v = visibility(k, position, n, rotation);
        // Skipped where the light is seen, as at most samples (speed: docs/design.md section 8).
        vec3 light_irradiance = v < 1.0 ? irradiance(k + 1, Y) : vec3(0.0);
        // E = E(all) - sum_k (1 - w_k v_k) E(k) (docs/design.md section 2) as set 0 minus
        // (1 - v) w_k E(k): the weights are in the sets and uniforms (frame_context.hpp).
        E -= (1.0 - v) * light_irradiance;
        attenuation -= (1.0 - v) * u_light_share[k];
#if SPECULAR
        // w_k is in the lobes' energies: v_k w_k P(k), only where the light reaches.
        if (glossy && v > 0.0) {
            lights_reflected += v * light_reflection(k, u_light_direction[k], r, alpha);
        }
#endif
    }
#endif
#if SPECULAR
    if (glossy) {
        float n_dot_v = clamp(dot(n, view), 1e-4, 1.0);
        vec3 f0 = specular_f0(base, metallic);
        vec3 single_scattering, multiple_scattering;
        split_sum_weights(f0, split_sum_dfg(n_dot_v, roughness), single_scattering,
                          multiple_scattering);
        vec3 prefiltered = mix(residual_reflection(map_direction(r), roughness) + lights_reflected,
                               u_floor.rgb, floor_share(position, r, alpha));
        vec3 diffuse_weight = multiple_scattering + diffuse_color(base, metallic) *
                                                        (1.0 - single_scattering - multiple_scattering);
        return single_scattering * prefiltered * specular_occlusion(n_dot_v, ao, alpha) +
               diffuse_weight * (E * (ao / PI)) + emissive;
    }
#endif
    return base * u_albedo_scale * E * attenuation * ao + emissive;
}
