// A glTF 2.0 material at a mesh fragment (specification, section 3.9): its factors times its
// five textures, each read on its own uv set (TEXCOORD_0 or TEXCOORD_1) through its own uv
// transform (KHR_texture_transform, built on the CPU as translation * rotation * scale) and
// sampler, the base colour times the vertex colour (COLOR_0). Shared by the geometry pass, the
// shadow pass's alpha test and the transparent pass. MATERIAL_TEXTURES 0 (a material without
// textures on a primitive without vertex colours, as an OBJ's): the factors alone, with no uv,
// colour or tangent read, so that the program interpolates none of them (llvmpipe interpolates
// every input a fragment shader reads). MATERIAL_LAYERS 1 (the geometry and transparent programs
// of a material with extension layers, mesh.hpp's Material::layered): also the layers' factors
// and nine textures, as SurfaceLayers (brdf.glsl); 0: none of them is declared or read.
in vec3 v_world_position;
in vec3 v_normal;
#if MATERIAL_TEXTURES
in vec2 v_texcoord;
in vec2 v_texcoord1;
in vec4 v_color;  // COLOR_0, or (1, 1, 1, 1)
in vec4 v_tangent;
#endif

// The texture references, in this order (gl_bindings.hpp's kMaterialTextures, mesh.hpp's
// Material::texture_references).
const int BASE_COLOR_TEXTURE = 0;
const int METALLIC_ROUGHNESS_TEXTURE = 1;
const int NORMAL_TEXTURE = 2;
const int OCCLUSION_TEXTURE = 3;
const int EMISSIVE_TEXTURE = 4;
const int MATERIAL_REFERENCES = 14;
// Base colour and emissive are sRGB, the others linear (metallic in B, roughness in G,
// occlusion in R).
layout(binding = BASE_COLOR_TEXTURE_UNIT) uniform sampler2D u_base_color_texture;
layout(binding = METALLIC_ROUGHNESS_TEXTURE_UNIT) uniform sampler2D u_metallic_roughness_texture;
layout(binding = NORMAL_TEXTURE_UNIT) uniform sampler2D u_normal_texture;
layout(binding = OCCLUSION_TEXTURE_UNIT) uniform sampler2D u_occlusion_texture;
layout(binding = EMISSIVE_TEXTURE_UNIT) uniform sampler2D u_emissive_texture;
uniform int u_textures;  // bit i: reference i is present
uniform mat3 u_uv_transform[MATERIAL_REFERENCES];
uniform int u_uv_sets;  // bit i: reference i reads TEXCOORD_1 (v_texcoord1), else TEXCOORD_0

uniform vec4 u_base_color;  // linear RGBA
// 1: the base-colour texture's RGB multiplies the base colour; 0: the object's colour replaced
// it (SceneObject::base_color), and only the texture's alpha is kept.
uniform float u_base_texture_color;
uniform float u_metallic;  // -1: a Lambertian material
uniform float u_roughness;
uniform float u_normal_scale;
uniform float u_occlusion_strength;
uniform vec3 u_emissive;  // emissive factor times KHR_materials_emissive_strength
uniform float u_alpha_cutoff;

// Outside any #if: a part is spliced in once, where it is first included (shader_sources.hpp).
#include "brdf.glsl"
#if MATERIAL_LAYERS
const int SPECULAR_TEXTURE = 5;
const int SPECULAR_COLOR_TEXTURE = 6;
const int CLEARCOAT_TEXTURE = 7;
const int CLEARCOAT_ROUGHNESS_TEXTURE = 8;
const int CLEARCOAT_NORMAL_TEXTURE = 9;
const int SHEEN_COLOR_TEXTURE = 10;
const int SHEEN_ROUGHNESS_TEXTURE = 11;
const int TRANSMISSION_TEXTURE = 12;
const int THICKNESS_TEXTURE = 13;
// Each extension's channels: specular in A, specular colour RGB (sRGB), clear coat in R, its
// roughness in G, its normal as normalTexture's, sheen colour RGB (sRGB), sheen roughness in A,
// transmission in R, thickness in G.
layout(binding = SPECULAR_TEXTURE_UNIT) uniform sampler2D u_specular_texture;
layout(binding = SPECULAR_COLOR_TEXTURE_UNIT) uniform sampler2D u_specular_color_texture;
layout(binding = CLEARCOAT_TEXTURE_UNIT) uniform sampler2D u_clearcoat_texture;
layout(binding = CLEARCOAT_ROUGHNESS_TEXTURE_UNIT) uniform sampler2D u_clearcoat_roughness_texture;
layout(binding = CLEARCOAT_NORMAL_TEXTURE_UNIT) uniform sampler2D u_clearcoat_normal_texture;
layout(binding = SHEEN_COLOR_TEXTURE_UNIT) uniform sampler2D u_sheen_color_texture;
layout(binding = SHEEN_ROUGHNESS_TEXTURE_UNIT) uniform sampler2D u_sheen_roughness_texture;
layout(binding = TRANSMISSION_TEXTURE_UNIT) uniform sampler2D u_transmission_texture;
layout(binding = THICKNESS_TEXTURE_UNIT) uniform sampler2D u_thickness_texture;
uniform float u_ior;                      // KHR_materials_ior
uniform float u_specular_factor;          // KHR_materials_specular
uniform vec3 u_specular_color;
uniform float u_clearcoat;                // KHR_materials_clearcoat
uniform float u_clearcoat_roughness;
uniform float u_clearcoat_normal_scale;
uniform vec3 u_sheen_color;               // KHR_materials_sheen
uniform float u_sheen_roughness;
uniform float u_transmission;             // KHR_materials_transmission
uniform float u_thickness;                // KHR_materials_volume
// The volume's attenuation coefficient, -ln(attenuationColor) / attenuationDistance per channel.
uniform vec3 u_attenuation_coefficient;
#endif

