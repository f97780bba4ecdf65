#pragma once
// The terms of the glTF 2.0 metallic-roughness specular BRDF (specification, Appendix B.3.2)
// that more than one integrator evaluates: the split sum's DFG table (split_sum.cpp) and the
// reference renderer's BRDF (renderer/reference). GGX's D is sampling.hpp's ggx_distribution,
// beside its sampling.

namespace oer {

// Height-correlated Smith visibility V = G2 / (4 n.l n.v) of GGX, the microfacet denominator
// included (E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
// JCGT 3(2), 2014, eq. 99; glTF 2.0 Appendix B.3.2):
//   V = 0.5 / (n.l sqrt(n.v^2 (1 - a^2) + a^2) + n.v sqrt(n.l^2 (1 - a^2) + a^2)), a = alpha.
double smith_visibility(double n_dot_v, double n_dot_l, double alpha);

// Smith's masking G1 of GGX towards a direction at n.w = n_dot_w (Heitz 2014, eq. 43 with
// GGX's Lambda): 2 n.w / (n.w + sqrt(a^2 + (1 - a^2) n.w^2)).
double smith_masking(double n_dot_w, double alpha);

}  // namespace oer
