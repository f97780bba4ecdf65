#version 450 core
#extension GL_GOOGLE_include_directive : require
// Anti-aliasing: the mean of each pixel's u_scale x u_scale supersamples, then the output
// transform. Radiance is averaged before tone mapping, as a multisample resolve would.
// Premultiplied by coverage alpha.
layout(binding = RESOLVE_RADIANCE_UNIT) uniform sampler2D u_radiance;
uniform int u_scale;
out vec4 o_color;
#include "display.glsl"
void main() {
    ivec2 base = ivec2(gl_FragCoord.xy) * u_scale;
    // The mean as a sum of fractions: samples near the largest float (a repaired +Inf in the
    // map) would overflow a plain sum to Inf. (Exact for 4 and 16 samples, powers of two.)
    float weight = 1.0 / float(u_scale * u_scale);
    vec4 mean = vec4(0.0);
    for (int y = 0; y < u_scale; ++y) {
        for (int x = 0; x < u_scale; ++x) {
            mean += weight * texelFetch(u_radiance, base + ivec2(x, y), 0);
        }
    }
    o_color = output_color(mean);
}
