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
// P(r) being the prefiltered radiance of the residual map plus each light's own, weighted by
// the same w_k v_k as its diffuse light (specular_lighting.glsl), so that switching, dimming or
// shadowing a light takes its reflection with it; so is the specular occlusion of ao. With
// an opaque floor, what a reflection sees below the horizon is the floor, not the map
// (floor_share), and of a light only its pixels above the horizon (its floor layer,
// SpecularEnvironment::floor_layers). P is read along the lobe's dominant direction (brdf.glsl).
// An unlit material (metallic -2, KHR_materials_unlit) sends its base colour.
//
// MATERIAL_LAYERS 1 (a material with the extensions' layers, brdf.glsl's SurfaceLayers;
// docs/materials.md): f0 and F90 are the layers' (KHR_materials_ior, _specular); the share
// transmission of the dielectric's diffuse lobe is transmitted instead, the radiance behind the
// thin wall P(-v) at transmission_roughness, tinted by the diffuse colour and the volume's
// transmittance (KHR_materials_transmission, _volume); a sheen lobe sheen E_sheen E / pi ao over
// the rest scaled by 1 - max(sheen) E_sheen (KHR_materials_sheen); and a clear coat, c E_c
// P_c(r_c) with E_c = 0.04 A_c + B_c, over the rest and the emission scaled by 1 - c E_c
// (KHR_materials_clearcoat). P(-v) and P_c hold each light's cube with the same w_k v_k as P(r),
// and the sheen's E holds them as the diffuse light does: every lobe keeps the lights'
// switching, dimming and shadows.
#include "math_constants.glsl"
#include "sh_lighting.glsl"
#include "shadow_filter.glsl"
#include "brdf.glsl"
#include "specular_lighting.glsl"
uniform vec2 u_yaw;  // (cos, sin) of the environment's yaw
uniform vec3 u_eye;
uniform float u_albedo_scale;      // 1 / pi (hdr model) or 1 (thesis model)
uniform float u_attenuation_base;  // thesis: 1 - sum_k (1 - w_k) luminance_share_k
#if LIGHTS_ON > 0
uniform vec3 u_light_direction[LIGHTS_ON];  // world space: turned by the yaw
uniform float u_light_share[LIGHTS_ON];     // w_k luminance_share_k (thesis); 0 (hdr)
#endif
#include "ground_lighting.glsl"
#if SPECULAR
// The opaque floor as reflections see it (surface_shading.cpp): its height and albedo, and its
// fade (the scene's centre x and z, the fade's start and end radius; end 0: no floor).
uniform float u_floor_height;
uniform float u_floor_albedo;
uniform vec4 u_floor_fade;

// Where a reflection along r from `position` meets the floor: along r mirrored downwards when
// it rises, so that a lobe about a rising r takes its downward part's floor.
vec3 floor_hit(vec3 position, vec3 r) {
    float down = -max(abs(r.y), 1e-3);
    return vec3(position.xz + r.xz * ((position.y - u_floor_height) / -down), u_floor_height)
        .xzy;
}

// The radiance a reflection sees of the floor at `hit`: the floor's own shading there, as the
// ground pass draws it (ground_lighting.glsl), the shadows and the occlusion the objects cast on
// it included (a chrome product's underside reflects the shadow it stands in). The ground's
// textures are bound wherever there is a ground; the caller reads this only where a reflection
// meets an opaque floor.
vec3 floor_radiance(vec3 hit) {
    vec3 E, E_open;
    float attenuation, open_attenuation;
    ground_irradiance(hit, E, attenuation, E_open, open_attenuation);
    return vec3(u_floor_albedo * u_albedo_scale) * E * attenuation;
}

