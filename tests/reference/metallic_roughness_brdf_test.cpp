// The reference renderer's BRDF (oer/reference/metallic_roughness_brdf.hpp) against what any
// BRDF of its kind must satisfy: a white furnace reflects everything at every angle and
// roughness (the multiple-scattering lobe gives back what single scattering loses), f is
// reciprocal, the estimator of its directional albedo from its own samples agrees with its
// tables (sample, pdf and evaluate describe the same function), and its density integrates to 1.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/lighting/sampling.hpp"
#include "oer/reference/metallic_roughness_brdf.hpp"
#include "oer/reference/pixel_random.hpp"

using namespace oer;
using reference::MetallicRoughnessBrdf;
using reference::SurfaceMaterial;

namespace {

const glm::dvec3 kNormal = glm::normalize(glm::dvec3(0.3, 1.0, -0.2));

// The unit direction at angle acos(n_dot_w) from kNormal, turned by `azimuth` about it.
glm::dvec3 direction_at(double n_dot_w, double azimuth) {
    const sampling::TangentFrame frame = sampling::tangent_frame(kNormal);
    const double s = std::sqrt(1.0 - n_dot_w * n_dot_w);
    return s * std::cos(azimuth) * frame.t + s * std::sin(azimuth) * frame.s + n_dot_w * kNormal;
}

SurfaceMaterial glossy(glm::dvec3 base, double metallic, double roughness) {
    return {base, metallic, roughness, true};
}

// The mean of the sampling estimator's weights f (n.l) / pdf over `count` stratified samples:
// an unbiased estimate of the directional albedo.
glm::dvec3 sampled_albedo(const MetallicRoughnessBrdf& brdf, int count) {
    reference::PixelRandom random(7, 11);
    glm::dvec3 sum(0.0);
    const int side = int(std::sqrt(double(count)));
    for (int i = 0; i < side; ++i) {
        for (int j = 0; j < side; ++j) {
            const double lobe = random.uniform();
            const auto sample =
                brdf.sample(lobe, (i + random.uniform()) / side, (j + random.uniform()) / side);
            if (sample) {
                sum += sample->weight;
            }
        }
    }
    return sum / double(side * side);
}

const std::vector<double> kRoughness = {0.0, 0.05, 0.3, 0.5, 0.75, 1.0};
const std::vector<double> kCosines = {0.1, 0.3, 0.6, 1.0};

}  // namespace

TEST(MetallicRoughnessBrdfFurnace, AWhiteMetalReflectsEverythingAtEveryAngleAndRoughness) {
    // Single scattering alone loses up to 60 % at roughness 1 and grazing angles (E1 ~ 0.4):
    // this fails without the multiple-scattering lobe, or with it scaled wrong.
    for (const double roughness : kRoughness) {
        for (const double cosine : kCosines) {
            const MetallicRoughnessBrdf brdf(glossy(glm::dvec3(1.0), 1.0, roughness), kNormal,
                                             direction_at(cosine, 0.7));
            const glm::dvec3 albedo = sampled_albedo(brdf, 40000);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(albedo[c], 1.0, 0.015)
                    << "roughness " << roughness << ", n.v " << cosine;
            }
            // The tables are single precision.
            EXPECT_NEAR(brdf.directional_albedo().g, 1.0, 1e-5);
        }
    }
}

TEST(MetallicRoughnessBrdfFurnace, AWhiteDielectricReflectsEverythingAtEveryAngleAndRoughness) {
    // The Lambertian lobe under the specular one takes exactly what it leaves: without the
    // coupling a white dielectric reflects up to 1 + F (10 % more at grazing angles).
    for (const double roughness : kRoughness) {
        for (const double cosine : kCosines) {
            const MetallicRoughnessBrdf brdf(glossy(glm::dvec3(1.0), 0.0, roughness), kNormal,
                                             direction_at(cosine, 2.0));
            const glm::dvec3 albedo = sampled_albedo(brdf, 40000);
            EXPECT_NEAR(albedo.g, 1.0, 0.015) << "roughness " << roughness << ", n.v " << cosine;
        }
    }
}

