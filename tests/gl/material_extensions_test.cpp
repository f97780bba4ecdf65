// The glTF material extensions' layers in the GL renderer (mesh.hpp's Material layers,
// docs/materials.md), against numbers known without it: under a constant map of radiance L every
// lobe reflects L times its directional albedo (a furnace), so each layer's energy is checked
// against the formula or table it stands for, per pixel, with the tolerances stated; an unlit
// material sends exactly its base colour; a coat's reflection of a light goes with the light.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>

#include <glm/geometric.hpp>

#include "frame_test_support.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/sheen_albedo.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/lighting/split_sum.hpp"
#include "prefiltered_cubes.hpp"
#include "synthetic_maps.hpp"
#include "test_meshes.hpp"

using namespace oer;
using oer::testing::front_camera;
using oer::testing::linear_request;
using oer::testing::linear_rgb;
using oer::testing::make_rig;
using oer::testing::sphere_normal;
using oer::testing::sphere_of;

namespace {

constexpr int kFurnaceSize = 96;
const glm::vec3 kRadiance{0.5f, 1.0f, 2.0f};

class MaterialExtensionsTest : public oer::testing::RendererSuite {
  protected:
    // The unit sphere in `material` under the constant map kRadiance, seen from the front.
    static Frame furnace(const Material& material) {
        static const auto rig = make_rig(oer::testing::constant_map(256, 128, kRadiance), 0, 3);
        FrameRequest request = linear_request(rig, front_camera(), kFurnaceSize);
        request.objects.push_back({sphere_of(material), glm::mat4(1.0f), std::nullopt});
        request.specular = oer::testing::specular_of(oer::testing::constant_cube(kRadiance));
        return render(request);
    }
};

// A black dielectric whose own specular lobe is off (KHR_materials_specular's factor 0: f0 and
// F90 0), so that a furnace shows the layer over it alone.
Material black_without_specular() {
    Material material = oer::testing::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.5f);
    material.specular.factor = 0.0f;
    return material;
}

struct Deviation {
    // The largest relative difference of any channel where n.v is at least 0.3: nearer the rim
    // the 256 x 128 sphere's interpolated normals depart from the exact ones this compares with,
    // where the lobes change fastest.
    double worst = 0.0;
    double mean = 0.0;  // the mean of the green channel's ratio got / expected
    int pixels = 0;
};

// Every sphere pixel against expected(n.v) times kRadiance: the mean ratio over all, the worst
// where n.v >= 0.5. Nearer the silhouette the normal turns fast across a pixel, and geometric
// specular antialiasing (material.glsl) widens the lobe there beyond the material's roughness
// that `expected` is computed at (at n.v = 0.5 on this sphere, 0.3 reads as 0.32).
Deviation compare(const Frame& frame, const std::function<glm::dvec3(double)>& expected) {
    const Camera camera = front_camera();
    Deviation d;
    double ratio_sum = 0.0;
    for (int y = 0; y < kFurnaceSize; ++y) {
        for (int x = 0; x < kFurnaceSize; ++x) {
            const auto n = sphere_normal(camera, kFurnaceSize, x, y);
            if (!n) {
                continue;
            }
            const double n_dot_v = glm::dot(*n, glm::normalize(glm::dvec3(camera.eye) - *n));
            const glm::dvec3 want = expected(n_dot_v) * glm::dvec3(kRadiance);
            const glm::dvec3 got = linear_rgb(frame, x, y);
            for (int c = 0; c < 3 && n_dot_v >= 0.5; ++c) {
                d.worst = std::max(d.worst, std::abs(got[c] - want[c]) / std::max(want[c], 1e-3));
            }
            ratio_sum += got.g / std::max(want.g, 1e-9);
            ++d.pixels;
        }
    }
    d.mean = ratio_sum / std::max(1, d.pixels);
    return d;
}

}  // namespace

