// The split sum's DFG table against what it must be: a mirror reflects all light, a rough
// metal loses energy to the single-scattering BRDF, and every entry agrees with the same
// integral done another way (a fine midpoint quadrature over the hemisphere of light
// directions, no importance sampling).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "directions.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/split_sum.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

// (A, B) by a midpoint rule in (theta, phi) of the light direction over the hemisphere, each
// cell weighted by its exact solid angle: the glTF BRDF written out (Appendix B: GGX D,
// height-correlated Smith V, Schlick's split), n = +z, v in the xz plane.
glm::dvec2 hemisphere_integral(double n_dot_v, double roughness, int rows, int columns) {
    const double alpha = roughness * roughness, a2 = alpha * alpha;
    const glm::dvec3 v(std::sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    return oer::testing::hemisphere_integral<glm::dvec2>(rows, columns, [&](const glm::dvec3& l) {
        const glm::dvec3 h = glm::normalize(l + v);
        const double n_dot_l = l.z, n_dot_h = h.z, v_dot_h = glm::dot(v, h);
        const double d_denominator = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
        const double d = a2 / (pi * d_denominator * d_denominator);
        const double visibility = 0.5 / (n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2) +
                                         n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2));
        const double fresnel = std::pow(1.0 - v_dot_h, 5.0);
        const double f = d * visibility * n_dot_l;
        return glm::dvec2((1.0 - fresnel) * f, fresnel * f);
    });
}

}  // namespace

TEST(SplitSum, AMirrorSeenHeadOnReflectsAllItsLight) {
    const DfgTable table = dfg_table(32, 1024);
    const glm::dvec2 ab = sample_dfg(table, 1.0, 0.0);
    std::printf("[ measured ] A + B at roughness 0, n.v 1: %.4f (A %.4f, B %.4f)\n", ab.x + ab.y,
                ab.x, ab.y);
    EXPECT_NEAR(ab.x + ab.y, 1.0, 0.02);
    // Head on, Schlick's term is nearly all F0's: B is small.
    EXPECT_LT(ab.y, 0.01);
}

TEST(SplitSum, ARoughMetalLosesEnergyAsRoughnessGrows) {
    const DfgTable table = dfg_table(32, 1024);
    double previous = 2.0;
    for (int step = 0; step <= 8; ++step) {
        const double roughness = step / 8.0;
        const glm::dvec2 ab = sample_dfg(table, 0.5, roughness);
        std::printf("[ measured ] n.v 0.5, roughness %.3f: A + B %.4f\n", roughness, ab.x + ab.y);
        if (step >= 2) {
            EXPECT_LT(ab.x + ab.y, previous) << "roughness " << roughness;
        }
        previous = ab.x + ab.y;
    }
    // At roughness 1 about half the light is lost to single scattering: what the shader's
    // multiple-scattering term adds back.
    EXPECT_LT(previous, 0.85);
    EXPECT_GT(previous, 0.4);
}

TEST(SplitSum, EntriesAgreeWithABruteForceHemisphereIntegral) {
    const int size = 32;
    const DfgTable table = dfg_table(size, 1024);
    // Texel centres, where the table holds its entries unblended.
    for (const auto& [i, j] : {std::pair{8, 16}, {24, 24}, {16, 12}, {31, 31}, {4, 28}}) {
        const double n_dot_v = (i + 0.5) / size, roughness = (j + 0.5) / size;
        const glm::dvec2 got = sample_dfg(table, n_dot_v, roughness);
        EXPECT_EQ(got, glm::dvec2(table.scale_bias[std::size_t(j * size + i)]));
        const glm::dvec2 want = hemisphere_integral(n_dot_v, roughness, 2048, 1024);
        const double total = want.x + want.y;
        std::printf("[ measured ] n.v %.3f roughness %.3f: A %.4f / %.4f, B %.4f / %.4f\n", n_dot_v,
                    roughness, got.x, want.x, got.y, want.y);
        EXPECT_NEAR(got.x, want.x, 0.01 * total) << n_dot_v << ", " << roughness;
        EXPECT_NEAR(got.y, want.y, 0.01 * total) << n_dot_v << ", " << roughness;
    }
}

TEST(SplitSum, BadSizesAndSampleCountsAreErrors) {
    for (const auto& [size, samples] :
         {std::pair{1, 16}, {257, 16}, {0, 16}, {8, 0}, {8, 65537}, {-4, 16}}) {
        try {
            dfg_table(size, samples);
            ADD_FAILURE() << size << " x " << samples << " was accepted";
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
            const std::string what = error.what();
            EXPECT_NE(what.find(size < 2 || size > 256 ? "size" : "samples"), std::string::npos)
                << what;
        }
    }
    EXPECT_EQ(dfg_table(2, 1).scale_bias.size(), 4u);
}
