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
// ground; an object's untextured material at unit albedo; or an object's surfaces as coloured
// and at unit albedo) and each frame weighs the slots by the albedos it draws them with,
// rho(s): a colour change, which re-weights, never re-bakes (docs/design.md section 9, "what
// invalidates what").
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
// `coefficients` bounce values per vector of the reflector slots (SceneTransfer::reflectors, in
// order, ReflectorSlot::vectors() each), point-major: direct[p * coefficients + i],
// bounce[(p * vectors + v) * coefficients + i], vectors = bounce_vectors(reflectors).
struct TransferPoints {
    std::size_t count = 0;
    std::vector<float> direct;
    std::vector<float> bounce;  // empty under Bounce::None
};

// What one bounce slot gathers, and how a frame weighs it (transfer_lighting.hpp's
// bounce_weights).
struct ReflectorSlot {
    enum class Kind : std::uint8_t {
        // The ground plane, at unit albedo; weighed by its albedo.
        Ground,
        // One material of the objects listed, at unit albedo (an untextured material, so that
        // its albedo is one colour); weighed by the objects' colour, else the material's.
        Material,
        // Everything the objects listed reflect, at the albedos they had at the bake (their
        // materials and textures), one vector per colour channel; weighed 1 when the objects
        // have no colour of their own, else 0.
        Native,
        // The same surfaces at unit albedo; weighed by the objects' colour when they have one,
        // else 0.
        Unit,
    };
    Kind kind = Kind::Ground;
    // The objects (indices into FrameRequest::objects) whose surfaces it gathers: of one mesh
    // and one colour (transfer_bake.hpp's reflector_slots); empty for the ground.
    std::vector<std::uint32_t> objects;
    std::uint32_t material = 0;  // Material: its index in the objects' Mesh::materials
    glm::vec3 albedo{0.0f};      // Ground: the ground's; Material: the material's base colour
    int vectors() const { return kind == Kind::Native ? 3 : 1; }
    bool operator==(const ReflectorSlot&) const = default;
};

// The bounce vectors a receiver point has for these slots.
inline std::size_t bounce_vectors(const std::vector<ReflectorSlot>& reflectors) {
    std::size_t vectors = 0;
    for (const ReflectorSlot& slot : reflectors) {
        vectors += std::size_t(slot.vectors());
    }
    return vectors;
}

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