// The share of a reflection along r that sees the floor instead of the map: the share of the
// lobe about r below the horizon, by the weight the floor is drawn with at `hit`, where the ray
// meets it (floor_hit; SceneBounds::ground_weight). Of a lobe whose axis is at elevation e, the
// cap of angular radius |e| about r lies wholly on r's side of the horizon, and it holds the
// share T / (alpha^2 + T) of the lobe, T = tan^2(|e| / 2) (GGX's cumulative distribution, as
// light_lod takes it); of the rest, half is taken on each side. A rough lobe about a level r
// sees both, and a lobe about an r going up still sees some floor: a smoothstep over +-alpha in
// r.y had a rough metal sphere's lower half reflect the floor where the reference's reaches
// the sky above it.
float floor_share(vec3 hit, vec3 r, float alpha) {
    if (u_floor_fade.w <= 0.0) {
        return 0.0;
    }
    float elevation = asin(clamp(r.y, -1.0, 1.0));
    float cap_tan2 = pow(tan(0.5 * abs(elevation)), 2.0);
    float outside_cap = alpha * alpha / (alpha * alpha + cap_tan2 + 1e-12);
    float below = r.y < 0.0 ? 1.0 - 0.5 * outside_cap : 0.5 * outside_cap;
    float t = clamp((distance(hit.xz, u_floor_fade.xy) - u_floor_fade.z) /
                        (u_floor_fade.w - u_floor_fade.z),
                    0.0, 1.0);
    return below * (1.0 - t * t * (3.0 - 2.0 * t));
}
#endif
#if SPECULAR && MATERIAL_LAYERS
// The sheen lobe's directional albedo E_sheen at (n.v, sheen roughness)
// (renderer/lighting/include/oer/lighting/sheen_albedo.hpp).
layout(binding = SHEEN_ALBEDO_UNIT) uniform sampler2D u_sheen_albedo;

float sheen_albedo(float n_dot_v, float sheen_roughness) {
    return texture(u_sheen_albedo, vec2(n_dot_v, sheen_roughness)).r;
}
#endif

#if SPECULAR
// The share of the residual map's irradiance that reaches the point (TRANSFER 1): the
// transfer's, which holds the occluders' shadow and their bounce, over the open residual's
// (the last irradiance set, frame_context.cpp), in luminance; 1 without occlusion.
float residual_visibility(vec3 transferred, float Y[SH_COUNT]) {
#if TRANSFER
    const vec3 kLuminance = vec3(0.2126, 0.7152, 0.0722);
    float open = dot(irradiance(LIGHTS_ON + 1, Y), kLuminance);
    return open > 1e-6 ? clamp(dot(transferred, kLuminance) / open, 0.0, 1.0) : 1.0;
#else
    return 1.0;
#endif
}
#endif

// A world direction in the map's own frame: the environment turned by the yaw lights
// direction d as the unturned one lights d turned back.
vec3 map_direction(vec3 d) {
    return vec3(u_yaw.x * d.x - u_yaw.y * d.z, d.y, u_yaw.y * d.x + u_yaw.x * d.z);
}

// n: the unit shading normal on the side seen; metallic -1 for a Lambertian material, -2 for
// an unlit one; transferred: the transfer's irradiance at the point (0 without occlusion);
// layers: the material's (plain_layers() without MATERIAL_LAYERS, where they are not read).
vec3 shade_object(vec3 position, vec3 n, vec3 base, float metallic, float roughness, float ao,
                  vec3 emissive, vec3 transferred, SurfaceLayers layers) {
    if (metallic < -1.5) {
        return base;
    }
    float Y[SH_COUNT];
    sh_basis(map_direction(n), Y);
    vec3 E = irradiance(0, Y) + transferred;
    float attenuation = u_attenuation_base;
#if SPECULAR
    bool glossy = metallic >= 0.0;
    vec3 view = normalize(u_eye - position);
    float alpha = roughness * roughness;
    vec3 r = specular_dominant_direction(n, reflect(-view, n), alpha);
    vec3 r_map = map_direction(r);
    vec3 lights_reflected = vec3(0.0);
    float n_dot_v = clamp(dot(n, view), 1e-4, 1.0);
    vec3 f0 = specular_f0(layers, base, metallic);
    float f90 = specular_f90(layers, metallic);
    vec3 single_scattering, multiple_scattering;
    split_sum_weights(f0, f90, split_sum_dfg(n_dot_v, roughness), single_scattering,
                      multiple_scattering);
    vec3 floor_point = floor_hit(position, r);
    float floor_weight = floor_share(floor_point, r, alpha);
#if MATERIAL_LAYERS
    // The coat reflects about its own normal at its own roughness; the thin wall transmits
    // straight through, along -v.
    float coat_alpha = layers.clearcoat_roughness * layers.clearcoat_roughness;
    vec3 coat_r_map = map_direction(specular_dominant_direction(
        layers.clearcoat_normal, reflect(-view, layers.clearcoat_normal), coat_alpha));
    float through_roughness = transmission_roughness(roughness, layers.ior);
    vec3 through_map = map_direction(-view);
    vec3 lights_coat = vec3(0.0);
    vec3 lights_through = vec3(0.0);
#endif
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
        // v_k w_k P(k), only where the light reaches. On an opaque floor, which hides what lies
        // below the horizon, P(k) is of the light's pixels above it (its floor layer).
        if (glossy && v > 0.0) {
            lights_reflected += v * light_reflection(k, r_map, roughness) *
                                compact_light_factor(k, u_light_direction[k], n, view, r, n_dot_v,
                                                     alpha, f0, f90, single_scattering,
                                                     u_floor_fade.w > 0.0);
#if MATERIAL_LAYERS
            if (layers.clearcoat > 0.0) {
                lights_coat += v * light_reflection(k, coat_r_map, layers.clearcoat_roughness);
            }
            if (layers.transmission > 0.0) {
                lights_through += v * light_reflection(k, through_map, through_roughness);
            }
#endif
        }
#endif
    }
