#pragma once
// Specular image-based lighting of a rig: the split-sum approximation of B. Karis,
// "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes (RTR4 section 10.5.2), made
// switchable per light as OER makes the diffuse (docs/design.md section 2). Prefiltered radiance is
// linear in the map, so for light weights w_k and visibilities v_k
//   P(S) = P(residual) + sum_k w_k v_k P(k),
// where the residual is the map with every light's pixels removed (set to 0) and P(k) the
// prefiltered radiance of light k's pixels alone. Each is a prefiltered cube map (below): the
// residual's at face_size, each light's at light_face_size, one layer of a cube-map array per
// light (SpecularEnvironment). A light's own cube keeps its shape in a reflection at every
// roughness: a studio's rectangular soft box reflects as a rectangle in chrome. The closed-form
// lobes this replaced (spherical Gaussians, one core and one glow per light) made every light
// round; against the exact prefiltering of a light's pixels their error at roughness 0 to 0.1
// was 0.70 to 1.22 relative RMS, the light's cube's 0.01 to 0.07 (docs/glossy-reference.md).
//
// The cube map: face order and orientation of the OpenGL cube-map table (as
// environment_layouts.hpp), level i of face size face_size >> i holding the radiance
// prefiltered with the GGX lobe of perceptual roughness roughness_of_level(i), with n = v = r
// (Karis's assumption), weighted by n.l:
//   P(r, alpha) = sum_l L(l) D(h) (n.l) / sum_l D(h) (n.l),   alpha = roughness^2,
// integrated by GGX importance sampling with filtered importance sampling (J. Krivanek and
// M. Colbert, "Real-time Shading with Filtered Importance Sampling", EGSR 2008): each sample
// reads the mip level of the unfiltered cube whose texel matches the sample's solid angle.
// Level 0 (roughness 0) is the map itself, area-averaged over each texel.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "oer/core/image.hpp"
#include "oer/lighting/light_location.hpp"
#include "oer/lighting/rig.hpp"

namespace oer {

struct SpecularOptions {
    int face_size = 256;  // level 0, a power of two in [4, 2048]
    int levels = 6;       // in [2, log2(face_size) + 1]; level levels - 1 is roughness 1
    int samples = 64;     // GGX samples per texel of levels 1 and above, in [1, 4096]
    // Level 0 of each light's cube: a power of two in [2^(levels - 1), face_size]. A light
    // is bright against its surroundings, so a texel of 0.7 degrees (128) keeps a soft box's
    // edges in a mirror while its cube costs a quarter of the residual's.
    int light_face_size = 128;
};

// One prefiltered cube map, or an array of `layers` cubes of the same sizes (a light's each).
struct PrefilteredCube {
    int face_size = 0;
    int levels = 0;
    int layers = 1;
    // Per level: layers x 6 faces (layer-major, each layer's faces in the order above) of
    // (face_size >> level)^2 texels, rows from t = 0, interleaved RGB as IEEE half floats
    // (GL_RGB16F, GL_HALF_FLOAT): linear radiance, as the map's.
    std::vector<std::vector<std::uint16_t>> rgb_half;

    // Bytes of the texels (what the cube costs in memory and on the renderer).
    std::size_t byte_size() const;
};

// What a glossy frame reads: P(residual), and P(k) for every light k of the rig as layer k of
// `lights` (none: a cube of 0 layers), both of the same levels, so that one lod
// (lod_of_roughness) reads both. An opaque floor hides what lies below the horizon, the map's
// y < 0, from every reflection: of a light that straddles the horizon (Blender's courtyard's
// brightest, a third of it below) a frame on such a floor reads P(k above), its pixels above
// the horizon alone, from a layer after the rig's lights; floor_layers[k] names it, k itself
// for a light wholly above, -1 for one wholly below (nothing to reflect).
struct SpecularEnvironment {
    PrefilteredCube residual;
    PrefilteredCube lights;
    std::vector<int> floor_layers;  // one per rig light

