#version 450 core
#extension GL_GOOGLE_include_directive : require
// Layered pass: the OPAQUE and MASK primitives whose material has the extensions' layers
// (mesh.hpp's Material::layered), forward shaded by surface_shading.glsl on the samples the
// geometry pass gave them (its stencil kLayeredSurface, its depth), which the deferred shading
// pass leaves alone: the G-buffer does not hold the layers, and a plain material's frame pays
// nothing for them. ALPHA_TEST 1 (MASK materials) cuts as the geometry pass did.
#define MATERIAL_TEXTURES 1
#define MATERIAL_LAYERS 1
#include "material.glsl"
#include "surface_shading.glsl"
in vec3 v_transferred_irradiance;
out vec4 o_color;
void main() {
    vec4 base = material_base_color();
#if ALPHA_TEST
    if (base.a < u_alpha_cutoff) {
        discard;
    }
#endif
    MaterialSample m = sample_material(u_eye);
#if TRANSFER
    vec3 transferred = v_transferred_irradiance;
#else
    vec3 transferred = vec3(0.0);
#endif
    o_color = vec4(shade_object(v_world_position, m.normal, base.rgb, m.metallic, m.roughness,
                                m.ao, m.emissive, transferred, m.layers),
                   1.0);
}
