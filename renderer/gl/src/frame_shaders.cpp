#include "frame_shaders.hpp"

#include <string_view>
#include <utility>

namespace oer::shaders {

const char* const kMeshVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
out vec3 v_world_position;
out vec3 v_normal;
out vec2 v_texcoord;
void main() {
    vec4 world = u_model * vec4(a_position, 1.0);
    v_world_position = world.xyz;
    v_normal = u_normal_matrix * a_normal;
    v_texcoord = a_texcoord;
    gl_Position = u_view_projection * world;
}
)";

const char* const kDepthFragment = R"(#version 450 core
void main() {}
)";

// Lighting functions shared by the deferred shading pass and the ground-visibility bake.
// Shadow maps of the lights that are on are the layers of one depth array (texture unit 4),
// so that any number of lights needs two texture units, not one per light.
const char* const kLightingFunctions = R"(
const float PI = 3.14159265358979;
const int SH_COUNT = SH_ORDER * SH_ORDER;
// Irradiance coefficients A_l w_l L_lm (DESIGN.md section 3): set 0 is the map with the lights
// that are off removed; set k + 1 is the k-th light that is on.
layout(std430, binding = 0) readonly buffer Irradiance { vec4 coefficients[]; };
// K_lm (times sqrt 2 for m != 0) of the recurrence below, computed on the CPU in double.
uniform float u_sh_scale[SH_COUNT];
#if LIGHTS_ON > 0
uniform mat4 u_light_matrix[LIGHTS_ON];
uniform int u_light_layer[LIGHTS_ON];      // the light's layer in the shadow arrays
uniform float u_light_kernel[LIGHTS_ON];   // PCF radius in shadow-map uv
uniform float u_normal_offset[LIGHTS_ON];  // receiver offset against acne, world units
#if SHADOWS
layout(binding = 4) uniform sampler2DArrayShadow u_shadow_maps;
#endif
#endif

// Real SH without the Condon-Shortley phase, polar axis z (the thesis's appendix A forms):
// Y_lm = K_lm Q_l^m(z) Re/Im (x + i y)^|m|, where Q_l^m = P_l^m / (1 - z^2)^(m/2) follows the
// associated Legendre recurrence. The same basis as renderer/src/sh.cpp.
void sh_basis(vec3 d, out float Y[SH_COUNT]) {
    float cm = 1.0, sm = 0.0;  // Re and Im of (x + i y)^m
    float q_mm = 1.0;          // (2m - 1)!!
    for (int m = 0; m < SH_ORDER; ++m) {
        float q_previous = 0.0;
        float q = q_mm;
        for (int l = m; l < SH_ORDER; ++l) {
            if (l == m + 1) {
                q_previous = q;
                q = d.z * float(2 * m + 1) * q_previous;
            } else if (l > m + 1) {
                float next = (float(2 * l - 1) * d.z * q - float(l + m - 1) * q_previous) /
                             float(l - m);
                q_previous = q;
                q = next;
            }
            int centre = l * (l + 1);
            if (m == 0) {
                Y[centre] = u_sh_scale[centre] * q;
            } else {
                Y[centre + m] = u_sh_scale[centre + m] * q * cm;
                Y[centre - m] = u_sh_scale[centre - m] * q * sm;
            }
        }
        float c = cm * d.x - sm * d.y;
        sm = cm * d.y + sm * d.x;
        cm = c;
        q_mm *= float(2 * m + 1);
    }
}

vec3 irradiance(int set, float Y[SH_COUNT]) {
    vec3 sum = vec3(0.0);
    for (int i = 0; i < SH_COUNT; ++i) {
        sum += coefficients[set * SH_COUNT + i].rgb * Y[i];
    }
    return sum;
}