    std::size_t byte_size() const;
};

// The perceptual roughness r that level `level` of a cube of `levels` levels is prefiltered
// for, and the fractional level a roughness reads: lod = (levels - 1) r (2 - r), inverted
// r = 1 - sqrt(1 - level / (levels - 1)) (Filament's perceptualRoughnessToLod, a fit of
// log2 of the lobe's width). The default six levels hold roughness 0, 0.11, 0.23, 0.37, 0.55
// and 1: denser where a reflection changes fastest. Five levels at i / 4 left a mirror at
// roughness 0.1 a blend of a sharp image and one at 0.25, 21 % under its light's radiance.
// The residual's cube is read at this lod; the shader's specular_lod is lod_of_roughness.
double roughness_of_level(int level, int levels);
double lod_of_roughness(double roughness, int levels);

// How a light's energy spreads about its direction, as its reflection needs it: the share
// `core_share` in a core of angular radius at most kLightCoreAngularRadius, the rest in a glow
// disc (light_profile's fit, light_location.hpp), each as T = tan^2(radius / 2). A light's
// angular_radius is the cap of all its pixels' solid angle: Blender's sunrise's sun reaches
// 25.7 degrees into its glow while most of its energy is in a core under a degree. Taken as a
// disc of that radius, its reflection on a metal at roughness 0.3 peaked at 1.57 times the
// reference's, the levels' blend judged for a wide light.
struct LightSpread {
    double core_share = 0.0;
    double core_cap_tan2 = 0.0;
    double glow_cap_tan2 = 0.0;
};
inline constexpr double kLightCoreAngularRadius = 0.00873;  // half a degree: a sun's is 0.27
LightSpread light_spread(double angular_radius, const LightProfile& profile);
// A uniform disc of angular radius rho: no core.
LightSpread disc_spread(double angular_radius);

// The fractional level at which a light's layer is read for roughness r: between the levels
// a and a + 1 around lod_of_roughness, the blend weight that gives the reflection's peak of
// the light exactly, instead of the lod's fraction. Of a disc of energy Phi, radiance
// Phi / Omega, prefiltered at GGX's alpha = r^2, the peak is Phi / Omega F(alpha), F the lobe's
// share within the disc's radius rho: for D(h) (n.h) about the reflection, whose half vectors
// lie within rho / 2, F = T / (alpha^2 + T), T = tan^2(rho / 2) (the GGX distribution's
// cumulative integral, Walter et al. 2007), and Omega = 4 pi T / (1 + T), so the peak is
// Phi M(alpha) / (4 pi), M = (1 + T) / (alpha^2 + T); a core and a glow add theirs by their
// shares. The weight w = (M(alpha) - M(alpha_a)) / (M(alpha_b) - M(alpha_a)) then makes
// (1 - w) P_a + w P_b peak at the light's own. A linear blend of levels whose peaks differ
// tenfold (a compact light between roughness 0.23 and 0.37) is the sharp level's peak diluted
// once: 1.4 times the true peak at roughness 0.3 for a disc of 2 degrees, 1.7 at 0.2 for one
// degree; a blend of two levels keeps each level's energy whatever its weight. A light as
// large as the lobe has equal peaks at both levels: w is then the lod's fraction. The shader's
// light_lod is this function, given the light's spread.
double light_lod(double roughness, int levels, const LightSpread& spread);
double light_cap_tan2(double angular_radius);

// Z(alpha), the integral over the sphere of the prefiltering kernel K(r, l) = D(h) (r.l) with
// n = v = r ((r.h)^2 = (1 + r.l) / 2), by which the lights' cubes are normalised. In closed
// form, with c = r.l and a2 = alpha^2:
//   Z = 2 pi int_0^1 D c dc = 8 a2 / (a2 - 1)^2 (ln(2 a2 / (1 + a2)) + (1 - a2) / (2 a2)),
// 4 as alpha goes to 0 and 1 at alpha = 1 (D = 1 / pi). The shader's prefilter_kernel_integral
// is this function.
double prefilter_kernel_integral(double alpha);

// K(r, l) / Z(alpha) for r.l = r_dot_l: the share of a point's energy that a level prefiltered
// at alpha holds towards r, per steradian (0 where r.l <= 0). The shader's prefilter_kernel.
double prefilter_kernel(double alpha, double r_dot_l);

// What a light's layer read at light_lod lacks of its core's reflection at roughness r, per
// unit of the core's energy, towards an r at r.l = r_dot_l from the light's direction:
//   K_alpha(r.l) - ((1 - w) K_alpha_a(r.l) + w K_alpha_b(r.l)),
// alpha = r^2, a and a + 1 the levels around light_lod and w its fraction. Two levels' kernels
// blended have the exact peak (light_lod) but not the exact shape: a spike of the sharp level
// on the wide level's skirt. For a sun, whose core holds most of its energy in under a degree,
// that put 0.78 of the reference's light within two pixels of a metal sphere's highlight at
// roughness 0.3 and the rest in a wide skirt (Blender's sunrise, 128^2). Taking the core as a
// point, adding its energy times this turns the blend into the exact kernel about the core;
// the glow keeps the levels' blend, which for a light wider than the lobe is its own shape.
// 0 below the second level and at the last: the mirror level is the light's own pixels
// resampled, and the first level's kernel (alpha 0.011) is narrower than the texels it is summed
// from (1.4 degrees at the default 128^2), so both hold a core as a texel, not a point (taken
// from the first level, a mirror's error under Blender's city went 0.378 -> 0.497).
double light_core_correction(double roughness, int levels, const LightSpread& spread,
                             double r_dot_l);

// The energy of a light's core that light_core_correction scales: core_share times the light's
// sum of L dOmega. 0 where the light's layer cannot hold its core as that kernel: where the
// core's peak at the second level passes the largest half float, to which the layer's texels
// are clamped (a sun at the largest float: the correction would be out of all proportion to
// the layer).
glm::dvec3 light_core_energy(const Light& light, const LightSpread& spread, int levels);

// The residual map (every rig light's pixels set to 0) prefiltered. The map must be the one
// the rig was built from (same size; rig.model Hdr: the thesis model has no specular term).
// Throws oer::Error (InvalidInput) for options out of range, a map of another size than the
// rig's source, or a Thesis rig. Deterministic: the same map, rig and options give the same
// bytes (fixed sample sequence, fixed split over threads).
PrefilteredCube prefilter_residual(const HdrImage& map, const Rig& rig,
                                   const SpecularOptions& options = {});

// Each light's pixels alone, prefiltered: layer k of `cube` is P(k) of rig light k, at
// light_face_size, and after them, in the order of the rig's lights, P(k above) of each light
// that straddles the horizon, which `floor_layers` names (SpecularEnvironment). Validation and
// errors as prefilter_residual.
struct PrefilteredLights {
    PrefilteredCube cube;
    std::vector<int> floor_layers;
};
PrefilteredLights prefilter_lights(const HdrImage& map, const Rig& rig,
                                   const SpecularOptions& options = {});

// Both, as a glossy frame reads them.
SpecularEnvironment prefilter_specular(const HdrImage& map, const Rig& rig,
                                       const SpecularOptions& options = {});

// The same for the whole map with no light removed (tests and measurements: the exact P(k) of
// a light is prefilter_map of a map holding only its pixels).
PrefilteredCube prefilter_map(const HdrImage& map, const SpecularOptions& options = {});

// Layer `layer` of the cube's radiance towards direction d (unit) at fractional level lod,
// trilinear as GL's textureLod on a seamless cube map (bilinear within a face, nearest across
// its edge): what the renderer reads, for tests and measurements on the CPU.
glm::dvec3 sample_cube(const PrefilteredCube& cube, const glm::dvec3& d, double lod, int layer = 0);

// A stored form for the asset store: a versioned header ("OERSPEC3"), each cube's sizes (face
// size, levels, layers: the residual's, then the lights'), the count of floor layers and each
// (int32), then the cubes' texels. decode throws oer::Error (InvalidInput) naming what is wrong
// for bytes that are truncated, of another version, of inconsistent sizes, with a floor layer
// that is not -1 or a layer of the lights' cube, or whose texels are not finite and
// non-negative.
std::string encode_specular_environment(const SpecularEnvironment& environment);
SpecularEnvironment decode_specular_environment(std::string_view bytes);

}  // namespace oer