// KHR_materials_unlit: the base colour is the radiance sent, whatever the light, to the float's
// last bits (the G-buffer and the shaded target are float in a linear frame).
TEST_F(MaterialExtensionsTest, UnlitSendsExactlyItsBaseColour) {
    Material material = oer::testing::metallic_roughness(glm::vec3(0.2f, 0.4f, 0.6f), 0.0f, 0.5f);
    material.model = ShadingModel::Unlit;
    material.emissive = glm::vec3(1.0f);  // ignored, as the extension says
    const Deviation d = compare(furnace(material), [](double) {
        return glm::dvec3(0.2, 0.4, 0.6) / glm::dvec3(kRadiance);
    });
    std::printf("[ measured ] unlit: worst relative difference %.2e over %d pixels\n", d.worst,
                d.pixels);
    ASSERT_GT(d.pixels, 2000);
    EXPECT_LT(d.worst, 1e-6);
}

// KHR_materials_ior and KHR_materials_specular set the dielectric's f0 = min(f0(ior) color, 1)
// factor and F90 = factor: over a black base the furnace shows the split sum's f0 A + F90 B
// plus its multiple scattering (brdf.glsl), from the CPU's DFG table; 2 % covers the table's
// bilinear lookup on the GPU and the cube's half floats.
TEST_F(MaterialExtensionsTest, IorAndSpecularSetTheDielectricsReflectance) {
    const DfgTable table = dfg_table(32, 1024);
    struct Case {
        float ior;
        float factor;
        glm::vec3 color;
    };
    for (const Case& c :
         {Case{2.0f, 1.0f, glm::vec3(1.0f)}, Case{1.2f, 1.0f, glm::vec3(1.0f)},
          Case{0.0f, 1.0f, glm::vec3(1.0f)}, Case{1.5f, 0.5f, glm::vec3(4.0f, 1.0f, 0.25f)}}) {
        Material material = oer::testing::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.3f);
        material.ior = c.ior;
        material.specular.factor = c.factor;
        material.specular.color = c.color;
        ASSERT_TRUE(material.layered());
        const double r = (c.ior - 1.0) / (c.ior + 1.0);
        const glm::dvec3 f0 =
            glm::min(r * r * glm::dvec3(c.color), glm::dvec3(1.0)) * double(c.factor);
        const double f90 = c.factor;
        const Deviation d = compare(furnace(material), [&](double n_dot_v) {
            const glm::dvec2 ab = sample_dfg(table, n_dot_v, 0.3);
            const glm::dvec3 single = f0 * ab.x + f90 * ab.y;
            const double e_ms = 1.0 - (ab.x + ab.y);
            const glm::dvec3 f_avg = f0 + (f90 - f0) / 21.0;
            return single + single * f_avg / (1.0 - e_ms * f_avg) * e_ms;
        });
        std::printf(
            "[ measured ] ior %.2f, specular %.2f x (%.2f, %.2f, %.2f): mean got / expected %.4f, "
            "worst pixel %.4f off\n",
            c.ior, c.factor, c.color.r, c.color.g, c.color.b, d.mean, d.worst);
        EXPECT_NEAR(d.mean, 1.0, 0.02) << "ior " << c.ior;
        EXPECT_LT(d.worst, 0.05) << "ior " << c.ior;
    }
}

