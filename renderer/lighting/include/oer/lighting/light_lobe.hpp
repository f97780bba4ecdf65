#pragma once
// A light's own prefiltered radiance P(k) (specular_environment.hpp) in closed form: the
// light as spherical Gaussians (SG), its point core and its glow of light_profile
// (light_location.hpp), each convolved with the GGX lobe as an SG. After J. Wang, P. Ren,
// M. Gong, J. Snyder and B. Guo, "All-Frequency Rendering of Dynamic, Spatially-Varying
// Reflectance", SIGGRAPH Asia 2009:
//   a normalised SG  G(d; a, lambda) = lambda / (2 pi (1 - exp(-2 lambda))) exp(lambda (d.a - 1))
//   integrates to 1 over the sphere; GGX's D of alpha = roughness^2 about the half vector is
//   close to G with sharpness 2 / alpha^2, which about the reflected direction (n = v = r,
//   |dh / dl| = 1 / 4) becomes sharpness 1 / (2 alpha^2);
//   two normalised SGs of one axis convolve to a normalised SG of sharpness
//   lambda_1 lambda_2 / (lambda_1 + lambda_2) (the product of their Fourier-Legendre bands).
// Wang et al.'s GGX sharpness holds for small alpha only: the prefiltering's lobe about r is
// D(h) (n.l) over the hemisphere, normalised by Z(alpha) = integral of D(h) (n.l) dl, which
// falls from 4 (alpha -> 0) to 1 (alpha = 1), so its peak is 1 / (pi alpha^2 Z). Matching that
// peak, the GGX lobe's sharpness is lambda_D = 2 / (alpha^2 Z) (1 / (2 alpha^2) for small
// alpha, 2 at alpha = 1, where Wang's gives 0.5 and the light's reflection a peak 2.5 times too
// low, measured against the exact prefiltering in tests/lighting/light_lobe_test.cpp). In
// closed form (n = v, u = (n.h)^2, a = alpha):
//   Z = 4 a^2 / (a^2 - 1)^2 (2 ln(2 a^2 / (a^2 + 1)) + (1 - a^2) / a^2),
// used here and in the shader as the fit Z / 4 = 1 / (1 + 0.6247 a + 2.4241 a^2), within 1.3 %
// of it over a in (0, 1].
// A lobe's sharpness is chosen so that its peak radiance is the mean radiance of the disc it
// stands for (lambda = 1 / (1 - cos radius)): a mirror shows a light as bright as it is.
#include <glm/vec3.hpp>

#include "oer/lighting/light_location.hpp"

namespace oer {

struct SphericalGaussian {
    glm::dvec3 axis{0.0, 1.0, 0.0};  // unit
    double sharpness = 1.0;          // lambda > 0
    glm::dvec3 energy{0.0};          // integral over the sphere, RGB (radiance x steradians)
};

struct LightLobes {
    SphericalGaussian core;  // the core's share of the light's energy
    SphericalGaussian glow;  // the rest
};

// Light k's lobes from its profile (light_profile of its own SH, which the shadows use too):
// axis its direction, energies core_share and 1 - core_share of light.intensity, the glow's
// sharpness from the profile's glow radius, the core's from a disc of one map pixel at the
// equator (2 pi / map_width wide: the least a core can be seen as).
LightLobes light_lobes(const Light& light, const LightProfile& profile, int map_width);

// The sharpness of a normalised SG of sharpness `sharpness` convolved with the GGX lobe of
// perceptual roughness `roughness` (about r, lambda_D as above); roughness 0 leaves it
// unchanged.
double prefiltered_sharpness(double sharpness, double roughness);

// The lobe's prefiltered radiance towards r (unit) at perceptual roughness `roughness`.
glm::dvec3 prefiltered_lobe(const SphericalGaussian& lobe, const glm::dvec3& r, double roughness);

}  // namespace oer