#endif
#if SPECULAR
    if (glossy) {
        // The lights' reflections are shadowed (v_k above); the residual's is occluded by what
        // the transfer says reaches the point of the residual map's light (its bounce off the
        // occluders included), as Lagarde's approximation takes an ambient occlusion.
        vec3 prefiltered =
            mix(residual_reflection(r_map, roughness),
                floor_weight > 0.0 ? floor_radiance(floor_point) : vec3(0.0), floor_weight) *
                specular_occlusion(n_dot_v, ao * residual_visibility(transferred, Y), alpha) +
            lights_reflected * specular_occlusion(n_dot_v, ao, alpha);
        // What the specular lobe leaves to the diffuse one (and to the transmitted one).
        vec3 under_specular = diffuse_color(base, metallic) *
                              (1.0 - single_scattering - multiple_scattering);
        vec3 specular = single_scattering * prefiltered;
        vec3 diffuse_irradiance = E * (ao / PI);
#if MATERIAL_LAYERS
        vec3 radiance = specular + (multiple_scattering +
                                    under_specular * (1.0 - layers.transmission)) *
                                       diffuse_irradiance;
        if (layers.transmission > 0.0) {
            vec3 behind = residual_reflection(through_map, through_roughness) + lights_through;
            radiance += under_specular * layers.transmission * layers.volume_transmittance *
                        behind;
        }
        if (max(layers.sheen_color.r, max(layers.sheen_color.g, layers.sheen_color.b)) > 0.0) {
            float e_sheen = sheen_albedo(n_dot_v, layers.sheen_roughness);
            radiance = radiance * sheen_albedo_scaling(layers.sheen_color, e_sheen) +
                       layers.sheen_color * e_sheen * diffuse_irradiance;
        }
        radiance += emissive;
        if (layers.clearcoat > 0.0) {
            float coat_n_dot_v = clamp(dot(layers.clearcoat_normal, view), 1e-4, 1.0);
            vec2 coat_dfg = split_sum_dfg(coat_n_dot_v, layers.clearcoat_roughness);
            vec3 coat_prefiltered =
                residual_reflection(coat_r_map, layers.clearcoat_roughness) + lights_coat;
            float coat_albedo = layers.clearcoat * clearcoat_albedo(coat_dfg);
            radiance = radiance * (1.0 - coat_albedo) +
                       coat_albedo * coat_prefiltered *
                           specular_occlusion(coat_n_dot_v, ao, coat_alpha);
        }
        return radiance;
#else
        return specular + (multiple_scattering + under_specular) * diffuse_irradiance + emissive;
#endif
    }
#endif
    return base * u_albedo_scale * E * attenuation * ao + emissive;
}
