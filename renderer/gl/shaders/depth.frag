#version 450 core
#extension GL_GOOGLE_include_directive : require
// Shadow pass: depth only. ALPHA_TEST 1, for MASK and BLEND primitives whose alpha varies or is
// under 1: no shadow where the base colour's alpha is under the cutoff (MASK's alpha_cutoff;
// 0.5 for BLEND, which casts a shadow where it is at least half opaque).
#if ALPHA_TEST
#define MATERIAL_TEXTURES 1
#define MATERIAL_LAYERS 0
#include "material.glsl"
void main() {
    if (material_base_color().a < u_alpha_cutoff) {
        discard;
    }
}
#else
void main() {}
#endif
