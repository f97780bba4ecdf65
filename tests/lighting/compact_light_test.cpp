// The compact-light factor (renderer/lighting/include/oer/lighting/compact_light.hpp): the
// prefiltering kernel's closed-form integral against quadrature, a point light's reflection
// turned into the BRDF's exactly, and a light wider than the lobe left to the split sum.

#include "oer/lighting/compact_light.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "oer/lighting/microfacet.hpp"
#include "oer/lighting/sampling.hpp"
#include "oer/lighting/split_sum.hpp"

using namespace oer;

namespace {

// Z(alpha) by the midpoint rule over c = r.l in [0, 1].
double closed_form_check_quadrature(double alpha) {
    const double a2 = alpha * alpha;
    constexpr int kSteps = 1 << 20;
    double sum = 0.0;
    for (int k = 0; k < kSteps; ++k) {
        const double c = (k + 0.5) / kSteps;
        sum += sampling::ggx_distribution(a2, 0.5 * (1.0 + c)) * c;
    }
    return 2.0 * std::numbers::pi * sum / kSteps;
}

glm::dvec3 unit(std::mt19937& random) {
    std::normal_distribution<double> normal;
    return glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
}

// A metal-like point (f0 0.9, 0.6, 0.3) with normal n, seen from v, at `roughness`; its split
// sum weight from the DFG table.
GlossyPoint glossy_point(const glm::dvec3& n, const glm::dvec3& v, double roughness,
                         const DfgTable& table) {
    GlossyPoint point;
    point.n = n;
    point.v = v;
    point.n_dot_v = std::clamp(glm::dot(n, v), 1e-4, 1.0);
    point.r = glm::reflect(-v, n);
    point.alpha = roughness * roughness;
    point.f0 = {0.9, 0.6, 0.3};
    point.f90 = 1.0;
    const glm::dvec2 dfg = sample_dfg(table, point.n_dot_v, roughness);
    point.single_scattering = point.f0 * dfg.x + point.f90 * dfg.y;
    return point;
}

}  // namespace

TEST(CompactLight, TheKernelsClosedFormIntegralIsTheQuadratures) {
    for (const double alpha : {0.005, 0.0121, 0.09, 0.25, 0.5, 0.9, 0.9997, 1.0}) {
        // The midpoint rule's own error at alpha 0.005, whose peak is 5e-5 wide in c: 3e-5.
        EXPECT_NEAR(prefilter_kernel_integral(alpha) / closed_form_check_quadrature(alpha), 1.0,
                    1e-4)
            << "alpha " << alpha;
    }
}

// A point light (a core of no extent holding all the energy): the split sum's reflection,
// single_scattering K(r, l) / Z, times the factor is the BRDF's F D V n.l at l, for random
// views, normals and lights within the lobe, roughness 0.3 to 1.
TEST(CompactLight, APointLightsSplitSumReflectionBecomesTheBrdfs) {
    const DfgTable table = dfg_table();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const LightSpread point_light{1.0, 1e-16, 1e-16};
    int checked = 0;
    double worst = 0.0;
    while (checked < 500) {
        const glm::dvec3 n = unit(random);
        const glm::dvec3 v = unit(random);
        if (glm::dot(n, v) < 0.1) {
            continue;
        }
        const double roughness = 0.3 + 0.7 * uniform(random);
        const GlossyPoint point = glossy_point(n, v, roughness, table);
        const glm::dvec3 l = glm::normalize(point.r + 0.5 * point.alpha * unit(random));
        const double n_dot_l = glm::dot(n, l), r_dot_l = glm::dot(point.r, l);
        if (n_dot_l <= 0.05 || r_dot_l <= 0.05) {
            continue;
        }
        const glm::dvec3 h = glm::normalize(l + v);
        const double a2 = point.alpha * point.alpha;
        const glm::dvec3 fresnel =
            point.f0 + (1.0 - point.f0) * std::pow(1.0 - glm::dot(v, h), 5.0);
        const glm::dvec3 brdf = fresnel *
                                sampling::ggx_distribution(a2, std::pow(glm::dot(n, h), 2.0)) *
                                smith_visibility(point.n_dot_v, n_dot_l, point.alpha) * n_dot_l;
        const glm::dvec3 split = point.single_scattering *
                                 sampling::ggx_distribution(a2, 0.5 * (1.0 + r_dot_l)) * r_dot_l /
                                 prefilter_kernel_integral(point.alpha);
        if (glm::any(glm::greaterThan(brdf, kCompactLightFactorMax * split))) {
            continue;  // clamped: not this check's case
        }
        const glm::dvec3 turned = split * compact_light_factor(l, point_light, point);
        for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, std::abs(turned[c] / brdf[c] - 1.0));
            ASSERT_NEAR(turned[c] / brdf[c], 1.0, 1e-5) << "channel " << c;
        }
        ++checked;
    }
    std::printf("[ measured ] a point light's reflection against the BRDF's: worst %.2e off\n",
                worst);
}

// A light wider than the lobe keeps the split sum: of a disc of 20 degrees under a lobe of
// roughness 0.1 (alpha 0.01) the lobe's share outside is 0.32 %, so that its split-sum
// reflection moves by at most that share times the bounded ratio, 2.3 %, whatever the view.
TEST(CompactLight, ALightWiderThanTheLobeKeepsTheSplitSum) {
    const DfgTable table = dfg_table();
    std::mt19937 random(11);
    const LightSpread disc = disc_spread(20.0 * std::numbers::pi / 180.0);
    for (int k = 0; k < 200; ++k) {
        const glm::dvec3 n = unit(random);
        const glm::dvec3 v = unit(random);
        if (glm::dot(n, v) < 0.1) {
            continue;
        }
        const GlossyPoint point = glossy_point(n, v, 0.1, table);
        const glm::dvec3 factor = compact_light_factor(point.r, disc, point);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(factor[c], 1.0, 0.0032 * (kCompactLightFactorMax - 1.0) + 1e-4);
        }
    }
}

// The dominant direction is r for a mirror, n at alpha 1, and between them turns from r towards
// n as alpha grows (Lagarde and de Rousiers 2014's lerp factor falls monotonically), in the
// plane of n and r, of unit length.
TEST(CompactLight, TheDominantDirectionLeansFromTheMirrorToTheNormal) {
    const glm::dvec3 n(0.0, 1.0, 0.0);
    const glm::dvec3 r = glm::normalize(glm::dvec3(1.0, 0.2, 0.0));
    EXPECT_LT(glm::length(specular_dominant_direction(n, r, 0.0) - r), 1e-12);
    EXPECT_LT(glm::length(specular_dominant_direction(n, r, 1.0) - n), 1e-12);
    double previous = glm::dot(r, n);
    for (const double alpha : {0.05, 0.1, 0.25, 0.5, 0.75, 0.95}) {
        const glm::dvec3 d = specular_dominant_direction(n, r, alpha);
        EXPECT_NEAR(glm::length(d), 1.0, 1e-12) << alpha;
        EXPECT_NEAR(d.z, 0.0, 1e-12) << alpha;
        EXPECT_GT(glm::dot(d, n), previous) << alpha;
        previous = glm::dot(d, n);
    }
}