#if LIGHTS_ON > 0
// 16 points of a Poisson disc of radius 1.
const vec2 POISSON[16] = vec2[](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725), vec2(-0.09418410, -0.92938870),
    vec2(0.34495938, 0.29387760), vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379), vec2(0.44323325, -0.97511554),
    vec2(0.53742981, -0.47373420), vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590), vec2(0.19984126, 0.78641367),
    vec2(0.14383161, -0.14100790));

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
#if PCF
    // One bilinear comparison per tap (2x2 texels). Four spread taps first: where they agree
    // the point is fully lit or fully in shadow, as nearly every point is; only penumbrae pay
    // for the other twelve.
    const int EARLY[4] = int[](0, 1, 5, 7);
    float sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        vec2 uv = uvz.xy + rotation * POISSON[EARLY[i]] * u_light_kernel[k];
        sum += texture(u_shadow_maps, vec4(uv, float(u_light_layer[k]), reference));
    }
    if (sum == 0.0 || sum == 4.0) {
        return sum / 4.0;
    }
    for (int i = 0; i < 16; ++i) {
        if (i == 0 || i == 1 || i == 5 || i == 7) {
            continue;
        }
        vec2 uv = uvz.xy + rotation * POISSON[i] * u_light_kernel[k];
        sum += texture(u_shadow_maps, vec4(uv, float(u_light_layer[k]), reference));
    }
    return sum / 16.0;
#else
    return texture(u_shadow_maps, vec4(uvz.xy, float(u_light_layer[k]), reference));
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
)";

const char* const kGeometryFragment = R"(#version 450 core
in vec3 v_world_position;
in vec3 v_normal;
in vec2 v_texcoord;
uniform vec4 u_base_color;
uniform int u_has_texture;
layout(binding = 0) uniform sampler2D u_base_texture;
uniform float u_specular_weight;  // 0: Lambertian only
uniform float u_shininess;
uniform vec3 u_eye;
layout(location = 0) out vec4 o_position;  // world position
layout(location = 1) out vec4 o_normal;    // world normal on the side seen, shininess
layout(location = 2) out vec4 o_albedo;    // linear albedo, specular weight
void main() {
    vec3 n = normalize(v_normal);
    // Open meshes (the bunny's base) show their inside, lit as a surface: a back face whose
    // normals also face away. A back face whose normals face the eye is a fold, such as
    // simplification leaves in slivers, and keeps them.
    if (!gl_FrontFacing && dot(n, u_eye - v_world_position) < 0.0) {
        n = -n;
    }
    vec3 albedo = u_base_color.rgb;
    if (u_has_texture != 0) {
        albedo *= texture(u_base_texture, v_texcoord).rgb;
    }
    o_position = vec4(v_world_position, 1.0);
    o_normal = vec4(n, u_shininess);
    o_albedo = vec4(albedo, u_specular_weight);
}
)";

const char* const kShadeFragment = R"(#version 450 core
// Deferred shading: every sample is shaded once, in whole blocks, by the program of its
// surface (SURFACE 0 the background, 1 objects, 2 the ground plane), which the stencil test
// routes to it. Shading the meshes' fragments directly costs far more on llvmpipe, whose 4x4
// blocks are mostly empty on small triangles, and whose SIMD lanes would run every branch of
// a shader that handled all three surfaces.
#include_lighting
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
uniform float u_attenuation_base;  // thesis: 1 - sum of the off lights' luminance shares
#if LIGHTS_ON > 0
uniform vec3 u_light_direction[LIGHTS_ON];
uniform vec3 u_light_intensity[LIGHTS_ON];
uniform float u_light_share[LIGHTS_ON];  // thesis model; 0 in the hdr model
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
        float v = ground_visibility(k, position);
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
        // c = c(on) - (1 - v) c(k) (DESIGN.md section 2).
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

#include_display
void main() {
    o_color = output_color(shade(ivec2(gl_FragCoord.xy)));
}
)";

const char* const kGroundVisibilityFragment = R"(#version 450 core
// Bakes light LIGHT's visibility on the ground plane y = u_ground_height over its shadow map:
// the texel's light ray meets the plane at one point, whose visibility is the same function the
// shading pass uses for objects.
#include_lighting
uniform mat4 u_inverse_light_matrix;
uniform float u_ground_height;
uniform int u_light;
uniform vec2 u_size;
out float o_visibility;
void main() {
    vec2 ndc = gl_FragCoord.xy / u_size * 2.0 - 1.0;
    vec4 a = u_inverse_light_matrix * vec4(ndc, -1.0, 1.0);
    vec4 b = u_inverse_light_matrix * vec4(ndc, 1.0, 1.0);
    vec3 from = a.xyz / a.w;
    vec3 to = b.xyz / b.w;
    if (abs(to.y - from.y) < 1e-12) {
        o_visibility = 1.0;  // a horizontal light never meets the plane within its map
        return;
    }
    vec3 point = mix(from, to, (u_ground_height - from.y) / (to.y - from.y));
    // The disc is not turned: per-texel noise would be magnified over the ground into a pattern.
    o_visibility = visibility(u_light, point, vec3(0.0, 1.0, 0.0), mat2(1.0));
}
)";

