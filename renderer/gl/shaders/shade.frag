#version 450 core
#extension GL_GOOGLE_include_directive : require
// Deferred shading: every sample is shaded once, in whole blocks, by the program of its
// surface (SURFACE 0 the background, 1 objects, 2 the ground plane), which the stencil test
// routes to it. Shading the meshes' fragments directly costs far more on llvmpipe, whose 4x4
// blocks are mostly empty on small triangles, and whose SIMD lanes would run every branch of
// a shader that handled all three surfaces.
#include "math_constants.glsl"
#include "sh_lighting.glsl"
#include "shadow_filter.glsl"
layout(binding = 0) uniform sampler2D u_positions;
layout(binding = 1) uniform sampler2D u_normals;
layout(binding = 2) uniform sampler2D u_albedos;
layout(binding = 3) uniform sampler2D u_environment;
uniform mat4 u_inverse_view_projection;
uniform vec2 u_viewport_size;
uniform vec2 u_yaw;  // (cos, sin) of the environment's yaw
uniform vec3 u_eye;
uniform float u_albedo_scale;      // 1 / pi (hdr model) or 1 (thesis model)
// The ground plane's normal never changes: its irradiance per set is computed once per frame
// on the CPU, and no SH is evaluated for its pixels.
uniform vec3 u_flat_irradiance[1 + LIGHTS_ON];
uniform float u_attenuation_base;  // thesis: 1 - sum_k (1 - w_k) luminance_share_k
#if LIGHTS_ON > 0
uniform vec3 u_light_direction[LIGHTS_ON];
uniform vec3 u_light_intensity[LIGHTS_ON];  // times the light's weight w_k
uniform float u_light_share[LIGHTS_ON];      // w_k luminance_share_k (thesis); 0 (hdr)
#if SHADOWS
// Each light's visibility on the ground plane, baked once per shadow map (the ground's depth
// in light space is a function of the shadow-map uv), read with one bilinear fetch.
layout(binding = 5) uniform sampler2DArray u_ground_visibility;
#endif
#endif
out vec4 o_color;

#if SURFACE == 0
vec4 shade(ivec2 pixel) {
#if ENVIRONMENT_BACKGROUND
    vec2 ndc = gl_FragCoord.xy / u_viewport_size * 2.0 - 1.0;
    vec4 near_point = u_inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = u_inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 d = normalize(far_point.xyz / far_point.w - near_point.xyz / near_point.w);
    d = vec3(u_yaw.x * d.x - u_yaw.y * d.z, d.y, u_yaw.y * d.x + u_yaw.x * d.z);
    // DESIGN.md section 3: theta from +Y, phi = atan2(z, x); u = (phi + pi) / 2pi, v = theta / pi.
    vec2 uv = vec2((atan(d.z, d.x) + PI) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
    return vec4(textureLod(u_environment, uv, 0.0).rgb, 1.0);
#else
    return vec4(0.0);
#endif
}
#else
#if SURFACE == 2 && LIGHTS_ON > 0
float ground_visibility(int k, vec3 position) {
#if SHADOWS
    vec4 p = u_light_matrix[k] * vec4(position, 1.0);
    vec2 uv = p.xy / p.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
        return 1.0;
    }
    return textureLod(u_ground_visibility, vec3(uv, float(u_light_layer[k])), 0.0).r;
#else
    return 1.0;
#endif
}
#endif

vec4 shade(ivec2 pixel) {
    vec3 position = texelFetch(u_positions, pixel, 0).xyz;
    vec4 albedo = texelFetch(u_albedos, pixel, 0);
#if SURFACE == 2
    vec3 E = u_flat_irradiance[0];
#else
    vec4 normal = texelFetch(u_normals, pixel, 0);
    vec3 n = normal.xyz;
    float Y[SH_COUNT];
    // The environment turned by yaw lights normal n as the unturned one lights n turned back.
    sh_basis(vec3(u_yaw.x * n.x - u_yaw.y * n.z, n.y, u_yaw.y * n.x + u_yaw.x * n.z), Y);
    vec3 E = irradiance(0, Y);
    vec3 specular = vec3(0.0);
#endif
    float attenuation = u_attenuation_base;
#if LIGHTS_ON > 0
#if SURFACE == 1
    vec3 view = normalize(u_eye - position);
    mat2 rotation = disc_rotation(gl_FragCoord.xy);
#endif
    for (int k = 0; k < LIGHTS_ON; ++k) {
#if SURFACE == 2
        // The ground's own plane hides a light below its horizon from its top (the true
        // irradiance there is 0, cos < 0), shadows on or off: visibility 0, so that none of the
        // light's SH is left, whose truncated clamped cosine still reaches above the horizon
        // (order 3, 5 degrees below: 0.05 of the light's facing irradiance, f(t) = 1/4 + t/2 +
        // 5/32 (3 t^2 - 1) at t = -0.087; Ramamoorthi and Hanrahan 2001, eq. 8).
        float v = u_light_direction[k].y < 0.0 ? 0.0 : ground_visibility(k, position);
        vec3 light_irradiance = u_flat_irradiance[k + 1];
#else
        float v = visibility(k, position, n, rotation);
        // Skipped where the light is seen, as at most samples (DESIGN.md section 8).
        vec3 light_irradiance = v < 1.0 ? irradiance(k + 1, Y) : vec3(0.0);
        // Normalised Blinn-Phong, (s + 8) / (8 pi), weighted by the light's intensity.
        vec3 l = u_light_direction[k];
        vec3 h = normalize(l + view);
        specular += v * albedo.a * (normal.w + 8.0) / (8.0 * PI) *
                    pow(max(dot(n, h), 0.0), normal.w) * max(dot(n, l), 0.0) *
                    u_light_intensity[k];
#endif
        // E = E(all) - sum_k (1 - w_k v_k) E(k) (DESIGN.md section 2) as set 0 minus
        // (1 - v) w_k E(k): the weights are in the sets and uniforms (frame_context.hpp).
        E -= (1.0 - v) * light_irradiance;
        attenuation -= (1.0 - v) * u_light_share[k];
    }
#endif
#if SURFACE == 2
    // The ground is Lambertian (DESIGN.md section 7).
    return vec4(albedo.rgb * u_albedo_scale * E * attenuation, 1.0);
#else
    return vec4(albedo.rgb * u_albedo_scale * E * attenuation + specular, 1.0);
#endif
}
#endif

#include "display.glsl"
void main() {
    o_color = output_color(shade(ivec2(gl_FragCoord.xy)));
}
