#version 450 core
#extension GL_GOOGLE_include_directive : require
// Deferred shading: every sample is shaded once, in whole blocks, by the program of its
// surface (SURFACE 0 the background, 1 objects, 2 the ground plane, 3 the ground plane as a
// shadow catcher, 4 objects whose material has the extensions' layers), which the stencil test
// routes to it. Shading the meshes' fragments directly costs far more on llvmpipe, whose 4x4
// blocks are mostly empty on small triangles, and whose SIMD lanes would run every branch of
// a shader that handled all the surfaces. Objects are shaded by surface_shading.glsl from
// the G-buffer (geometry.frag); the transparent pass shades BLEND primitives with the same
// code afterwards. SURFACE 4 also reads the layers the geometry pass packed
// (layer_gbuffer.glsl); SURFACE 1 reads none, and shades the core model.
#define OBJECT_SURFACE (SURFACE == 1 || SURFACE == 4)
#define GROUND_SURFACE (SURFACE == 2 || SURFACE == 3)
#define MATERIAL_LAYERS (SURFACE == 4)
#include "surface_shading.glsl"
#include "layer_gbuffer.glsl"
// Position and ao; shading normal and roughness; base colour and metallic (-1: Lambertian).
layout(binding = GBUFFER_POSITIONS_UNIT) uniform sampler2D u_positions;
layout(binding = GBUFFER_NORMALS_UNIT) uniform sampler2D u_normals;
layout(binding = GBUFFER_ALBEDOS_UNIT) uniform sampler2D u_albedos;
layout(binding = ENVIRONMENT_UNIT) uniform sampler2D u_environment;
layout(binding = GBUFFER_EMISSIVE_UNIT) uniform sampler2D u_emissive;
uniform mat4 u_inverse_view_projection;
uniform vec2 u_viewport_size;
#if TRANSFER && OBJECT_SURFACE
// The G-buffer's transferred irradiance.
layout(binding = GBUFFER_TRANSFERRED_UNIT) uniform sampler2D u_transferred;
#endif
#if GROUND_SURFACE
uniform vec4 u_ground_fade;  // the scene's centre (x, z), the fade's start and end radius
#endif
#if MATERIAL_LAYERS
layout(binding = GBUFFER_LAYERS_FIRST_UNIT) uniform usampler2D u_layers_first;
layout(binding = GBUFFER_LAYERS_SECOND_UNIT) uniform usampler2D u_layers_second;
#endif
#if SURFACE == 3
uniform float u_shadow_intensity;  // ShadowOptions::intensity
#endif
out vec4 o_color;

// What the background shows at this fragment, premultiplied: the map along the view ray, or
// nothing (a colour or transparency, which display.glsl composes under it).
vec4 background() {
#if ENVIRONMENT_BACKGROUND
    vec2 ndc = gl_FragCoord.xy / u_viewport_size * 2.0 - 1.0;
    vec4 near_point = u_inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = u_inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 d = map_direction(normalize(far_point.xyz / far_point.w - near_point.xyz / near_point.w));
    // docs/design.md section 3: theta from +Y, phi = atan2(z, x);
    // u = (phi + pi) / 2pi, v = theta / pi.
    vec2 uv = vec2((atan(d.z, d.x) + PI) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
    return vec4(textureLod(u_environment, uv, 0.0).rgb, 1.0);
#else
    return vec4(0.0);
#endif
}

#if SURFACE == 0
vec4 shade(ivec2 pixel) {
    return background();
}
#elif OBJECT_SURFACE
vec4 shade(ivec2 pixel) {
    vec4 position = texelFetch(u_positions, pixel, 0);
    vec4 normal = texelFetch(u_normals, pixel, 0);
    vec4 albedo = texelFetch(u_albedos, pixel, 0);
    vec3 emissive = texelFetch(u_emissive, pixel, 0).rgb;
#if TRANSFER
    vec3 transferred = texelFetch(u_transferred, pixel, 0).rgb;
#else
    vec3 transferred = vec3(0.0);
#endif
#if MATERIAL_LAYERS
    SurfaceLayers layers = unpack_layers(texelFetch(u_layers_first, pixel, 0),
                                         texelFetch(u_layers_second, pixel, 0));
#else
    SurfaceLayers layers = plain_layers();
#endif
    return vec4(shade_object(position.xyz, normal.xyz, albedo.rgb, albedo.a, normal.w, position.w,
                             emissive, transferred, layers),
                1.0);
}
#else
// The ground's irradiance at the sample (ground_lighting.glsl), shaded as its albedo reflects
// it, or as the shadow it catches.
vec4 shade(ivec2 pixel) {
    vec3 position = texelFetch(u_positions, pixel, 0).xyz;
    vec4 albedo = texelFetch(u_albedos, pixel, 0);
    vec3 E, E_open;
    float attenuation, open_attenuation;
    ground_irradiance(position, E, attenuation, E_open, open_attenuation);
    // SceneBounds::ground_weight: the plane fades into the background far from the scene.
    float t = clamp((distance(position.xz, u_ground_fade.xy) - u_ground_fade.z) /
                        (u_ground_fade.w - u_ground_fade.z),
                    0.0, 1.0);
    float weight = 1.0 - t * t * (3.0 - 2.0 * t);
#if SURFACE == 3
    // The share of the open ground's light that the objects take away, by luminance (Rec. 709),
    // none where they add light (what they reflect onto it).
    const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);
    float open_light = dot(E_open, LUMINANCE) * open_attenuation;
    float taken = open_light > 0.0 ? 1.0 - dot(E, LUMINANCE) * attenuation / open_light : 0.0;
    float shadow = u_shadow_intensity * weight * clamp(taken, 0.0, 1.0);
    vec4 behind = background();
    // Over the map, the map darkened; over a colour or nothing, black of the shadow's opacity.
    return behind.a > 0.0 ? vec4(behind.rgb * (1.0 - shadow), 1.0) : vec4(0.0, 0.0, 0.0, shadow);
#else
    vec4 ground = vec4(albedo.rgb * u_albedo_scale * E * attenuation, 1.0);
    // The background is looked up only where it shows: most of the floor is drawn whole.
    return weight < 1.0 ? weight * ground + (1.0 - weight) * background() : ground;
#endif
}
#endif

#include "display.glsl"
void main() {
    o_color = output_color(shade(ivec2(gl_FragCoord.xy)));
}
