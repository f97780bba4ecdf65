#pragma once
// The sampling primitives every integrator in the tree shares: the specular cube's prefilter
// (specular_environment.cpp), the split sum's DFG table (split_sum.cpp), the reference renderer
// and the transfer bake. One definition each, so that the estimators sample the same way (as
// Filament's libs/ibl shares one set among its prefilters).
//  - Low-discrepancy points: the radical inverse in base 2 (J. G. van der Corput, 1935) and the
//    Hammersley set built on it (J. M. Hammersley and D. C. Handscomb, "Monte Carlo Methods",
//    1964; M. Pharr, W. Jakob and G. Humphreys, "Physically Based Rendering", 3rd ed., 2016,
//    section 7.4.1).
//  - GGX importance sampling of the half vector: the inverse of the cumulative distribution of
//    D(h) (n.h) (B. Walter, S. Marschner, H. Li and K. Torrance, "Microfacet Models for
//    Refraction through Rough Surfaces", EGSR 2007, eqs. 33, 35 and 36), as in B. Karis, "Real
//    Shading in Unreal Engine 4", SIGGRAPH 2013, ImportanceSampleGGX.
//  - GGX importance sampling of the normals visible from a direction: E. Heitz, "Sampling the
//    GGX Distribution of Visible Normals", JCGT 7(4), 2018 (the reference renderer's specular
//    lobe, whose weight G2 / G1 stays near 1 at every roughness).
//  - Cosine-weighted hemisphere directions: Malley's method (Pharr, Jakob and Humphreys 2016,
//    section 13.6.3) on P. Shirley and K. Chiu's concentric map, "A Low Distortion Map Between
//    Disk and Square", 1997.
// Each function is the exact sequence of floating-point operations its callers' results (the
// stored cubes and tables, the frames) were measured with: changing one changes those bytes.
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace oer::sampling {

// The radical inverse of i in base 2: i's binary digits mirrored about the point, in [0, 1)
// (0, 1/2, 1/4, 3/4, 1/8, ... for i = 0, 1, 2, 3, 4, ...). Its first 2^m values are the
// multiples of 2^-m in some order, so every prefix of the sequence is spread evenly.
double radical_inverse(std::uint32_t i);

// Point i of the Hammersley set of `count` points in the unit square: (i / count,
// radical_inverse(i)).
glm::dvec2 hammersley(std::uint32_t i, std::uint32_t count);

// A half vector drawn about n = +z with density D(h) (n.h) over the solid angle, D the GGX
// distribution of alpha^2 = alpha2.
struct GgxHalfVector {
    glm::dvec3 direction;  // unit; direction.z = n.h = sqrt(cos2_theta)
    double cos2_theta;     // (n.h)^2, as D(h) takes it
};

// u in [0, 1) picks the polar angle, cos^2 theta = (1 - u) / (1 + (alpha^2 - 1) u), and phi is
// the azimuth in radians. alpha2 in (0, 1].
GgxHalfVector ggx_half_vector(double alpha2, double u, double phi);

// GGX's D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2) (Walter et al. 2007, eq. 33), per
// unit solid angle of h, at (n.h)^2 = cos2_theta.
double ggx_distribution(double alpha2, double cos2_theta);

// A unit half vector h about +z with density D_v(h) = G1(v) max(0, v.h) D(h) / v.z over the
// solid angle (Heitz 2018's listing), for v (unit, v.z > 0) in the same frame, GGX of alpha,
// (u1, u2) uniform in [0, 1)^2.
glm::dvec3 ggx_visible_normal(const glm::dvec3& v, double alpha, double u1, double u2);

// The tangents (t, s) that make (t, s, n) a right-handed orthonormal frame about the unit n
// (T. Duff, J. Burgess, P. Christensen, C. Hery, A. Kensler, M. Liani and R. Villemin,
// "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017).
struct TangentFrame {
    glm::dvec3 t, s;
};
TangentFrame tangent_frame(const glm::dvec3& n);

// A direction about the unit normal n with density cos / pi for (u1, u2) uniform in [0, 1)^2:
// a uniform point on the disc by the concentric map, lifted onto the hemisphere (Malley's
// method). The concentric map keeps the square's strata compact on the disc, so stratified
// (u1, u2) give stratified directions. The frame about n is tangent_frame's.
glm::dvec3 cosine_direction(const glm::dvec3& n, double u1, double u2);

}  // namespace oer::sampling
