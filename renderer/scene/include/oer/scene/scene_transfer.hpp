#pragma once
// Precomputed radiance transfer of a scene (P.-P. Sloan, J. Kautz and J. Snyder,
// "Precomputed Radiance Transfer for Real-Time Rendering in Dynamic, Low-Frequency Lighting
// Environments", SIGGRAPH 2002): per receiver point (each vertex of each object's primitives,
// and each texel of a grid on the ground around the objects) the SH vector that turns the
// residual map's radiance coefficients into the irradiance that reaches it past every occluder
// (the objects and the ground plane), and, under Bounce::One, the vectors that add what the
// objects and the ground reflect onto it once.
//
// For radiance coefficients L_i (docs/design.md section 3: world frame, the yaw applied, no A_l),
//   E(x) = sum_i direct_i(x) R_i + sum_s rho_c(s) sum_i bounce_s,i(x) L_c,i   (per channel c)
// where R is the residual map (the rig's radiance minus every light's own pixels) and L the
// whole lighting of the frame (R plus each light's pixels times its weight): the lights' own
// direct light keeps its shadow maps, their reflected light goes through the transfer.
// Without occluders direct_i(x) = A_l Y_i(n(x)), so direct . R is plain SH irradiance.
//
// The bounce is linear in the albedo of what reflects, so it is baked per reflector slot s (the
// ground, or the surfaces of one material of one object) at unit albedo, and each frame weighs
// the slots by the albedos it draws them with, rho(s): a colour change, which re-weights, never
// re-bakes (docs/design.md section 9, "what invalidates what").
//
// Plain data: the frame renderer reads it (FrameRequest::transfer), the bake
// (oer/transfer/transfer_bake.hpp) writes it, the codec (oer/transfer/transfer_codec.hpp)
// stores it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace oer {

// The albedo of the renderer's ground plane (docs/design.md section 7): the GL renderer draws it,
// the reference traces it, and the transfer's ground reflects it.
constexpr float kGroundAlbedo = 0.8f;

// Transfers are baked at this order (bands 0 to 6, 49 coefficients). Sloan et al. chose order 5
// for diffuse transfer, which is enough for the direct light of a smooth map; it is not for
// what a low sun reflects off the product onto the ground (the one-bounce term): on the bunny
// under Blender's sunrise, the ground near it was 8.4 % from the one-bounce reference at order 5
// and is 6.5 % at order 7 (plain SH: 16.3 %), for 20 % more bake time. A frame may use the first
// order^2 coefficients of any lower order, which are exactly that order's transfer (the
// coefficients of a projection do not depend on the order it stops at).
constexpr int kTransferBakeOrder = 7;

// One receiver set: count points, each `coefficients` direct values and, under Bounce::One,
// `coefficients` bounce values per reflector slot (SceneTransfer::reflectors), point-major:
// direct[p * coefficients + i], bounce[(p * slots + s) * coefficients + i].
struct TransferPoints {
    std::size_t count = 0;
    std::vector<float> direct;
    std::vector<float> bounce;  // empty under Bounce::None
};

// A surface of the scene that reflects in the bounce: one material of one object's mesh.
struct ReflectingSurface {
    std::uint32_t object = 0;    // index into FrameRequest::objects
    std::uint32_t material = 0;  // index into that object's Mesh::materials
    bool operator==(const ReflectingSurface&) const = default;
};

// What one bounce slot gathers: the ground plane's reflection (surfaces empty), or the
// objects' surfaces listed, which a frame always draws with one albedo (one surface, or several
// of the same mesh, material and colour: transfer_bake.hpp's reflector_slots).
struct ReflectorSlot {
    // Frames with the ground plane use the slots with the ground; frames without it the others:
    // with the plane, an object reflects the map above the horizon alone (the plane's own light
    // below it is the ground's slot), without it the whole map.
    bool with_ground = true;
    std::vector<ReflectingSurface> surfaces;
    // The albedo the slot's surfaces have as their mesh gives them (linear RGB): the ground's,
    // or the material's base colour factor times its texture's mean colour. A textured surface
    // reflects its texture's mean (the bounce gathers light over a whole hemisphere of hits,
    // which averages the texels anyway).
    glm::vec3 albedo{0.0f};
    bool ground() const { return surfaces.empty(); }
};

// The ground plane's receivers: a resolution x resolution grid of texel centres over
// [centre.x - half_size, centre.x + half_size] x [centre.y - half_size, ...] in world x and z,
// row r at z = centre.y - half_size + (r + 0.5) * 2 half_size / resolution, column c likewise
// in x; point index r * resolution + c. Beyond the grid nothing occludes or reflects onto the
// ground (the grid is made large enough for that), so its edge texels hold the unoccluded
// cosine transfer at +Y.
struct GroundTransfer {
    glm::vec2 centre{0.0f};  // world (x, z)
    float half_size = 0.0f;
    float height = 0.0f;  // world y of the plane
    int resolution = 0;
    TransferPoints points;
};

// The light a frame models (`oer render --bounce`, the API's "bounce"), and the reference
// renderer's matching mode.
enum class Bounce : std::uint8_t {
    None,  // light straight from the environment only: the ground lights nothing
    One,   // plus one diffuse bounce off the meshes and the ground
};

struct SceneTransfer {
    int order = kTransferBakeOrder;  // of the stored vectors; coefficients = order^2
    Bounce bounce = Bounce::One;
    int rays = 0;  // per receiver point
    // [object][primitive], parallel to FrameRequest::objects and each mesh's primitives; each
    // one point per vertex of the primitive.
    std::vector<std::vector<TransferPoints>> objects;
    std::optional<GroundTransfer> ground;   // when the scene has the ground plane
    std::vector<ReflectorSlot> reflectors;  // the bounce's slots, under Bounce::One
    double bake_ms = 0.0;                   // how long the bake took, for logs and metrics

    int coefficients() const { return order * order; }
};

}  // namespace oer
