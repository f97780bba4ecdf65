#version 450 core
#extension GL_GOOGLE_include_directive : require
// Bakes light LIGHT's visibility on the ground plane y = u_ground_height over its shadow map:
// the texel's light ray meets the plane at one point, whose visibility is the same function the
// shading pass uses for objects.
#include "shadow_filter.glsl"
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
    // The spiral is not turned: per-texel noise would be magnified over the ground into a pattern.
    o_visibility = baked_visibility(u_light, point, vec3(0.0, 1.0, 0.0));
}
