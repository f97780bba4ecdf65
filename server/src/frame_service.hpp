#pragma once
// Frames for POST and GET /v1/render: the encoded frame of a render request, from the LRU of
// encoded frames (keyed by the request's ETag) when it is there, else prepared on the calling
// HTTP thread (its map and specular cube), then completed and rendered by a worker of the pool
// (the transfer of a frame with occlusion on, from TransferRegistry, baked there when neither
// memory nor the store has it: a bake is render work, on the workers' queue at their priority)
// and encoded on the calling HTTP thread (so the GL worker moves on to the next frame). A frame
// whose scene has a glossy material under an hdr rig gets the rig's specular cube
// (EnvironmentRegistry::specular); any other gets none.
//
// The calling thread waits for the worker while its client does: once the request's deadline
// passes (503) or its client closes the connection, the frame is stopped (oer/core/
// cancellation.hpp): skipped by a worker that has not started it, stopped between passes or bake
// chunks by one that has, unless other frames wait for the same bake (AssetRegistry).
//
// What invalidates what (docs/design.md section 9 explains each row): a change pays for what it
// invalidates, which is where each cached thing's key stops.
//   change               | computed again                        | reused
//   camera               | geometry and shading passes           | shadow maps, transferred
//                        |                                       | irradiance, transfer, rig
//   light switch, dimmer | irradiance sets, transferred irr.     | shadow maps (per light),
//                        |                                       | transfer
//   environment's yaw    | shadow maps, transferred irradiance   | transfer, rig
//   colour               | transferred irradiance (slot weights) | transfer, shadow maps
//   floor                | nothing for the standard scene (both  | shadow maps
//                        | baked ahead); else the other state's  |
//                        | transfer, once                        |
//   shadow settings      | shadow maps of that setting           | transfer
//   bounce, transform    | transfer                              | rig, meshes
//   product              | transfer (baked ahead), shadow maps   | rig
//   environment          | rig, specular cube, shadow maps       | transfer
// Keys: the encoded frame's ETag (everything); the transfer's id (transfer_registry.hpp:
// meshes, transforms, ground, bounce, rays); the shadow maps' (shadow_pass.cpp: meshes, transforms,
// the light's direction and size, resolution, filter); the transferred irradiance's
// (frame_context.hpp: transfer, rig, weights, yaw, floor, bounce, bounce weights).
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "bake_lane.hpp"
#include "client_work_budget.hpp"
#include "environment_registry.hpp"
#include "mesh_registry.hpp"
#include "oer/api/hotspot_request.hpp"
#include "oer/api/render_request.hpp"
#include "oer/server/byte_lru_cache.hpp"
#include "render_cost.hpp"
#include "render_pool.hpp"
#include "service_metrics.hpp"
#include "transfer_registry.hpp"

