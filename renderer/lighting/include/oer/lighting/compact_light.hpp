#pragma once
// The BRDF's own reflection of a compact light, where the split sum's is wrong (the shader's
// compact_light_factor, renderer/gl/shaders/specular_lighting.glsl, is this file's).
//
// A light's reflection is its own prefiltered cube read about r (specular_environment.hpp),
// times the split sum's single scattering: P_k(r) (F0 A + F90 B). Of a light small against the
// lobe that keeps the energy over all directions but not where it goes: the cube's lobe is the
// prefiltering kernel K(r, l) = D(h) (r.l) about r with n = v = r, where the BRDF's,
// F D G2 / (4 n.l n.v) n.l, leans to the normal and rises at grazing view. For a point light of
// energy Phi at l the two are
//   split:  Phi single_scattering K(r, l) / Z(alpha)
//   BRDF:   Phi F(v.h) D(n.h) V(n.v, n.l) n.l,   V = G2 / (4 n.l n.v) (height-correlated Smith),
// so the factor that turns one into the other is their ratio, taken at the light's point
// nearest r (its disc's), for the light's core and its glow by their shares. It applies by the
// share of the lobe outside each disc, 1 - T / (alpha^2 + T) (GGX's cumulative distribution,
// as light_lod takes it): a light wider than the lobe (a soft box in chrome) keeps its shape
// and the split sum, whose lobe then draws the light's own picture.
//
// Measured against the reference renderer (bench/material_gallery.cpp, a metal sphere alone
// under Blender's studio): relative RMS error at roughness 0.3 from 0.19 to 0.13, at 0.5 from
// 0.17 to 0.11 (docs/glossy-reference.md).

#include <glm/vec3.hpp>

#include "oer/lighting/specular_environment.hpp"

namespace oer {

// The direction the split sum's cubes are read along (the shader's specular_dominant_direction,
// brdf.glsl): the mirror direction r leaned towards n as the lobe widens, normalize(mix(n, r,
// s)), s = (1 - alpha)(sqrt(1 - alpha) + alpha) (Lagarde and de Rousiers 2014, listing 22).
glm::dvec3 specular_dominant_direction(const glm::dvec3& n, const glm::dvec3& r, double alpha);

// A glossy surface point as the split sum shades it: unit normal, view and reflection
// directions (r: the direction the cubes are read along, specular_dominant_direction), n.v (clamped
// as the shader clamps it), GGX's alpha, the Fresnel terms, and the split sum's single-scattering
// weight F0 A + F90 B at (n.v, roughness).
struct GlossyPoint {
    glm::dvec3 n;
    glm::dvec3 v;
    glm::dvec3 r;
    double n_dot_v = 1.0;
    double alpha = 0.0;
    glm::dvec3 f0{0.04};
    double f90 = 1.0;
    glm::dvec3 single_scattering{1.0};
    // An opaque floor hides the light's part below the horizon (y < 0): the light's point
    // nearest r is then taken on the horizon.
    bool floor_below = false;
};

// The shader's bound on the ratio: where the kernel has all but left the light's point while
// the BRDF still sees it (grazing view), the ratio of two vanishing lobes says little.
inline constexpr double kCompactLightFactorMax = 8.0;

// BRDF over split sum for a point light on the disc of tan^2(radius / 2) = cap_tan2 about
// `toward_light`, at the disc's point nearest r; clamped to [0, kCompactLightFactorMax].
glm::dvec3 point_light_ratio(const glm::dvec3& toward_light, double cap_tan2,
                             const GlossyPoint& point);

// The factor of the light's reflection: 1 + sum over core and glow of share outside
// (ratio - 1).
glm::dvec3 compact_light_factor(const glm::dvec3& toward_light, const LightSpread& spread,
                                const GlossyPoint& point);

}  // namespace oer
