#pragma once
// Meshes: uploads stored by content id, decoded meshes kept in memory (LRU by bytes) so that
// the render workers' per-mesh GPU caches stay warm between frames, and read back from the
// asset store after a restart. The preset `default` is the built-in product.
#include <memory>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "oer/mesh/mesh_loading.hpp"
#include "oer/server/asset_store.hpp"
#include "oer/server/shared_lru_cache.hpp"
#include "service_metrics.hpp"

namespace oer::server {

struct StoredMesh {
    std::string id;  // content id, or kDefaultPresetId
    std::shared_ptr<const Mesh> mesh;
    nlohmann::json json;  // mesh_to_json: the API's answer
};

class MeshRegistry {
  public:
    MeshRegistry(AssetStore& store, ServiceMetrics& metrics, const MeshLimits& limits,
                 std::size_t cache_bytes);

    struct Upload {
        std::shared_ptr<const StoredMesh> mesh;
        bool cached = false;  // these bytes were stored already
    };
    // Throws oer::Error for bytes that do not load (InvalidInput) or are over the limits.
    Upload upload(std::string_view bytes, MeshFormat format);

    // nullptr when no mesh has that id.
    std::shared_ptr<const StoredMesh> find(const std::string& id);

  private:
    std::shared_ptr<const StoredMesh> remember(const std::string& id, Mesh mesh, MeshFormat format);

    AssetStore& store_;
    ServiceMetrics& metrics_;
    const MeshLimits limits_;
    std::shared_ptr<const StoredMesh> preset_;
    SharedLruCache<StoredMesh> meshes_;
};

}  // namespace oer::server
