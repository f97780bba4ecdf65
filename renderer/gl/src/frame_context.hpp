#pragma once
// What every pass of one frame reads (passes/frame_passes.hpp): the request, and what follows
// from it before any GL call (the lights' weights, their irradiance sets, the scene's bounds,
// the camera and light matrices, the supersampling), computed once by make_frame_context and
// read-only after: what a pass produces is its return value, not a field here.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "gl_program.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_bounds.hpp"

namespace oer {

// Surface kinds, the geometry pass's stencil values; each has its own shading program.
constexpr int kBackgroundSurface = 0;
constexpr int kObjectSurface = 1;
constexpr int kGroundSurface = 2;
// An object whose material has the extensions' layers (Material::layered), which the G-buffer's
// layer targets hold: shaded by its own program (shade.frag, SURFACE 4).
constexpr int kLayeredSurface = 4;
// The shading program of the ground's samples when it is a shadow catcher (shade.frag).
constexpr int kShadowCatcherProgram = 3;

struct FrameContext {
    explicit FrameContext(const FrameRequest& request_) : request(request_), rig(*request_.rig) {}

    const FrameRequest& request;
    const Rig& rig;

    // Lights.
    std::vector<float> weights;    // per rig light, FrameRequest::lights (0 off, 1 as captured)
    std::vector<std::size_t> lit;  // the rig indices of the lights of weight above 0
    glm::vec2 yaw_cos_sin{1.0f, 0.0f};
    // E = E(all) - sum_k (1 - w_k v_k) E(k) (docs/design.md section 2) split as
    // [E(all) - sum_k (1 - w_k) E(k)] - sum_k (1 - v_k) w_k E(k), since
    // 1 - w v = (1 - w) + w (1 - v): set 0 is the bracket, constant over the frame, and set
    // i + 1 is w_k E(k) for the i-th lit light k, which the shading pass takes off in its shadow
    // exactly as it took off an on light's E(k) before weights. A specular frame under
    // occlusion has one more, last: the open residual map's E(all) - sum_k E(k), against which
    // the shading measures how much of the residual's light the transfer lets through.
    std::vector<ShRgb> irradiance_sets;
    // Each set's irradiance on the ground plane (its normal +Y, which the yaw leaves unchanged):
    // ground_lighting.glsl's u_flat_irradiance.
    std::vector<glm::vec3> ground_irradiance;
    // Thesis model: 1 - sum_k (1 - w_k) luminance_share_k, split as the irradiance is.
    double attenuation_base = 1.0;

    // Occlusion (FrameRequest::occlusion with its transfer): set 0 is then the lights'
    // part alone, sum_k w_k E(k), and the residual map's irradiance, occluded and reflected,
    // comes from the transfer (transfer_lighting.hpp) per vertex of every object's primitives
    // and per texel of the ground's grid. With the ground, each light lights with its part above
    // the horizon only.
    bool transfer = false;
    std::vector<glm::vec3> transferred_vertices;  // every object's primitives, in order
    // [object][primitive]: the index in transferred_vertices of the primitive's first vertex
    std::vector<std::vector<std::size_t>> transferred_offsets;
    std::vector<glm::vec3> transferred_ground;  // the grid's texels, GroundTransfer's order
    // The open ground's (open_ground_irradiance): the grid's value where nothing occludes it,
    // the floor's beyond the grid, and the shadow-catching floor's light without the objects.
    glm::vec3 open_ground_transferred{0.0f};

    // Materials. specular: some object has a glossy material (Material::glossy) and the rig's
    // model is hdr (the thesis's has no specular BRDF): the frame reads FrameRequest::specular
    // and the DFG table, and its object programs are the SPECULAR 1 variants. blending: some
    // primitive is alpha mode BLEND, for the transparent pass. layered: in a specular frame,
    // some primitive's material has the extensions' layers (Material::layered), for the
    // G-buffer's layer targets and the shading pass's SURFACE 4 (OPAQUE and MASK ones) and the
    // transparent pass's MATERIAL_LAYERS 1 (BLEND ones).
    bool specular = false;
    bool blending = false;
    bool layered = false;

    // Scene and camera.
    SceneBounds scene;
    Camera camera;
    float near_plane = 0.0f;
    float ground_half_size = 0.0f;
    glm::mat4 view_projection{1.0f};