const char* const kFullscreenVertex = R"(#version 450 core
void main() {
    gl_Position =
        vec4(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1), 1.0, 1.0);
}
)";

// Exposure, tone mapping, sRGB and compositing over the background color, applied to
// premultiplied linear radiance (alpha = coverage) when DISPLAY_OUTPUT is 1; linear output
// (EXR) keeps the radiance as it is.
const char* const kDisplayFunctions = R"(
#if DISPLAY_OUTPUT
uniform float u_exposure_scale;
uniform int u_tonemap;     // 0 neutral, 1 aces, 2 none: as renderer/src/tonemap.cpp
uniform vec4 u_background;     // sRGB color; alpha 1 to composite over it, 0 for transparency

vec3 neutral(vec3 color) {  // Khronos PBR Neutral
    const float start_compression = 0.8 - 0.04;
    const float desaturation = 0.15;
    float x = min(color.r, min(color.g, color.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;
    float peak = max(color.r, max(color.g, color.b));
    if (peak < start_compression) return color;
    const float d = 1.0 - start_compression;
    float new_peak = 1.0 - d * d / (peak + d - start_compression);
    color *= new_peak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(color, vec3(new_peak), g);
}

vec3 aces(vec3 c) {  // Stephen Hill's fit
    vec3 v = vec3(dot(vec3(0.59719, 0.35458, 0.04823), c), dot(vec3(0.07600, 0.90834, 0.01566), c),
                  dot(vec3(0.02840, 0.13383, 0.83777), c));
    vec3 f = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081);
    return vec3(dot(vec3(1.60475, -0.53108, -0.07367), f), dot(vec3(-0.10208, 1.10813, -0.00605), f),
                dot(vec3(-0.00327, -0.07276, 1.07602), f));
}

vec3 srgb_encode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec4 output_color(vec4 radiance) {
    float alpha = clamp(radiance.a, 0.0, 1.0);
    vec3 linear = alpha > 0.0 ? max(radiance.rgb / alpha, 0.0) * u_exposure_scale : vec3(0.0);
    vec3 mapped = linear;
    if (u_tonemap == 0) mapped = neutral(linear);
    else if (u_tonemap == 1) mapped = aces(linear);
    vec3 display = srgb_encode(clamp(mapped, 0.0, 1.0));
    if (u_background.a > 0.0) {
        return vec4(mix(u_background.rgb, display, alpha), 1.0);
    }
    return vec4(display, alpha);
}
#else
vec4 output_color(vec4 radiance) { return radiance; }
#endif
)";

const char* const kResolveFragment = R"(#version 450 core
// Anti-aliasing: the mean of each pixel's u_scale x u_scale supersamples, then the output
// transform. Radiance is averaged before tone mapping, as a multisample resolve would.
layout(binding = 0) uniform sampler2D u_radiance;  // premultiplied by coverage alpha
uniform int u_scale;
out vec4 o_color;
#include_display
void main() {
    ivec2 base = ivec2(gl_FragCoord.xy) * u_scale;
    vec4 sum = vec4(0.0);
    for (int y = 0; y < u_scale; ++y) {
        for (int x = 0; x < u_scale; ++x) {
            sum += texelFetch(u_radiance, base + ivec2(x, y), 0);
        }
    }
    o_color = output_color(sum / float(u_scale * u_scale));
}
)";

std::string compose(const char* source) {
    std::string text = source;
    for (const auto& [marker, part] : {std::pair{"#include_lighting\n", kLightingFunctions},
                                       std::pair{"#include_display\n", kDisplayFunctions}}) {
        const std::size_t at = text.find(marker);
        if (at != std::string::npos) {
            text.replace(at, std::string_view(marker).size(), part);
        }
    }
    return text;
}

}  // namespace oer::shaders