TEST(MetallicRoughnessBrdfSampling, TheSampledAlbedoOfColouredMaterialsMatchesTheTables) {
    // sample()'s weights average to directional_albedo() (which the tables give) only if
    // sample, pdf and evaluate agree: a wrong density or a lobe chosen with the wrong chance
    // moves the mean. Gold-like metal, red plastic, and a half-metallic mix.
    const std::vector<SurfaceMaterial> materials = {
        glossy({1.0, 0.78, 0.34}, 1.0, 0.3), glossy({0.8, 0.1, 0.08}, 0.0, 0.5),
        glossy({0.2, 0.6, 0.9}, 0.5, 0.15), glossy({0.9, 0.9, 0.9}, 0.0, 0.05)};
    for (const SurfaceMaterial& material : materials) {
        for (const double cosine : kCosines) {
            const MetallicRoughnessBrdf brdf(material, kNormal, direction_at(cosine, 4.0));
            const glm::dvec3 expected = brdf.directional_albedo();
            const glm::dvec3 albedo = sampled_albedo(brdf, 40000);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(albedo[c], expected[c], 0.02 * expected[c] + 2e-3)
                    << "roughness " << material.roughness << ", metallic " << material.metallic
                    << ", n.v " << cosine << ", channel " << c;
                EXPECT_LE(albedo[c], 1.0 + 0.015);
            }
        }
    }
}

TEST(MetallicRoughnessBrdfSampling, TheDensityAndTheDirectionsLostUnderTheHorizonMakeOne) {
    // Visible-normal sampling reflects some directions under the horizon (sample() gives
    // nullopt): pdf over the upper hemisphere integrates to 1 less that share, which a density
    // of the wrong normalisation (the half vector's Jacobian, G1, the lobe's chance) misses.
    // Uniform directions estimate the integral; rough lobes only (a sharp lobe's integral needs
    // its own sampling, which the albedo test checks).
    for (const double roughness : {0.4, 0.7, 1.0}) {
        const MetallicRoughnessBrdf brdf(glossy({0.8, 0.5, 0.3}, 0.5, roughness), kNormal,
                                         direction_at(0.3, 1.0));
        const int side = 400;
        double integral = 0.0;
        int lost = 0;
        reference::PixelRandom random(5, 9);
        for (int i = 0; i < side; ++i) {
            for (int j = 0; j < side; ++j) {
                // Uniform in solid angle: cos theta uniform in (0, 1].
                const double cosine = 1.0 - (i + 0.5) / side;
                integral +=
                    brdf.pdf(direction_at(cosine, 2.0 * std::numbers::pi * (j + 0.5) / side)) *
                    2.0 * std::numbers::pi / (side * side);
                lost += !brdf.sample(random.uniform(), random.uniform(), random.uniform());
            }
        }
        const double lost_share = double(lost) / (side * side);
        EXPECT_GT(lost_share, 0.005) << "roughness " << roughness;
        EXPECT_NEAR(integral + lost_share, 1.0, 0.01) << "roughness " << roughness;
    }
}

TEST(MetallicRoughnessBrdfReciprocity, SwappingTheViewAndTheLightChangesNothing) {
    // Helmholtz reciprocity, f(v, l) = f(l, v), which path tracing's estimators assume; the
    // rasteriser's diffuse weighting by (1 - E(n.v)) alone would fail it.
    reference::PixelRandom random(3, 5);
    for (int i = 0; i < 2000; ++i) {
        const SurfaceMaterial material =
            glossy({random.uniform(), random.uniform(), random.uniform()}, random.uniform(),
                   random.uniform());
        const glm::dvec3 v = direction_at(0.02 + 0.98 * random.uniform(), 6.3 * random.uniform());
        const glm::dvec3 l = direction_at(0.02 + 0.98 * random.uniform(), 6.3 * random.uniform());
        const glm::dvec3 forward = MetallicRoughnessBrdf(material, kNormal, v).evaluate(l);
        const glm::dvec3 backward = MetallicRoughnessBrdf(material, kNormal, l).evaluate(v);
        for (int c = 0; c < 3; ++c) {
            ASSERT_NEAR(forward[c], backward[c], 1e-9 * (1.0 + forward[c]))
                << "roughness " << material.roughness << ", metallic " << material.metallic;
        }
    }
}

TEST(MetallicRoughnessBrdfReciprocity, ALambertianMaterialIsItsAlbedoOverPi) {
    const MetallicRoughnessBrdf brdf({{0.2, 0.4, 0.6}, 0.0, 1.0, false}, kNormal,
                                     direction_at(0.5, 0.0));
    const glm::dvec3 f = brdf.evaluate(direction_at(0.3, 2.0));
    EXPECT_NEAR(f.b, 0.6 / std::numbers::pi, 1e-12);
    EXPECT_EQ(brdf.evaluate(-kNormal), glm::dvec3(0.0));
}
