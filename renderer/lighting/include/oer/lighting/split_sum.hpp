#pragma once
// The second factor of the split-sum approximation (B. Karis, "Real Shading in Unreal
// Engine 4", SIGGRAPH 2013; RTR4 section 10.5.2): the directional albedo of the glTF
// specular BRDF (GGX D, height-correlated Smith visibility, Schlick Fresnel; glTF 2.0
// Appendix B) with white light, split by Schlick's F = F0 + (1 - F0)(1 - v.h)^5 as
//   E_ss(n.v, roughness) = F0 A + B,
//   A = integral of (1 - (1 - v.h)^5) f_spec / F n.l dl,  B = integral of (1 - v.h)^5 f_spec / F
//   n.l dl,
// tabulated by GGX importance sampling. A + B is the single-scattering energy E_ss of a white
// metal; the shader compensates the rest by C. Fdez-Aguera, "A Multiple-Scattering
// Microfacet Model for Real-Time Image-based Lighting", JCGT 8(1), 2019.
#include <vector>

#include <glm/vec2.hpp>

namespace oer {

struct DfgTable {
    int size = 0;
    // size x size (A, B): row j at perceptual roughness (j + 0.5) / size, column i at
    // n.v = (i + 0.5) / size (texel centres, as a GL_RG32F texture sampled with clamping).
    std::vector<glm::vec2> scale_bias;
};

// Throws oer::Error (InvalidInput) for size outside [2, 256] or samples outside [1, 65536].
// Deterministic (Hammersley points).
DfgTable dfg_table(int size = 32, int samples = 1024);

// The table read bilinearly as the shader does (clamped at the edges).
glm::dvec2 sample_dfg(const DfgTable& table, double n_dot_v, double roughness);

}  // namespace oer