namespace oer::server {

struct EncodedFrame {
    std::shared_ptr<const std::string> bytes;
    std::string content_type;
    std::string etag;
    bool cache_hit = false;
    std::string server_timing;  // W3C Server-Timing, per pass; empty for a cached frame
    Camera camera;              // what the frame is seen from (api::resolved_camera)
    // Drawn without the occlusion transfer the request asked for, which is being baked: not
    // the representation the request names, for no client to keep (FrameService::render's
    // preliminary_allowed).
    bool preliminary = false;
};

// A render request with its ids resolved and its camera computed, once: the answer's camera
// header and the frame request both take the camera from here.
struct ResolvedRender {
    const api::RenderSpec& spec;
    std::shared_ptr<const Environment> environment;
    std::vector<std::shared_ptr<const Mesh>> meshes;  // one per object, in order
    std::vector<std::string> mesh_ids;
    Camera camera;
};

// Where the frame of a hotspots request shows each of them (POST and GET /v1/hotspots).
struct HotspotPlacements {
    Camera camera;                           // the frame's (api::resolved_camera)
    std::vector<PointPlacement> placements;  // one per hotspot, in the request's order
};

// The surface of the product a pixel shows (POST /v1/pick): where on which mesh, and the point
// there as a surface hotspot names it; no spot where the pixel shows no object.
struct PickedSurface {
    Camera camera;
    std::optional<api::SurfaceSpot> spot;
    ScenePoint point;
};

// Where the bake ahead of one scene's transfer stands: queued, baking, ready, or not prepared
// (over the budgets, refused by a full queue, failed, or removed since).
struct ScenePreparation {
    enum class State { NotPrepared, Queued, Baking, Ready };
    State state = State::NotPrepared;
    double fraction = 0.0;
    std::optional<double> seconds_left;  // Baking, once a part is done: at the rate so far
};

// Where the preparation of a mesh stands (GET /v1/meshes/{id}/preparation): the transfers of
// its standard scene (FrameService::prepare), on the floor (its first frames) and without it
// (the floor's toggle).
struct MeshPreparation {
    ScenePreparation first_frames;
    ScenePreparation without_floor;
};

// How the request named its members, for the `parameter` of a 404.
enum class RequestForm { Json, Query };

// Which workers draw a frame: the interactive pool, or the batch jobs' own worker below it
// (job_service.hpp), so that a batch frame never holds a place an interactive one waits for.
enum class Lane { Interactive, Batch };

class FrameService {
  public:
    FrameService(EnvironmentRegistry& environments, MeshRegistry& meshes,
                 TransferRegistry& transfers, RenderPool& pool, RenderPool& batch_pool,
                 ByteLruCache& frames, ServiceMetrics& metrics, std::chrono::seconds deadline,
                 RenderBudgets budgets, double transfer_rays_per_phase,
                 ClientWorkBudget& client_work, std::function<void(std::string_view)> log);

    // Who asks: the client's address (its share of render work) and whether it has gone. A
    // batch job's frame is bounded by the job's own limits, not the client's share of
    // rendering, and waits for its worker without the request deadline (until `gone`).
    struct Client {
        std::string address;
        std::function<bool()> gone;
        Lane lane = Lane::Interactive;
    };

    // etag: api::render_etag(spec), computed once by the caller (which answers 304 with it).
    // A frame not in the cache is first checked against `client`'s share of render work, then
    // charged the work it took (client_work_budget.hpp). Throws HttpError (404 for an unknown id,
    // 413 over a budget, 429 past the client's share, 503 past the deadline or once the client
    // has gone), QueueFull, and what to_frame_request and the renderer throw.
    // preliminary_allowed: a frame whose occlusion transfer is not ready is drawn at once
    // without it (its lighting unoccluded), marked preliminary and kept apart from the whole
    // frames (asked for again, it is served from there until the transfer is ready), while
    // the transfer is baked ahead for the frames asked for next; otherwise the frame waits
    // for it.
    EncodedFrame render(const api::RenderSpec& spec, const std::string& etag, RequestForm form,
                        const Client& client, bool preliminary_allowed = false);

    // Where the frame that request.render draws shows each hotspot: that frame's depth
    // (FrameRenderer::place_points) from its geometry pass alone, at one sample a pixel,
    // without shadow maps or transfer (its cost estimated and charged as such a frame's), on a
    // worker of the pool while the client waits, charged to its share of render work. Throws as
    // render does, and InvalidParameter
    // for a hotspot on a primitive or triangle its object's mesh lacks.
    HotspotPlacements place_hotspots(const api::HotspotRequest& request, RequestForm form,
                                     const Client& client);
    // The surface the pixel's centre shows in the frame that request.render draws: a ray cast on
    // the HTTP thread against the objects' triangles (the reference renderer's Embree scene;
    // alpha-tested and blended surfaces let it through as the reference does), the ground never
    // counting as the product. Held while the client is past its share of render work, and
    // the time it took charged to that share. Throws as render does before it renders.
    PickedSurface pick(const api::PickRequest& request, RequestForm form, const Client& client);
    // What render checks before any work: the ids known (404), the cost within the budgets
    // (413), the variants and materials in the meshes (422), each named as a JSON request names
    // it. For a batch job's frames, when it is submitted.
    void check(const api::RenderSpec& spec) { resolve(spec, RequestForm::Json); }

