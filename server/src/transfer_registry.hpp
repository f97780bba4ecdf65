#pragma once
// Scenes' precomputed radiance transfers (oer/transfer/transfer_bake.hpp), which a
// frame with occlusion on needs for its objects, their transforms and colours, the ground and
// the bounce. Kept like a rig's specular cube: in memory (LRU by bytes), else read back from the
// asset store (an entry that is damaged, or does not fit its scene, is logged, dropped and baked
// again, never served), else baked once however many frames of the scene arrive together
// (AssetRegistry), on the calling thread (an HTTP thread, or start-up: never a GL render
// worker), stored and remembered (in memory only when the disk is full: the frame is not
// refused for it). A bake of the Stanford bunny takes up to about 2 s.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "asset_registry.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_transfer.hpp"
#include "oer/server/asset_store.hpp"
#include "service_metrics.hpp"

namespace oer::server {

// The id a scene's transfer is stored and cached under: SHA-256 over everything the bake reads,
// each object's mesh id (mesh_ids, parallel to request.objects: content ids, or the preset's),
// transform and base colour, the ground, the bounce, the ray count of transfer_ray_count's rule,
// kTransferBakeOrder and the bake's version (transfer_registry.cpp).
std::string transfer_id(const FrameRequest& request, const std::vector<std::string>& mesh_ids,
                        int rays);

class TransferRegistry {
  public:
    using Log = std::function<void(std::string_view)>;

    // rays_per_phase: ServiceConfig::transfer_ray_budget, which transfer_ray_count shares out.
    TransferRegistry(AssetStore& store, ServiceMetrics& metrics, Log log, std::size_t cache_bytes,
                     double rays_per_phase);

    // The transfer of request's objects, ground and bounce, from memory, the store, or baked
    // (with transfer_ray_count's rays for the budget on every core). Throws oer::Error as
    // bake_transfer does (InvalidInput for a request without objects).
    std::shared_ptr<const SceneTransfer> transfer(const FrameRequest& request,
                                                  const std::vector<std::string>& mesh_ids);

  private:
    std::shared_ptr<const SceneTransfer> load_stored(const std::string& id,
                                                     const FrameRequest& request);
    std::shared_ptr<const SceneTransfer> bake(const std::string& id, const FrameRequest& request,
                                              int rays);

    AssetStore& store_;
    ServiceMetrics& metrics_;
    const Log log_;
    AssetRegistry<SceneTransfer> transfers_;
    const double rays_per_phase_;
};

}  // namespace oer::server