    // Shadows, per light that is on (parallel to lit).
    bool shadows = false;  // requested and at least one light on
    bool pcf = false;
    int shadow_resolution = 0;
    std::vector<glm::vec3> light_directions;  // turned by the yaw
    std::vector<glm::mat4> light_matrices;
    // tan of each light's glow angular radius (light_profile): PCSS's penumbra per unit of
    // blocker distance; and the share of its energy in a core, whose shadows are hard
    std::vector<float> light_spreads;
    std::vector<float> light_core_shares;
    // Per lit light: how its energy spreads for its reflection (specular_environment.hpp).
    std::vector<LightSpread> reflection_spreads;
    float normal_offset = 0.0f;  // receiver offset against acne, world units
    // SH_ORDER, LIGHTS_ON, SHADOWS and PCF for every program that lights (frame_programs.cpp).
    std::string lighting_defines;
    // "#define SPECULAR 0|1\n" for the programs that shade objects (frame.specular).
    std::string specular_define;
    // "#define TRANSFER 0|1\n" for the geometry, shading and transparent programs (transfer).
    std::string transfer_define;

    // Supersampling: the G-buffer is scale times the frame's size on each side.
    int scale = 1;
    int samples_wide = 0;
    int samples_high = 0;
};

// The transferred irradiance of the last frame with occlusion, and what it was computed from.
// It depends on the transfer, the rig, the lights' weights, the environment's yaw, the ground
// and the bounce, and the objects' colours, never on the camera: while the camera alone moves
// (an orbit), frames reuse it instead of evaluating every vertex's transfer again (8 ms a frame
// for the bunny under one bounce). Held weakly, so that it never keeps a transfer or a rig alive.
struct TransferredIrradianceInputs {
    std::weak_ptr<const SceneTransfer> transfer;
    std::weak_ptr<const Rig> rig;
    std::vector<float> weights;
    double yaw_degrees = 0.0;
    bool ground = false;
    Bounce bounce = Bounce::One;
    std::vector<glm::vec3> weights_of_bounce;  // per bounce vector (bounce_weights)
    // The same values, and the same transfer and rig objects, both still alive.
    bool same_as(const TransferredIrradianceInputs& other) const;
};
struct TransferredIrradianceCache {
    std::optional<TransferredIrradianceInputs> inputs;
    std::vector<glm::vec3> vertices;
    std::vector<std::vector<std::size_t>> offsets;
    std::vector<glm::vec3> ground;
    glm::vec3 open_ground{0.0f};
    std::size_t reuses = 0;  // frames that took the values from here
};

// The request must have passed validate_frame_request. cache: the renderer's, which the
// frame's transferred irradiance is taken from or stored in.
FrameContext make_frame_context(const FrameRequest& request, TransferredIrradianceCache& cache);

// Whether any primitive of the request's objects blends.
bool has_blending(const FrameRequest& request);

// Whether a primitive drawn with `material` is shaded by the layered programs in this frame.
bool shaded_layered(const FrameContext& frame, const Material& material);

// Supersamples per pixel side for `samples` samples per pixel (FrameRequest::samples).
int supersampling_scale(int samples);

// The lights' uniforms, shared by the shading pass and the ground-visibility bake.
void set_light_uniforms(gl::Program& program, const FrameContext& frame);

// Exposure, tone map and background of the display transform (the shading pass's at one
// sample per pixel, the resolve pass's above).
void set_display_uniforms(gl::Program& program, const FrameRequest& request);

// The name of element i of a uniform array: "name[i]".
std::string element(const char* name, std::size_t i);

// The level-of-detail error (draw_primitive's max_error, in the mesh's units) of a mesh drawn
// with `model` into the frame: one sample at its bounding sphere's nearest point.
float sample_lod_error(const FrameContext& frame, const Mesh& mesh, const glm::mat4& model);

// The longest triangle edge (draw_primitive's max_edge, in the mesh's units) a level of detail
// may have in this frame: a frame lit through a transfer interpolates it between vertices, so
// no longer than the refinement made them (transfer_edge_length); else no bound.
float transfer_lod_edge(const FrameContext& frame, const Mesh& mesh);

// The largest factor by which a transform stretches a length: a mesh-space error times it bounds
// the world-space error.
float largest_scale(const glm::mat4& transform);

}  // namespace oer
