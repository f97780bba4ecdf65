#include "oer/lighting/compact_light.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "oer/lighting/microfacet.hpp"
#include "oer/lighting/sampling.hpp"

namespace oer {

glm::dvec3 point_light_ratio(const glm::dvec3& toward_light, double cap_tan2,
                             const GlossyPoint& point) {
    const double radius = 2.0 * std::atan(std::sqrt(cap_tan2));
    const double cos_to_r = std::clamp(glm::dot(toward_light, point.r), -1.0, 1.0);
    const glm::dvec3 across = point.r - cos_to_r * toward_light;
    const double across_length = glm::length(across);
    const double turn = std::min(std::acos(cos_to_r), radius);
    glm::dvec3 l = across_length > 1e-5
                       ? std::cos(turn) * toward_light + std::sin(turn) * (across / across_length)
                       : point.r;
    if (point.floor_below && l.y < 0.0) {
        l = glm::normalize(glm::dvec3(l.x, 1e-4, l.z));
    }
    const double n_dot_l = glm::dot(point.n, l);
    const double r_dot_l = glm::dot(point.r, l);
    const double a2 = point.alpha * point.alpha;
    glm::dvec3 brdf(0.0);
    if (n_dot_l > 0.0) {
        const glm::dvec3 h = glm::normalize(l + point.v);
        const double n_dot_h = glm::dot(point.n, h);
        const double v_dot_h = std::clamp(glm::dot(point.v, h), 0.0, 1.0);
        const glm::dvec3 fresnel = point.f0 + (point.f90 - point.f0) * std::pow(1.0 - v_dot_h, 5.0);
        brdf = fresnel * sampling::ggx_distribution(a2, n_dot_h * n_dot_h) *
               smith_visibility(point.n_dot_v, n_dot_l, point.alpha) * n_dot_l;
    }
    const double kernel = prefilter_kernel(point.alpha, r_dot_l);
    return glm::clamp(brdf / glm::max(point.single_scattering * kernel, glm::dvec3(1e-8)),
                      glm::dvec3(0.0), glm::dvec3(kCompactLightFactorMax));
}

glm::dvec3 specular_dominant_direction(const glm::dvec3& n, const glm::dvec3& r, double alpha) {
    const double smoothness = 1.0 - alpha;
    return glm::normalize(glm::mix(n, r, smoothness * (std::sqrt(smoothness) + alpha)));
}

glm::dvec3 compact_light_factor(const glm::dvec3& toward_light, const LightSpread& spread,
                                const GlossyPoint& point) {
    const double a2 = point.alpha * point.alpha;
    glm::dvec3 factor(1.0);
    const double core_outside = a2 / (a2 + spread.core_cap_tan2);
    if (core_outside > 1e-3) {
        factor += spread.core_share * core_outside *
                  (point_light_ratio(toward_light, spread.core_cap_tan2, point) - 1.0);
    }
    const double glow_outside = a2 / (a2 + spread.glow_cap_tan2);
    if (glow_outside > 1e-3) {
        factor += (1.0 - spread.core_share) * glow_outside *
                  (point_light_ratio(toward_light, spread.glow_cap_tan2, point) - 1.0);
    }
    return factor;
}

}  // namespace oer