// KHR_materials_sheen over a black base without specular: the furnace shows sheen E_sheen(n.v)
// L, E_sheen from the CPU's table (sheen_albedo.hpp, checked against a brute-force quadrature by
// tests/lighting/sheen_albedo_test.cpp); 2 % on the mean and 5 % on any pixel cover the GPU's
// bilinear lookup and half floats.
// White sheen over a white diffuse base keeps the furnace's energy: (1 - E) L + E L = L.
TEST_F(MaterialExtensionsTest, SheenReflectsItsDirectionalAlbedo) {
    const SheenAlbedoTable table = sheen_albedo_table(32, 1024);
    const glm::dvec3 color(0.9, 0.6, 0.3);
    // From 0.3: below it the table's rows steepen (E_sheen(0.25) falls from 0.37 at 0.5 to 0.07
    // at 0.1), and the GPU's 8-bit bilinear weights, not the shading, set the error.
    for (const float roughness : {0.3f, 0.5f, 1.0f}) {
        Material material = black_without_specular();
        material.sheen.color = glm::vec3(color);
        material.sheen.roughness = roughness;
        const Deviation d = compare(furnace(material), [&](double n_dot_v) {
            return color * sample_sheen_albedo(table, n_dot_v, roughness);
        });
        Material white = oer::testing::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.5f);
        white.specular.factor = 0.0f;
        white.sheen.color = glm::vec3(1.0f);
        white.sheen.roughness = roughness;
        const Deviation kept = compare(furnace(white), [](double) { return glm::dvec3(1.0); });
        std::printf(
            "[ measured ] sheen roughness %.1f over black: E_sheen(1) %.4f, E_sheen(0.25) %.4f; "
            "mean got / expected %.4f, worst pixel %.4f off; white over white: worst %.2e off\n",
            roughness, sample_sheen_albedo(table, 1.0, roughness),
            sample_sheen_albedo(table, 0.25, roughness), d.mean, d.worst, kept.worst);
        EXPECT_NEAR(d.mean, 1.0, 0.02) << roughness;
        EXPECT_LT(d.worst, 0.05) << roughness;
        EXPECT_LT(kept.worst, 1e-3) << roughness;
    }
}

// KHR_materials_clearcoat over a black base without specular: the furnace shows the coat's
// directional albedo, clearcoat (0.04 A + B)(n.v, coat roughness), from the CPU's DFG table
// (2 %, as above). A white coat over a white metal keeps the furnace's energy (the base
// attenuated by 1 - clearcoat E_c, brdf.glsl's clearcoat_albedo): never above L by more than
// the 3 % of the white furnace of material_shading_test.cpp.
TEST_F(MaterialExtensionsTest, ClearcoatReflectsItsAlbedoAndKeepsAWhiteFurnace) {
    const DfgTable table = dfg_table(32, 1024);
    for (const float roughness : {0.0f, 0.3f, 0.7f, 1.0f}) {
        Material material = black_without_specular();
        material.clearcoat.factor = 0.8f;
        material.clearcoat.roughness = roughness;
        const Deviation d = compare(furnace(material), [&](double n_dot_v) {
            const glm::dvec2 ab = sample_dfg(table, n_dot_v, roughness);
            return glm::dvec3(0.8 * (0.04 * ab.x + ab.y));
        });
        Material white = oer::testing::metallic_roughness(glm::vec3(1.0f), 1.0f, 0.4f);
        white.clearcoat.factor = 1.0f;
        white.clearcoat.roughness = roughness;
        const Deviation kept = compare(furnace(white), [](double) { return glm::dvec3(1.0); });
        std::printf(
            "[ measured ] clearcoat 0.8, roughness %.1f, over black: mean got / expected %.4f, "
            "worst pixel %.4f off; white coat over white metal: mean / L %.4f, worst %.4f off\n",
            roughness, d.mean, d.worst, kept.mean, kept.worst);
        EXPECT_NEAR(d.mean, 1.0, 0.02) << roughness;
        EXPECT_LT(d.worst, 0.06) << roughness;
        EXPECT_LE(kept.mean, 1.0 + 0.03) << roughness;
        EXPECT_NEAR(kept.mean, 1.0, 0.03) << roughness;
    }
}

