// A light's lobes as spherical Gaussians and their GGX prefiltering (light_lobe.hpp), after
// J. Wang, P. Ren, M. Gong, J. Snyder and B. Guo, "All-Frequency Rendering of Dynamic,
// Spatially-Varying Reflectance", SIGGRAPH Asia 2009 (section 4: the SG of a normalised lobe,
// the NDF as an SG and their convolution). renderer/gl/shaders/specular_lighting.glsl
// evaluates the same formulas per pixel.
#include "oer/lighting/light_lobe.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace oer {

namespace {

// The sharpness whose normalised SG peaks at the mean radiance of a disc of that angular
// radius: the SG's peak is lambda / (2 pi (1 - exp(-2 lambda))) times its energy, the disc's
// mean radiance its energy over 2 pi (1 - cos radius); they agree, up to 1 - exp(-2 lambda),
// for lambda = 1 / (1 - cos radius). 1 - cos r = 2 sin^2(r / 2), exact for small radii.
double disc_sharpness(double angular_radius) {
    const double half_sine = std::sin(0.5 * angular_radius);
    return 1.0 / (2.0 * half_sine * half_sine);
}

}  // namespace

LightLobes light_lobes(const Light& light, const LightProfile& profile, int map_width) {
    const double core_radius = std::numbers::pi / double(map_width);
    LightLobes lobes;
    lobes.core.axis = light.direction;
    lobes.core.sharpness = disc_sharpness(core_radius);
    lobes.core.energy = profile.core_share * light.intensity;
    lobes.glow.axis = light.direction;
    // A glow narrower than the core (a profile that is all core has radius 0) is drawn as wide
    // as the core: no lobe is sharper than a map pixel.
    lobes.glow.sharpness = disc_sharpness(std::max(profile.glow_angular_radius, core_radius));
    lobes.glow.energy = (1.0 - profile.core_share) * light.intensity;
    return lobes;
}

double prefiltered_sharpness(double sharpness, double roughness) {
    // GGX's lobe about r has sharpness lambda_D = 2 / (alpha^2 Z) = 1 / (2 alpha^2 (Z / 4))
    // (light_lobe.hpp, Z / 4 by its fit); the convolution's sharpness lambda lambda_D / (lambda +
    // lambda_D) written without lambda_D, which roughness 0 makes infinite.
    const double alpha = roughness * roughness;
    const double quarter_z = 1.0 / (1.0 + 0.6247 * alpha + 2.4241 * alpha * alpha);
    return sharpness / (1.0 + 2.0 * alpha * alpha * quarter_z * sharpness);
}

glm::dvec3 prefiltered_lobe(const SphericalGaussian& lobe, const glm::dvec3& r, double roughness) {
    const double lambda = prefiltered_sharpness(lobe.sharpness, roughness);
    // d.a - 1 = -|d - a|^2 / 2 for unit vectors, without the cancellation of 1 - d.a.
    const glm::dvec3 offset = r - lobe.axis;
    const double normalisation = lambda / (2.0 * std::numbers::pi * -std::expm1(-2.0 * lambda));
    return lobe.energy * (normalisation * std::exp(-0.5 * lambda * glm::dot(offset, offset)));
}

}  // namespace oer
