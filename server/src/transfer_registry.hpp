#pragma once
// Scenes' precomputed radiance transfers (oer/transfer/transfer_bake.hpp), which a
// frame with occlusion on needs for its objects, their transforms and colours, the ground and
// the bounce. Kept like a rig's specular cube: in memory (LRU by bytes), else read back from the
// asset store (an entry that is damaged, or does not fit its scene, is logged, dropped and baked
// again, never served), else baked once however many frames of the scene arrive together
// (AssetRegistry), on the calling thread, stored and remembered (in memory only when the disk is
// full: the frame is not refused for it). A bake of the Stanford bunny takes up to about 2 s.
// Bakes run where their frames are rendered (FrameService: on a render worker, or at start-up),
// and stop once no frame waits for them.
//
// The store's transfers are bounded together (store_bytes, --transfer-store-bytes): past it the
// least recently used are removed, from the store and from memory, and baked again when a frame
// needs one. Each stored transfer has a record of the meshes its scene holds
// (DerivedKind::TransferMeshes, written before it and removed after it, so that every stored
// transfer has one), and goes when any of them is deleted (remove_with_mesh).
//
// The index of stored transfers (their sizes and last uses) is this process's: it is read from
// the store at start-up (ordered by when each was written), and follows what this process bakes,
// reads and removes. Processes sharing a data folder each keep the quota over what they know,
// so the folder holds at most the quota per process; removal with a mesh reads the records on
// disk, and so removes every process's transfers of it.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "asset_registry.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_transfer.hpp"
#include "oer/server/asset_store.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "service_metrics.hpp"

namespace oer::server {

// The id a scene's transfer is stored and cached under: SHA-256 over everything the bake reads,
// each object's mesh id (mesh_ids, parallel to request.objects: content ids, or the preset's) and
// transform, the ground, the bounce, the ray count of transfer_ray_count's rule,
// kTransferBakeOrder and the bake's version (transfer_registry.cpp). Not the objects' colours,
// which weigh the bounce's reflector slots, unless the slots group objects by colour
// (reflectors_follow_colours).
std::string transfer_id(const FrameRequest& request, const std::vector<std::string>& mesh_ids,
                        int rays);

// Where the making of one transfer stands.
struct TransferPreparation {
    enum class State { Absent, Baking, Ready };
    State state = State::Absent;
    double fraction = 0.0;         // Baking: of the bake's rays traced
    double elapsed_seconds = 0.0;  // Baking: since it started
};

class TransferRegistry {
  public:
    using Log = std::function<void(std::string_view)>;

    // rays_per_phase: ServiceConfig::transfer_ray_budget, which transfer_ray_count shares out;
    // store_bytes: ServiceConfig::transfer_store_bytes. Reads the store's transfers and their
    // records (removing a transfer without a record, which an older version stored, and the
    // least recently written past store_bytes). Throws oer::Error (Io) when the store fails.
    TransferRegistry(AssetStore& store, ServiceMetrics& metrics, Log log, std::size_t cache_bytes,
                     double rays_per_phase, std::uint64_t store_bytes);

    // The transfer of request's objects, ground and bounce, from memory, the store, or baked
    // (with transfer_ray_count's rays for the budget on every core). Throws oer::Error as
    // bake_transfer does (InvalidInput for a request without objects), Cancelled once `stop` is
    // requested (the bake itself stops once every frame waiting for it has stopped).
    // keep_in_memory false (a bake ahead, which no frame draws yet): a transfer it bakes is
    // only stored (kept in memory after all when the disk is full), so that uploads nobody
    // renders do not fill the memory cache.
    std::shared_ptr<const SceneTransfer> transfer(const FrameRequest& request,
                                                  const std::vector<std::string>& mesh_ids,
                                                  const std::stop_token& stop = {},
                                                  bool keep_in_memory = true);

    // The id request's transfer has (transfer_id with the rays of transfer_ray_count's rule for
    // `object_points` receiver points: the objects' vertices, known before they are decoded).
    std::string id_for(const FrameRequest& request, const std::vector<std::string>& mesh_ids,
                       std::uint64_t object_points) const;
    // The id request's transfer has (its objects' meshes decoded: transfer_ray_count's rule
    // counts their vertices).
    std::string id_of(const FrameRequest& request, const std::vector<std::string>& mesh_ids) const;
    // Whether transfer id is ready to draw: in memory or stored.
    bool ready(const std::string& id);
    // Whether transfer id is being baked (and how far it has come), is stored, or neither.
    TransferPreparation preparation(const std::string& id) const;

    // Removes every stored transfer whose scene holds mesh_id, from the store and from memory;
    // how many it removed.
    std::size_t remove_with_mesh(const std::string& mesh_id);

    // The bytes of the stored transfers this process knows of (at most store_bytes once a call
    // of transfer() has returned).
    std::uint64_t stored_bytes() const;

  private:
    struct StoredTransfer {
        std::uint64_t bytes = 0;
        std::uint64_t last_use = 0;  // of use_clock_
    };

    std::shared_ptr<const SceneTransfer> load_stored(const std::string& id,
                                                     const FrameRequest& request);
    std::shared_ptr<const SceneTransfer> bake(const std::string& id, const FrameRequest& request,
                                              int rays, const std::stop_token& stop,
                                              const std::vector<std::string>& mesh_ids,
                                              bool keep_in_memory);
    // Counts id's use (it moves to the back of the eviction order), with its size when it has
    // just been stored or read.
    void note_use(const std::string& id, std::optional<std::uint64_t> bytes = std::nullopt);
    // The size of transfer id's file (its sealed form), as the store's quota counts it; 0 when
    // it is gone.
    std::uint64_t stored_file_bytes(const std::string& id) const;
    // Removes the least recently used stored transfers until those known fit store_bytes.
    void evict_over_budget();
    // Removes transfer id and its record, in that order, from the store and from memory.
    void remove_stored(const std::string& id);

    AssetStore& store_;
    ServiceMetrics& metrics_;
    const Log log_;
    AssetRegistry<SceneTransfer> transfers_;
    const double rays_per_phase_;
    const std::uint64_t store_budget_;
    mutable std::mutex baking_mutex_;
    std::map<std::string, std::shared_ptr<BakeProgress>> baking_;  // guarded by baking_mutex_
    mutable std::mutex index_mutex_;
    std::map<std::string, StoredTransfer> stored_;  // guarded by index_mutex_
    std::uint64_t stored_bytes_ = 0;                // guarded by index_mutex_
    std::uint64_t use_clock_ = 0;                   // guarded by index_mutex_
};

}  // namespace oer::server
