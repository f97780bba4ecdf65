#pragma once
// What a render will cost, estimated from the request and its meshes' summaries before any of
// it runs (no mesh decoded, no transfer baked, no GL work), and checked against the service's
// budgets: one small request could otherwise take gigabytes (sixteen 8192² shadow maps: 4 GiB;
// twelve meshes each with four 4096² textures: 4 GiB), minutes (64 copies of a 1M-triangle
// mesh) or gigabytes of disk (the transfer of a 5M-triangle mesh: 2 GB).
//
// The figures are upper estimates of what the renderer allocates and does, per part:
//  - memory: the distinct meshes as decoded (their summaries), their textures again as GL holds
//    them with their mipmaps (4/3 of the decoded bytes: llvmpipe keeps them in the process's
//    memory, a GPU's driver stages them there), the frame's targets at
//    kTargetBytesPerSample per sample (render_targets.cpp: positions, normals, albedos,
//    emissive, transferred, depth and shaded; float formats for EXR), one 32-bit depth map per
//    shadowing light (shadow_map_cache.cpp), and the transfer with occlusion on (held while
//    baked, then stored);
//  - time: triangles drawn (the geometry pass, each shadowing light's pass and the ground's
//    visibility pass) at kTrianglesPerSecond, samples drawn and shaded (once, and once per
//    light) at kSampleLightsPerSecond, and the bake: kBakeSecondsPerPoint per receiver point
//    and its rays (transfer_ray_count's rule, twice with the bounce) at kRaysPerSecond; the
//    rates are those of the slowest machine the service runs on (llvmpipe and Embree on 2
//    cores), measured in docs/design.md section 9, so that a GPU finishes well within them;
//  - disk: the transfer's stored bytes (transfer_codec.cpp: a float per coefficient, and with
//    the bounce three more per coefficient).
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_registry.hpp"
#include "oer/api/render_request.hpp"

namespace oer::server {

// The limits a render's estimate must stay within (ServiceConfig: --max-render-memory-bytes,
// --max-render-seconds, --max-transfer-bytes).
struct RenderBudgets {
    std::uint64_t memory_bytes = 2ull << 30;
    double seconds = 30.0;
    std::uint64_t transfer_bytes = 64ull << 20;
};

struct RenderCost {
    std::uint64_t mesh_bytes = 0;        // the distinct meshes, decoded
    std::uint64_t texture_bytes = 0;     // of which their textures
    std::uint64_t gl_texture_bytes = 0;  // the textures as GL holds them, with mipmaps
    std::uint64_t target_bytes = 0;      // the frame's render targets
    std::uint64_t shadow_bytes = 0;      // the shadow maps
    std::uint64_t transfer_bytes = 0;    // the transfer (memory while baked, then disk)
    double draw_seconds = 0.0;           // triangles drawn
    double shade_seconds = 0.0;          // samples shaded
    double bake_seconds = 0.0;           // the transfer's rays

    std::uint64_t memory_bytes() const {
        return mesh_bytes + gl_texture_bytes + target_bytes + shadow_bytes + transfer_bytes;
    }
    double seconds() const { return draw_seconds + shade_seconds + bake_seconds; }
};

// Bytes of the render targets per sample (the widest formats, an EXR frame's).
inline constexpr std::uint64_t kTargetBytesPerSample = 84;
// llvmpipe and Embree on 2 cores (docs/design.md section 9 has the measurements).
inline constexpr double kTrianglesPerSecond = 4.0e6;
inline constexpr double kSampleLightsPerSecond = 1.0e7;
inline constexpr double kRaysPerSecond = 1.5e7;
inline constexpr double kBakeSecondsPerPoint = 2.0e-5;

// The cost of rendering spec with these meshes (one summary per object, in order, the same
// mesh id counted once) under a rig of `rig_lights` lights; rays_per_phase is the service's
// transfer ray budget.
RenderCost estimate_render_cost(const api::RenderSpec& spec,
                                const std::vector<MeshSummary>& object_meshes,
                                const std::vector<std::string>& mesh_ids, std::size_t rig_lights,
                                double rays_per_phase);

// Throws HttpError 413 (LimitExceeded) naming the first budget the cost is over, its estimate
// and the parts that make it, and how to bring it down; the problem's `estimate` and `budget`
// members carry the figures.
void check_render_cost(const RenderCost& cost, const RenderBudgets& budgets);

}  // namespace oer::server
