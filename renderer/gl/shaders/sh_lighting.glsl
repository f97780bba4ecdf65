// Irradiance from spherical harmonics for the deferred shading pass: the SH basis at a
// direction and the irradiance of one coefficient set there. SH_ORDER: bands 0 .. SH_ORDER-1.
const int SH_COUNT = SH_ORDER * SH_ORDER;
// Irradiance coefficients A_l w_l L_lm (docs/design.md section 3): set 0 is the map with each
// light k scaled to its weight w_k, E(all) - sum_k (1 - w_k) E(k); set i + 1 is w_k E(k) for the
// i-th light of weight above 0 (renderer/gl/src/frame_context.hpp).
layout(std430, binding = IRRADIANCE_SETS_BINDING) readonly buffer Irradiance {
    vec4 coefficients[];
};
// K_lm (times sqrt 2 for m != 0) of the recurrence below, computed on the CPU in double.
uniform float u_sh_scale[SH_COUNT];

// Real SH without the Condon-Shortley phase, polar axis z (the thesis's appendix A forms):
// Y_lm = K_lm Q_l^m(z) Re/Im (x + i y)^|m|, where Q_l^m = P_l^m / (1 - z^2)^(m/2) follows the
// associated Legendre recurrence. The same basis as renderer/lighting/src/sh.cpp.
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