#if MATERIAL_TEXTURES
bool has_texture(int reference) { return (u_textures & (1 << reference)) != 0; }

vec2 material_uv(int reference) {
    vec2 uv = (u_uv_sets & (1 << reference)) != 0 ? v_texcoord1 : v_texcoord;
    return (u_uv_transform[reference] * vec3(uv, 1.0)).xy;
}
#endif

vec4 material_base_color() {
    vec4 base = u_base_color;
#if MATERIAL_TEXTURES
    if (has_texture(BASE_COLOR_TEXTURE)) {
        vec4 texel = texture(u_base_color_texture, material_uv(BASE_COLOR_TEXTURE));
        base *= vec4(mix(vec3(1.0), texel.rgb, u_base_texture_color), texel.a);
    }
    // The vertex colour multiplies as the texture does (its RGB replaced with it by the object's
    // colour, its alpha kept).
    base *= vec4(mix(vec3(1.0), v_color.rgb, u_base_texture_color), v_color.a);
#endif
    return base;
}

struct MaterialSample {
    vec3 normal;      // unit shading normal, on the side seen
    float metallic;   // -1: Lambertian, -2: unlit
    float roughness;  // perceptual
    float ao;         // 1 + strength (occlusion - 1)
    vec3 emissive;
#if MATERIAL_LAYERS
    SurfaceLayers layers;
#endif
};

#if MATERIAL_TEXTURES
// n perturbed by a tangent-space normal map's texel (the tangent frame of glTF 2.0 section
// 3.7.2.1: bitangent = w cross(n, t); the map's xy scaled by its scale, section 3.9.3; t made
// orthogonal to the interpolated n), or n where the frame degenerates.
vec3 mapped_normal(vec3 n, vec3 texel, float scale) {
    vec3 t = v_tangent.xyz - n * dot(n, v_tangent.xyz);
    if (dot(t, t) <= 1e-12) {
        return n;
    }
    t = normalize(t);
    vec3 b = v_tangent.w * cross(n, t);
    vec3 mapped = texel * 2.0 - 1.0;
    mapped.xy *= scale;
    return normalize(t * mapped.x + b * mapped.y + n * mapped.z);
}
#endif

// Geometric specular antialiasing (Y. Tokuyoshi and A. S. Kaplanyan, "Improved Geometric
// Specular Antialiasing", I3D 2019, after A. S. Kaplanyan, S. Hill, A. Patney and A. Lefohn,
// "Filtering Distributions of Normals for Shading Antialiasing", HPG 2016): a pixel sees the
// normals that vary across it, so its lobe is GGX widened by their variance,
//   alpha^2 + min(2 sigma^2, kappa),  sigma^2 = 0.25 (|dn/dx|^2 + |dn/dy|^2),  kappa = 0.18,
// returned as perceptual roughness (alpha = roughness^2). Without it a curved mirror point-
// samples a small bright light: a sphere twenty pixels wide showed the sun of Blender's sunrise
// at its full radiance in whichever pixel's centre met its reflection (55 times the reference's
// error over that sphere), where the reference averages the pixel's footprint. n must be
// computed in uniform control flow (its derivatives).
float antialiased_roughness(vec3 n, float roughness) {
    vec3 dndx = dFdx(n), dndy = dFdy(n);
    float variance = 0.25 * (dot(dndx, dndx) + dot(dndy, dndy));
    float alpha = roughness * roughness;
    return sqrt(sqrt(clamp(alpha * alpha + min(2.0 * variance, 0.18), 0.0, 1.0)));
}