// KHR_materials_transmission without specular (factor 0): all of the diffuse lobe is
// transmitted, the constant map behind the thin wall tinted by the base colour, base L exactly;
// KHR_materials_volume multiplies it by attenuationColor^(thickness / attenuationDistance).
TEST_F(MaterialExtensionsTest, TransmissionSendsTheEnvironmentTimesItsShare) {
    const glm::dvec3 base(0.5, 0.7, 0.9);
    Material material = oer::testing::metallic_roughness(glm::vec3(base), 0.0f, 0.2f);
    material.specular.factor = 0.0f;
    material.transmission.factor = 1.0f;
    const Deviation thin = compare(furnace(material), [&](double) { return base; });
    material.volume.thickness = 1.0f;
    material.volume.attenuation_distance = 2.0f;
    material.volume.attenuation_color = glm::vec3(0.25f, 0.5f, 1.0f);
    const glm::dvec3 through = base * glm::pow(glm::dvec3(0.25, 0.5, 1.0), glm::dvec3(0.5));
    const Deviation thick = compare(furnace(material), [&](double) { return through; });
    // Half transmitted, half diffuse: the same radiance in a furnace.
    material.volume = VolumeLayer{};
    material.transmission.factor = 0.5f;
    const Deviation half = compare(furnace(material), [&](double) { return base; });
    std::printf(
        "[ measured ] transmission: thin wall worst pixel %.2e off, through the volume %.2e, "
        "half transmitted %.2e\n",
        thin.worst, thick.worst, half.worst);
    EXPECT_LT(thin.worst, 2e-3);
    EXPECT_LT(thick.worst, 2e-3);
    EXPECT_LT(half.worst, 2e-3);
}

// A mirror coat over a black base reflects a small light, and loses it with the light's weight
// and in the light's shadow: the coat's lobe is weighted w_k v_k as the base's specular lobe is.
TEST_F(MaterialExtensionsTest, TheCoatsReflectionOfALightGoesWithTheLight) {
    const glm::dvec3 direction = glm::normalize(glm::dvec3(0.35, 0.6, 1.0));
    const HdrImage map =
        oer::testing::disc_map(1024, 512, glm::vec3(0.05f), {{direction, 0.1, glm::vec3(100.0f)}});
    const auto rig = make_rig(map, 1, 3);
    ASSERT_EQ(rig->lights.size(), 1u);
    Material material = black_without_specular();
    material.clearcoat.factor = 1.0f;
    FrameRequest request = linear_request(rig, front_camera(), 128);
    request.objects.push_back({sphere_of(material), glm::mat4(1.0f), std::nullopt});
    request.specular = std::make_shared<const SpecularEnvironment>(prefilter_specular(map, *rig));
    request.shadows.enabled = false;
    const auto peak = [](const Frame& frame) {
        double best = 0.0;
        for (int i = 0; i < frame.width * frame.height; ++i) {
            best = std::max(best, double(frame.linear[std::size_t(i) * 4 + 1]));
        }
        return best;
    };
    const double lit = peak(render(request));
    request.lights = {0.5f};
    const double dimmed = peak(render(request));
    request.lights = {0.0f};
    const double off = peak(render(request));
    // A box over the highlight, across its rays towards the light (the highlight lies about the
    // half vector of the view and the light), out of the camera's view of it.
    request.lights = {};
    const glm::dvec3 highlight = glm::normalize(direction + glm::dvec3(0.0, 0.0, 1.0));
    const glm::dvec3 blocker = highlight + 1.5 * direction;
    request.objects.push_back(
        {oer::testing::shared(oer::testing::box(glm::vec3(blocker - 0.35),
                                                glm::vec3(blocker + 0.35), glm::vec3(0.5f))),
         glm::mat4(1.0f), std::nullopt});
    request.shadows.enabled = true;
    request.shadows.resolution = 2048;
    const double shadowed = peak(render(request));
    std::printf(
        "[ measured ] coat's highlight: %.3f lit, %.3f at weight 0.5, %.4f off, %.4f in the "
        "box's shadow\n",
        lit, dimmed, off, shadowed);
    EXPECT_LT(shadowed, 0.05 * lit);
    // At normal incidence the coat reflects 4 % of the light's radiance of 100.
    EXPECT_GT(lit, 2.0);
    EXPECT_NEAR(dimmed / lit, 0.5, 0.05);
    EXPECT_LT(off, 0.05 * lit);
}

