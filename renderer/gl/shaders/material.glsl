// A glTF 2.0 material at a mesh fragment (specification, section 3.9): its factors times its
// five textures, each read on its own uv set (TEXCOORD_0 or TEXCOORD_1) through its own uv
// transform (KHR_texture_transform, built on the CPU as translation * rotation * scale) and
// sampler, the base colour times the vertex colour (COLOR_0). Shared by the geometry pass, the
// shadow pass's alpha test and the transparent pass. MATERIAL_TEXTURES 0 (a material without
// textures on a primitive without vertex colours, as an OBJ's): the factors alone, with no uv,
// colour or tangent read, so that the program interpolates none of them (llvmpipe interpolates
// every input a fragment shader reads).
in vec3 v_world_position;
in vec3 v_normal;
#if MATERIAL_TEXTURES
in vec2 v_texcoord;
in vec2 v_texcoord1;
in vec4 v_color;  // COLOR_0, or (1, 1, 1, 1)
in vec4 v_tangent;
#endif

// The texture references, in this order (gl_bindings.hpp's kMaterialTextures).
const int BASE_COLOR_TEXTURE = 0;
const int METALLIC_ROUGHNESS_TEXTURE = 1;
const int NORMAL_TEXTURE = 2;
const int OCCLUSION_TEXTURE = 3;
const int EMISSIVE_TEXTURE = 4;
// Base colour and emissive are sRGB, the others linear (metallic in B, roughness in G,
// occlusion in R).
layout(binding = BASE_COLOR_TEXTURE_UNIT) uniform sampler2D u_base_color_texture;
layout(binding = METALLIC_ROUGHNESS_TEXTURE_UNIT) uniform sampler2D u_metallic_roughness_texture;
layout(binding = NORMAL_TEXTURE_UNIT) uniform sampler2D u_normal_texture;
layout(binding = OCCLUSION_TEXTURE_UNIT) uniform sampler2D u_occlusion_texture;
layout(binding = EMISSIVE_TEXTURE_UNIT) uniform sampler2D u_emissive_texture;
uniform int u_textures;  // bit i: reference i is present
uniform mat3 u_uv_transform[5];
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
    float metallic;   // -1: Lambertian
    float roughness;  // perceptual
    float ao;         // 1 + strength (occlusion - 1)
    vec3 emissive;
};

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
#if MATERIAL_TEXTURES
    if (has_texture(NORMAL_TEXTURE)) {
        // The tangent frame (glTF 2.0 section 3.7.2.1): bitangent = w cross(n, t), the map's xy
        // scaled by normal_scale (section 3.9.3); t made orthogonal to the interpolated n.
        vec3 t = v_tangent.xyz - n * dot(n, v_tangent.xyz);
        if (dot(t, t) > 1e-12) {
            t = normalize(t);
            vec3 b = v_tangent.w * cross(n, t);
            vec3 mapped = texture(u_normal_texture, material_uv(NORMAL_TEXTURE)).xyz * 2.0 - 1.0;
            mapped.xy *= u_normal_scale;
            n = normalize(t * mapped.x + b * mapped.y + n * mapped.z);
        }
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
    m.normal = flip ? -n : n;
    return m;
}
