#version 450 core
#extension GL_GOOGLE_include_directive : require
// G-buffer of the opaque and alpha-masked primitives (BLEND ones are the transparent pass's):
// world position and ambient occlusion, shading normal and perceptual roughness, linear base
// colour and metallic (-1 for a Lambertian material), emitted radiance. ALPHA_TEST 1 (MASK
// materials) discards the fragments whose alpha is under the cutoff (glTF 2.0 section 3.9.4);
// MATERIAL_TEXTURES 0 is a material without textures (material.glsl). TRANSFER 1 (occlusion
// frames) also keeps the transfer's irradiance, interpolated from the vertices. MATERIAL_LAYERS 1
// (a material with the extensions' layers, in a frame with the G-buffer's two layer targets):
// also its layers, packed (layer_gbuffer.glsl).
#include "material.glsl"
#include "layer_gbuffer.glsl"
uniform vec3 u_eye;
layout(location = 0) out vec4 o_position;  // world position, ao
layout(location = 1) out vec4 o_normal;    // shading normal on the side seen, roughness
layout(location = 2) out vec4 o_albedo;    // linear base colour, metallic or -1
layout(location = 3) out vec4 o_emissive;  // emitted radiance
#if TRANSFER
in vec3 v_transferred_irradiance;
layout(location = 4) out vec4 o_transferred;  // the transfer's irradiance
#endif
#if MATERIAL_LAYERS
layout(location = 5) out uvec4 o_layers_first;  // pack_layers's first and second
layout(location = 6) out uvec4 o_layers_second;
#endif
void main() {
    vec4 base = material_base_color();
#if ALPHA_TEST
    if (base.a < u_alpha_cutoff) {
        discard;
    }
#endif
    MaterialSample m = sample_material(u_eye);
    o_position = vec4(v_world_position, m.ao);
    o_normal = vec4(m.normal, m.roughness);
    o_albedo = vec4(base.rgb, m.metallic);
    o_emissive = vec4(m.emissive, 1.0);
#if TRANSFER
    o_transferred = vec4(v_transferred_irradiance, 1.0);
#endif
#if MATERIAL_LAYERS
    pack_layers(m.layers, o_layers_first, o_layers_second);
#endif
}