// The shading pass reads a layered material's layers from the G-buffer, packed
// (layer_gbuffer.glsl: half floats, the coat's normal octahedral, the coat's and transmission's
// weights in 8 bits); the transparent pass reads them from the material, unpacked. With every
// layer on, under a map with a light, the same sphere drawn OPAQUE and as BLEND at alpha 1
// (blended "over" the background by its alpha 1: its own radiance) agrees per pixel within the
// packing's error: 2e-3 of the pixel's radiance, or 2e-3 of the frame's brightest.
TEST_F(MaterialExtensionsTest, TheGBuffersPackedLayersShadeAsTheMaterialsOwn) {
    const glm::dvec3 direction = glm::normalize(glm::dvec3(-0.4, 0.5, 1.0));
    const HdrImage map = oer::testing::disc_map(512, 256, glm::vec3(0.2f, 0.3f, 0.5f),
                                                {{direction, 0.3, glm::vec3(20.0f)}});
    const auto rig = make_rig(map, 1, 3);
    Material material = oer::testing::metallic_roughness(glm::vec3(0.6f, 0.3f, 0.2f), 0.0f, 0.4f);
    material.ior = 1.4f;
    material.specular.factor = 0.8f;
    material.specular.color = glm::vec3(1.0f, 0.8f, 0.6f);
    material.clearcoat.factor = 0.8f;
    material.clearcoat.roughness = 0.2f;
    material.sheen.color = glm::vec3(0.3f, 0.5f, 0.7f);
    material.sheen.roughness = 0.6f;
    material.transmission.factor = 0.6f;
    material.volume.thickness = 0.5f;
    material.volume.attenuation_distance = 1.0f;
    material.volume.attenuation_color = glm::vec3(0.9f, 0.6f, 0.3f);
    ASSERT_TRUE(material.layered());
    const auto frame_of = [&](const Material& drawn) {
        FrameRequest request = linear_request(rig, front_camera(), kFurnaceSize);
        request.objects.push_back({sphere_of(drawn), glm::mat4(1.0f), std::nullopt});
        request.specular =
            std::make_shared<const SpecularEnvironment>(prefilter_specular(map, *rig));
        return render(request);
    };
    Material blended = material;
    blended.alpha_mode = AlphaMode::Blend;
    const Frame deferred = frame_of(material);
    const Frame forward = frame_of(blended);
    const Camera camera = front_camera();
    double brightest = 0.0;
    for (int y = 0; y < kFurnaceSize; ++y) {
        for (int x = 0; x < kFurnaceSize; ++x) {
            const glm::dvec3 rgb = linear_rgb(forward, x, y);
            brightest = std::max({brightest, rgb.r, rgb.g, rgb.b});
        }
    }
    double worst = 0.0;
    int pixels = 0;
    for (int y = 0; y < kFurnaceSize; ++y) {
        for (int x = 0; x < kFurnaceSize; ++x) {
            if (!sphere_normal(camera, kFurnaceSize, x, y)) {
                continue;
            }
            const glm::dvec3 got = linear_rgb(deferred, x, y);
            const glm::dvec3 want = linear_rgb(forward, x, y);
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst,
                                 std::abs(got[c] - want[c]) / std::max(want[c], 1e-3 * brightest));
            }
            ++pixels;
        }
    }
    std::printf(
        "[ measured ] every layer, packed against the material's own: worst %.2e of the pixel's "
        "radiance over %d pixels (brightest %.2f)\n",
        worst, pixels, brightest);
    ASSERT_GT(pixels, 2000);
    EXPECT_GT(brightest, 1.0);
    EXPECT_LT(worst, 2e-3);
}