#if MATERIAL_LAYERS
// The extensions' factors times their textures at the fragment (mesh.hpp's layers), n the
// interpolated normal, which the coat follows where it has no normal map, turned to the side
// seen where flip is (as sample_material turns its shading normal).
SurfaceLayers sample_layers(vec3 n, bool flip) {
    float specular = u_specular_factor;
    vec3 specular_color = u_specular_color;
    float clearcoat = u_clearcoat;
    float clearcoat_roughness = u_clearcoat_roughness;
    vec3 clearcoat_normal = n;
    vec3 sheen_color = u_sheen_color;
    float sheen_roughness = u_sheen_roughness;
    float transmission = u_transmission;
    float thickness = u_thickness;
#if MATERIAL_TEXTURES
    if (has_texture(SPECULAR_TEXTURE)) {
        specular *= texture(u_specular_texture, material_uv(SPECULAR_TEXTURE)).a;
    }
    if (has_texture(SPECULAR_COLOR_TEXTURE)) {
        specular_color *=
            texture(u_specular_color_texture, material_uv(SPECULAR_COLOR_TEXTURE)).rgb;
    }
    if (has_texture(CLEARCOAT_TEXTURE)) {
        clearcoat *= texture(u_clearcoat_texture, material_uv(CLEARCOAT_TEXTURE)).r;
    }
    if (has_texture(CLEARCOAT_ROUGHNESS_TEXTURE)) {
        clearcoat_roughness *=
            texture(u_clearcoat_roughness_texture, material_uv(CLEARCOAT_ROUGHNESS_TEXTURE)).g;
    }
    if (has_texture(CLEARCOAT_NORMAL_TEXTURE)) {
        clearcoat_normal = mapped_normal(
            n, texture(u_clearcoat_normal_texture, material_uv(CLEARCOAT_NORMAL_TEXTURE)).xyz,
            u_clearcoat_normal_scale);
    }
    if (has_texture(SHEEN_COLOR_TEXTURE)) {
        sheen_color *= texture(u_sheen_color_texture, material_uv(SHEEN_COLOR_TEXTURE)).rgb;
    }
    if (has_texture(SHEEN_ROUGHNESS_TEXTURE)) {
        sheen_roughness *=
            texture(u_sheen_roughness_texture, material_uv(SHEEN_ROUGHNESS_TEXTURE)).a;
    }
    if (has_texture(TRANSMISSION_TEXTURE)) {
        transmission *= texture(u_transmission_texture, material_uv(TRANSMISSION_TEXTURE)).r;
    }
    if (has_texture(THICKNESS_TEXTURE)) {
        thickness *= texture(u_thickness_texture, material_uv(THICKNESS_TEXTURE)).g;
    }
#endif
    clearcoat_roughness = antialiased_roughness(clearcoat_normal, clearcoat_roughness);
    return material_layers(u_ior, specular, specular_color, clearcoat, clearcoat_roughness,
                           flip ? -clearcoat_normal : clearcoat_normal, sheen_color, sheen_roughness, transmission,
                           volume_transmittance(u_attenuation_coefficient, thickness));
}
#endif

MaterialSample sample_material(vec3 eye) {
    MaterialSample m;
    vec3 n = normalize(v_normal);
    // Open meshes (the bunny's base) show their inside, lit as a surface: a back face whose
    // normals also face away. A back face whose normals face the eye is a fold, such as
    // simplification leaves in slivers, and keeps them.
    bool flip = !gl_FrontFacing && dot(n, eye - v_world_position) < 0.0;
    m.metallic = u_metallic;
    m.roughness = u_roughness;
    m.ao = 1.0;
    m.emissive = u_emissive;
#if MATERIAL_LAYERS
    m.layers = sample_layers(n, flip);
#endif
#if MATERIAL_TEXTURES
    if (has_texture(NORMAL_TEXTURE)) {
        n = mapped_normal(n, texture(u_normal_texture, material_uv(NORMAL_TEXTURE)).xyz,
                          u_normal_scale);
    }
    if (u_metallic >= 0.0 && has_texture(METALLIC_ROUGHNESS_TEXTURE)) {
        vec4 texel =
            texture(u_metallic_roughness_texture, material_uv(METALLIC_ROUGHNESS_TEXTURE));
        m.roughness *= texel.g;
        m.metallic *= texel.b;
    }
    if (has_texture(OCCLUSION_TEXTURE)) {
        float occlusion = texture(u_occlusion_texture, material_uv(OCCLUSION_TEXTURE)).r;
        m.ao = 1.0 + u_occlusion_strength * (occlusion - 1.0);
    }
    if (has_texture(EMISSIVE_TEXTURE)) {
        m.emissive *= texture(u_emissive_texture, material_uv(EMISSIVE_TEXTURE)).rgb;
    }
#endif
    m.roughness = antialiased_roughness(n, m.roughness);
    m.normal = flip ? -n : n;
    return m;
}