    // Bakes ahead, on the bake lane (bake_lane.hpp), the transfer of mesh_id's standard scene (the
    // mesh alone, untransformed, on the ground, one bounce: the scene of a product's first frames),
    // so that they find it ready instead of baking it; then the same scene's without the floor,
    // so that the floor's toggle finds it too (the bounce off the floor is not separable from the
    // light the objects reflect onto each other from below the horizon: docs/design.md section
    // 9). Skipped (logged) when its cost is over the budgets, or when the lane's queue is full.
    void prepare(const std::string& mesh_id);
    // Where that preparation stands; nullopt when no mesh has that id.
    std::optional<MeshPreparation> preparation(const std::string& mesh_id);

  private:
    // Bakes waiting for the bake lane at most; beyond, bake_ahead queues nothing.
    static constexpr std::size_t kMaxQueuedBakes = 16;
    // Queues the bake of request's transfer on the bake lane, nobody waiting for it (its
    // outcome logged, naming `what`), unless it is queued or under way already.
    void bake_ahead(std::shared_ptr<const FrameRequest> request, std::vector<std::string> mesh_ids,
                    const std::string& what);
    // The standard scene of mesh (prepare's), on the floor or not; with mesh empty, enough for
    // its transfer's id.
    static FrameRequest standard_scene(std::shared_ptr<const Mesh> mesh, bool ground);
    // Where the bake ahead of the transfer with that id stands.
    ScenePreparation scene_preparation(const std::string& transfer_id);

    // The environment the spec names, then its cost estimated from its meshes' summaries and
    // checked against the budgets (413), then the meshes, decoded, and its camera; 404 for an
    // unknown id.
    ResolvedRender resolve(const api::RenderSpec& spec, RequestForm form);
    // The frame to render: the resolved scene with its map and specular cube where it needs
    // them (404 when the store no longer holds the map); its transfer comes on the worker.
    FrameRequest frame_request(const ResolvedRender& resolved);
    // The frame a worker renders from request, with its transfer when occlusion is on, while
    // the client waits and within the deadline (503 past either); a batch frame yields to
    // interactive ones (rendered_once again until one try is not stopped for them).
    Frame rendered(std::shared_ptr<FrameRequest> request, const std::vector<std::string>& mesh_ids,
                   const Client& client);
    // One try: nullopt when a batch frame was stopped to let an interactive frame go first.
    std::optional<Frame> rendered_once(std::shared_ptr<FrameRequest> request,
                                       const std::vector<std::string>& mesh_ids,
                                       const Client& client);
    // The job's result once a worker has run it, while the client waits and within the
    // deadline: past either, `stop` is requested and 503 thrown. A batch client's job is stopped
    // when an interactive frame arrives: nullopt when it stopped before it finished.
    std::optional<Frame> awaited(std::future<Frame>& pending, std::stop_source& stop,
                                 const Client& client);
    // The spec of the frame whose depth places hotspots and whose camera a pick sees through:
    // the same camera, meshes and ground, at one sample a pixel, without shadows, transfer or
    // the environment's map behind.
    static api::RenderSpec geometry_only(const api::RenderSpec& spec);
    // Past the client's share of uncached render work (client_work_budget.hpp): held a moment,
    // watching for the client leaving, then 429 with Retry-After.
    void hold_past_share(const Client& client);

    EnvironmentRegistry& environments_;
    MeshRegistry& meshes_;
    TransferRegistry& transfers_;
    RenderPool& pool_;
    RenderPool& batch_pool_;
    ByteLruCache& frames_;
    ServiceMetrics& metrics_;
    const std::chrono::seconds deadline_;
    const RenderBudgets budgets_;
    const double transfer_rays_per_phase_;
    ClientWorkBudget& client_work_;
    const std::function<void(std::string_view)> log_;
    std::mutex queued_mutex_;
    std::set<std::string> queued_;  // transfer ids of preparations queued or under way
    // Last: destroyed first, stopping its bake before what the bake uses goes.
    BakeLane bake_lane_;
};

}  // namespace oer::server
