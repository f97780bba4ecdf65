#pragma once
// Specular image-based lighting of a rig: the split-sum approximation of B. Karis,
// "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes (RTR4 section 10.5.2), made
// switchable per light as OER makes the diffuse (docs/design.md section 2). Prefiltered radiance is
// linear in the map, so for light weights w_k and visibilities v_k
//   P(S) = P(residual) + sum_k w_k v_k P(k),
// where the residual is the map with every light's pixels removed (set to 0) and P(k) the
// prefiltered radiance of light k's pixels alone. P(residual) is one prefiltered cube map
// (below); each P(k) is analytic, the light's lobes (light_lobe.hpp), since a light is small
// and a cube map per light would cost its memory again per light.
//
// The cube map: face order and orientation of the OpenGL cube-map table (as
// environment_layouts.hpp), level i of face size face_size >> i holding the radiance
// prefiltered with the GGX lobe of perceptual roughness i / (levels - 1), with n = v = r
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
#include "oer/lighting/rig.hpp"

namespace oer {

struct SpecularOptions {
    int face_size = 256;  // level 0, a power of two in [4, 2048]
    int levels = 5;       // in [2, log2(face_size) + 1]; level levels - 1 is roughness 1
    int samples = 64;     // GGX samples per texel of levels 1 and above, in [1, 4096]
};

struct PrefilteredCube {
    int face_size = 0;
    int levels = 0;
    // Per level: 6 faces of (face_size >> level)^2 texels, rows from t = 0, interleaved RGB as
    // IEEE half floats (GL_RGB16F, GL_HALF_FLOAT): linear radiance, as the map's.
    std::vector<std::vector<std::uint16_t>> rgb_half;

    // Bytes of the texels (what the cube costs in memory and on the renderer).
    std::size_t byte_size() const;
};

// The perceptual roughness that level `level` of a cube of `levels` levels is prefiltered for,
// and back (the shader reads lod = roughness * (levels - 1)).
double roughness_of_level(int level, int levels);

// The residual map (every rig light's pixels set to 0) prefiltered. The map must be the one
// the rig was built from (same size; rig.model Hdr: the thesis model has no specular term).
// Throws oer::Error (InvalidInput) for options out of range, a map of another size than the
// rig's source, or a Thesis rig. Deterministic: the same map, rig and options give the same
// bytes (fixed sample sequence, fixed split over threads).
PrefilteredCube prefilter_residual(const HdrImage& map, const Rig& rig,
                                   const SpecularOptions& options = {});

// The same for the whole map with no light removed (tests and measurements: the exact P(k) of
// a light is prefilter_map of a map holding only its pixels).
PrefilteredCube prefilter_map(const HdrImage& map, const SpecularOptions& options = {});

// The cube's radiance towards direction d (unit) at fractional level lod, trilinear as GL's
// textureLod on a seamless cube map (bilinear within a face, nearest across its edge): what
// the renderer reads, for tests and measurements on the CPU.
glm::dvec3 sample_cube(const PrefilteredCube& cube, const glm::dvec3& d, double lod);

// A stored form for the asset store: a versioned header ("OERSPEC1", sizes) then the texels.
// decode throws oer::Error (InvalidInput) naming what is wrong for bytes that are truncated,
// of another version, of inconsistent sizes, or whose texels are not finite and non-negative.
std::string encode_prefiltered_cube(const PrefilteredCube& cube);
PrefilteredCube decode_prefiltered_cube(std::string_view bytes);

}  // namespace oer
