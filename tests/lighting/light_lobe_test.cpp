// A light's spherical-Gaussian lobes against sums over the sphere: a lobe carries its energy,
// keeps it when prefiltered, and a disc light's glow peaks at the disc's radiance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>

#include "oer/lighting/equirect.hpp"
#include "oer/lighting/light_lobe.hpp"
#include "oer/lighting/rig.hpp"
#include "synthetic_maps.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

// The lobe's prefiltered radiance summed over a 4096 x 2048 equirect grid, each pixel weighted
// by its exact solid angle.
glm::dvec3 integral_over_sphere(const SphericalGaussian& lobe, double roughness) {
    const equirect::Grid grid(4096, 2048);
    glm::dvec3 sum(0.0);
    for (int y = 0; y < grid.height; ++y) {
        glm::dvec3 row(0.0);
        for (int x = 0; x < grid.width; ++x) {
            row += prefiltered_lobe(lobe, grid.direction(x, y), roughness);
        }
        sum += row * grid.row_solid_angle[std::size_t(y)];
    }
    return sum;
}

SphericalGaussian lobe_of(double sharpness) {
    SphericalGaussian lobe;
    lobe.axis = glm::normalize(glm::dvec3(0.6, 0.3, -0.74));
    lobe.sharpness = sharpness;
    lobe.energy = {2.0, 1.0, 0.5};
    return lobe;
}

}  // namespace

TEST(LightLobe, ALobesIntegralIsItsEnergy) {
    for (const double sharpness : {0.5, 4.0, 60.0, 1000.0}) {
        const SphericalGaussian lobe = lobe_of(sharpness);
        const glm::dvec3 integral = integral_over_sphere(lobe, 0.0);
        std::printf("[ measured ] sharpness %g: integral / energy %.5f\n", sharpness,
                    integral.r / lobe.energy.r);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(integral[c], lobe.energy[c], 0.01 * lobe.energy[c]) << sharpness;
        }
    }
}

TEST(LightLobe, PrefilteringLeavesAMirrorUnchangedAndWidensWithRoughness) {
    for (const double sharpness : {2.0, 300.0, 2e5}) {
        EXPECT_EQ(prefiltered_sharpness(sharpness, 0.0), sharpness);
        double previous = sharpness;
        for (int step = 1; step <= 10; ++step) {
            const double widened = prefiltered_sharpness(sharpness, step / 10.0);
            EXPECT_LT(widened, previous) << sharpness << " at roughness " << step / 10.0;
            EXPECT_GT(widened, 0.0);
            previous = widened;
        }
        // At roughness 1 no lobe is sharper than GGX's own, 1 / (2 alpha^2) = 0.5.
        EXPECT_LE(previous, 0.5);
    }
}

TEST(LightLobe, APrefilteredLobeKeepsItsEnergy) {
    const SphericalGaussian lobe = lobe_of(2000.0);
    for (const double roughness : {0.1, 0.3, 0.6, 1.0}) {
        const glm::dvec3 integral = integral_over_sphere(lobe, roughness);
        std::printf("[ measured ] roughness %.1f (sharpness %.4g): integral / energy %.5f\n",
                    roughness, prefiltered_sharpness(lobe.sharpness, roughness),
                    integral.g / lobe.energy.g);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(integral[c], lobe.energy[c], 0.01 * lobe.energy[c]) << roughness;
        }
        // And it is spread: its peak falls with roughness as 1 / sharpness does.
        EXPECT_LT(prefiltered_lobe(lobe, lobe.axis, roughness).g,
                  prefiltered_lobe(lobe, lobe.axis, 0.0).g);
    }
}

TEST(LightLobe, AUniformDiscsGlowPeaksAtTheDiscsRadiance) {
    const glm::dvec3 centre = glm::normalize(glm::dvec3(0.4, 0.8, 0.3));
    const glm::vec3 radiance{300.0f, 200.0f, 100.0f};
    for (const double radius : {0.08, 0.15}) {
        const HdrImage map =
            oer::testing::disc_map(1024, 512, glm::vec3(0.0f), {{centre, radius, radiance}});
        RigOptions options;
        options.light_count = 1;
        options.sh_order = 3;
        const Rig rig = build_rig(map, {}, options);
        ASSERT_EQ(rig.lights.size(), 1u);
        const LightLobes lobes = light_lobes(rig.lights[0], rig.sh.per_light[0], rig.source_width);
        EXPECT_EQ(lobes.glow.axis, rig.lights[0].direction);
        EXPECT_EQ(lobes.core.axis, rig.lights[0].direction);
        const glm::dvec3 total = lobes.core.energy + lobes.glow.energy;
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(total[c], rig.lights[0].intensity[c], 1e-9 * rig.lights[0].intensity[c]);
        }
        const glm::dvec3 peak = prefiltered_lobe(lobes.glow, lobes.glow.axis, 0.0);
        std::printf(
            "[ measured ] disc of radius %.2f: core share %.4f, glow peak / radiance "
            "%.4f %.4f %.4f\n",
            radius, lobes.core.energy.g / rig.lights[0].intensity.g, peak.r / radiance.r,
            peak.g / radiance.g, peak.b / radiance.b);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(peak[c], radiance[c], 0.02 * radiance[c]) << radius;
        }
    }
}
