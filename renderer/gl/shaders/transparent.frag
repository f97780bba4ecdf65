#version 450 core
#extension GL_GOOGLE_include_directive : require
// Transparent pass: BLEND primitives (glTF 2.0 section 3.9.4), forward shaded by the same
// surface shading as the deferred pass, over the shaded frame: premultiplied radiance, blended
// "over" (T. Porter and T. Duff, "Compositing Digital Images", SIGGRAPH 1984) as
// src + (1 - src alpha) dst by the pass's blend state, alpha being coverage. MATERIAL_LAYERS 1:
// a material with the extensions' layers (material.glsl).
#define MATERIAL_TEXTURES 1
// It draws objects only; glossy ones reflect the floor as the ground is drawn, from the ground's
// textures the shading pass left bound (ground_lighting.glsl).
#define GROUND_SURFACE 0
#include "material.glsl"
#include "surface_shading.glsl"
in vec3 v_transferred_irradiance;
out vec4 o_color;
void main() {
    vec4 base = material_base_color();
    MaterialSample m = sample_material(u_eye);
#if TRANSFER
    vec3 transferred = v_transferred_irradiance;
#else
    vec3 transferred = vec3(0.0);
#endif
#if MATERIAL_LAYERS
    SurfaceLayers layers = m.layers;
#else
    SurfaceLayers layers = plain_layers();
#endif
    vec3 radiance = shade_object(v_world_position, m.normal, base.rgb, m.metallic, m.roughness,
                                 m.ao, m.emissive, transferred, layers);
    o_color = vec4(radiance * base.a, base.a);
}
