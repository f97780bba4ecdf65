#pragma once
// Frames for POST and GET /v1/render: the encoded frame of a render request, from the LRU of
// encoded frames (keyed by the request's ETag) when it is there, else rendered by a worker of
// the pool within the request's deadline and encoded on the calling HTTP thread (so the GL
// worker moves on to the next frame); a frame whose request gave up at the deadline is skipped
// by the worker that reaches it, unless it is already being rendered. A frame whose scene has a
// glossy material under an hdr rig gets the rig's specular cube (EnvironmentRegistry::specular);
// any other gets none. A frame with occlusion on gets its scene's transfer (TransferRegistry),
// baked on the calling thread when neither memory nor the store has it.
#include <chrono>
#include <memory>
#include <string>

#include "client_work_budget.hpp"
#include "environment_registry.hpp"
#include "mesh_registry.hpp"
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

// How the request named its members, for the `parameter` of a 404.
enum class RequestForm { Json, Query };

class FrameService {
  public:
    FrameService(EnvironmentRegistry& environments, MeshRegistry& meshes,
                 TransferRegistry& transfers, RenderPool& pool, ByteLruCache& frames,
                 ServiceMetrics& metrics, std::chrono::seconds deadline, RenderBudgets budgets,
                 double transfer_rays_per_phase, ClientWorkBudget& client_work);

    // etag: api::render_etag(spec), computed once by the caller (which answers 304 with it).
    // A frame not in the cache is first checked against `client`'s share of render work, then
    // charged the work it took (client_work_budget.hpp). Throws HttpError (404 for an unknown id,
    // 413 over a budget, 429 past the client's share, 503 past the deadline), QueueFull, and what
    // to_frame_request and the renderer throw.
    EncodedFrame render(const api::RenderSpec& spec, const std::string& etag, RequestForm form,
                        const std::string& client);

  private:
    // The environment the spec names, then its cost estimated from its meshes' summaries and
    // checked against the budgets (413), then the meshes, decoded, and its camera; 404 for an
    // unknown id.
    ResolvedRender resolve(const api::RenderSpec& spec, RequestForm form);
    // The frame to render: the resolved scene with its map, specular cube and transfer where
    // it needs them (404 when the store no longer holds the map).
    FrameRequest frame_request(const ResolvedRender& resolved);
    // The frame a worker renders from request, within the deadline (503 past it).
    Frame rendered(std::shared_ptr<const FrameRequest> request);

    EnvironmentRegistry& environments_;
    MeshRegistry& meshes_;
    TransferRegistry& transfers_;
    RenderPool& pool_;
    ByteLruCache& frames_;
    ServiceMetrics& metrics_;
    const std::chrono::seconds deadline_;
    const RenderBudgets budgets_;
    const double transfer_rays_per_phase_;
    ClientWorkBudget& client_work_;
};

}  // namespace oer::server
