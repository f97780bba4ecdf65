#pragma once
// The bake of a scene's transfer (oer/scene/scene_transfer.hpp) on Embree: per receiver point, rays
// over the cosine-weighted hemisphere of its normal against the scene's objects and ground plane
// (the same surfaces and plane the frame renderer draws: oer/scene/scene_bounds.hpp), and under
// Bounce::One what those rays hit, reflecting its own direct transfer once.
// And the rules that choose how much a scene needs ("model only what a scene needs").
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <stop_token>
#include <vector>

#include "oer/lighting/rig.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_transfer.hpp"

namespace oer {

// How far a bake has come, for a caller that reports it while the bake's threads run: the
// receivers traced so far over both phases, of `total` (set once the bake has built its scene
// and starts tracing; 0 before), since `start` (when it was made).
struct BakeProgress {
    std::atomic<std::uint64_t> done{0};
    std::atomic<std::uint64_t> total{0};
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

    // In [0, 1]; 0 before tracing starts.
    double fraction() const {
        const std::uint64_t all = total.load();
        return all == 0 ? 0.0 : double(std::min(done.load(), all)) / double(all);
    }
};

struct TransferBakeOptions {
    Bounce bounce = Bounce::One;
    int rays = 0;     // per receiver point, rounded down to a square; 0: transfer_ray_count's rule
    int threads = 0;  // 0: every core
    // Checked by every thread before each chunk of kBakeChunk receivers (a few milliseconds of
    // rays): once a stop is requested the bake throws oer::Error (Cancelled) within one chunk.
    std::stop_token stop;
    // Counted up by every chunk of receivers traced, when given.
    BakeProgress* progress = nullptr;
};

// The receivers a bake thread traces between two looks at its stop token.
inline constexpr std::size_t kBakeChunk = 32;

// The rays per receiver point the rule gives for these objects (their vertex count bounds the
// bake's work; see the definition for the rule and its measurements).
// rays_per_phase: the budget the scene's receivers share (kTransferRayBudget, measured in the
// definition; a service may spend less to bake faster, more for less noise).
inline constexpr double kTransferRayBudget = 6.0e6;
int transfer_ray_count(const std::vector<SceneObject>& objects,
                       double rays_per_phase = kTransferRayBudget);
// The same rule for objects of `object_points` vertices in all, known before they are decoded
// (a service's estimate of a bake's cost).
int transfer_ray_count(std::uint64_t object_points, double rays_per_phase = kTransferRayBudget);
// The receiver points of a scene whose objects have `object_points` vertices in all: theirs and
// the ground's grid, which every scene's transfer holds.
std::uint64_t transfer_point_count(std::uint64_t object_points);

// The bounce's reflector slots (oer/scene/scene_transfer.hpp) of request's scene, so that a
// colour change re-weighs them and bakes nothing: with the ground, the
// ground's slot; then per group of objects (each object its own group, or past
// kMaxSeparateReflectors objects, the objects of one mesh and one colour together), a Material
// slot per material its primitives draw when they are at most kMaxMaterialSlots and none has a
// base-colour texture (one vector each, exact), else a Native and a Unit slot (four vectors,
// exact with textures).
inline constexpr std::size_t kMaxMaterialSlots = 3;
inline constexpr std::size_t kMaxSeparateReflectors = 4;
std::vector<ReflectorSlot> reflector_slots(const FrameRequest& request);
// Whether request's reflector slots depend on its objects' colours (past kMaxSeparateReflectors
// objects): a service keys its transfers by the colours then.
bool reflectors_follow_colours(const FrameRequest& request);
// The bounce vectors of one group of objects of `mesh` (reflector_slots): one per material its
// primitives draw when those are at most kMaxMaterialSlots, none has a base-colour texture,
// and each variant draws one material wherever the default draws one (so that a variant only
// re-weighs the slots); else a Native and a Unit slot, 4. For a service's estimate of a
// transfer's size before the meshes are decoded (its mesh summary keeps this).
std::size_t object_bounce_vectors(const Mesh& mesh);

// The transfer of request.objects (with their transforms) and, when request.ground, of the
// ground plane under them. Throws oer::Error (InvalidInput) for a request without objects,
// (Internal) when Embree fails, (Cancelled) once options.stop is requested.
SceneTransfer bake_transfer(const FrameRequest& request, const TransferBakeOptions& options);

}  // namespace oer
