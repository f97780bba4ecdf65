#pragma once
// Meshes: uploads stored by content id, decoded meshes kept in memory (LRU by bytes) so that
// the render workers' per-mesh GPU caches stay warm between frames, and read back from the
// asset store after a restart. The preset `default` is the built-in product. Uploaded meshes are
// listed by id and removed from the store and from memory.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "asset_registry.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/server/asset_store.hpp"
#include "service_metrics.hpp"
#include "upload_budget.hpp"

namespace oer::server {

// What a render needs to know of a mesh before decoding it (render_cost.hpp): kept in memory
// and stored beside the mesh (DerivedKind::MeshSummary) when the mesh is first decoded.
struct MeshSummary {
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;        // also the receiver points of its transfer
    std::uint64_t texture_bytes = 0;   // every texture decoded (RGBA, 8 bits a channel)
    std::uint64_t resident_bytes = 0;  // what the decoded mesh holds, textures included
    std::uint64_t bounce_vectors = 0;  // of an object of it in a transfer (object_bounce_vectors)
};

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
    // Throws oer::Error for bytes that do not load (InvalidInput) or are over the limits,
    // HttpError 503 when the upload budget has no room for it now, and StorageFull when the
    // disk has no room for them (nothing is kept then).
    // Concurrent uploads of the same bytes load and store them once (AssetRegistry): the later
    // ones wait for the first and answer as cached (or with the same error).
    // file_name: what the load's errors call the file (upload_file_name).
    Upload upload(std::string_view bytes, MeshFormat format, const std::string& file_name);

    // nullptr when no mesh has that id.
    std::shared_ptr<const StoredMesh> find(const std::string& id);
    // The summary of mesh id without decoding it (nullopt when no mesh has that id): from
    // memory, else from its stored record; a mesh stored without one (by an older version) is
    // decoded once to make it.
    std::optional<MeshSummary> summary(const std::string& id);

    // The uploaded meshes (the preset is not listed) with ids after `after` ("" for the first
    // page), at most limit of them; each with its file's size and format and when it was stored.
    ListedPage list(std::string_view after, std::size_t limit);

    // Removes the uploaded mesh id (a content id: the preset is not removed) from the store and
    // from memory; false when no mesh has that id. A mesh is one file, removed at once. The
    // transfers of scenes holding it are removed after it (TransferRegistry::remove_with_mesh,
    // by the DELETE route); until then no frame reaches them, as their ids hash the mesh's.
    bool remove(const std::string& id);

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
    std::mutex summaries_mutex_;
    std::map<std::string, MeshSummary> summaries_;  // a few numbers per stored mesh
};

}  // namespace oer::server
