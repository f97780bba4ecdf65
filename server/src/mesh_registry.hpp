#pragma once
// Meshes: uploads stored by content id, decoded meshes kept in memory (LRU by bytes) so that
// the render workers' per-mesh GPU caches stay warm between frames, and read back from the
// asset store after a restart. The preset `default` is the built-in product.
#include <memory>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "asset_registry.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/server/asset_store.hpp"
#include "service_metrics.hpp"
#include "upload_budget.hpp"

namespace oer::server {

struct StoredMesh {
    std::string id;  // content id, or kDefaultPresetId
    std::shared_ptr<const Mesh> mesh;
    nlohmann::json json;  // mesh_to_json: the API's answer
};

class MeshRegistry {
  public:
    MeshRegistry(AssetStore& store, ServiceMetrics& metrics, UploadBudget& budget,
                 const MeshLimits& limits, std::size_t cache_bytes);

    // The mesh, and whether these bytes were there already (nothing was loaded).
    using Upload = AssetRegistry<StoredMesh>::Upload;
    // Throws oer::Error for bytes that do not load (InvalidInput) or are over the limits, and
    // HttpError 503 when the upload budget has no room for it now.
    // Concurrent uploads of the same bytes load and store them once (AssetRegistry): the later
    // ones wait for the first and answer as cached (or with the same error).
    Upload upload(std::string_view bytes, MeshFormat format);

    // nullptr when no mesh has that id.
    std::shared_ptr<const StoredMesh> find(const std::string& id);

  private:
    std::shared_ptr<const StoredMesh> read_stored(const std::string& id);
    // Counted in oer_meshes_loaded_total.
    Mesh load(std::string_view bytes, const std::string& name, MeshFormat format);
    std::shared_ptr<const StoredMesh> remember(const std::string& id, Mesh mesh, MeshFormat format);

    AssetStore& store_;
    ServiceMetrics& metrics_;
    UploadBudget& budget_;
    const MeshLimits limits_;
    AssetRegistry<StoredMesh> meshes_;
};

}  // namespace oer::server
