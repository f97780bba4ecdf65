#pragma once
// Environments and their rigs: uploads preprocessed once (by content id of bytes and options),
// rigs kept in memory (LRU by bytes) in front of the asset store, stored rigs read back after a
// restart without recomputation, a damaged stored rig recomputed from its source, and the
// decoded maps (for backgrounds and previews) in an LRU of their own. The preset `default` is
// the built-in studio with its rig and its specular cube at default options, made once at
// start-up (the default product is glossy: the first frame and the readiness check need it).
// Each uploaded rig's specular cubes (its residual map and each light prefiltered,
// specular_environment.hpp) are made only when a frame needs them, then kept like the rig: in
// memory (LRU by bytes) and in the store by rig id. Uploaded environments are listed by rig id and
// removed with all that was derived from them. A cube, or a rig recomputed for a lookup, that the
// disk has no room for is kept in memory only (logged): frames and lookups do not fail for want of
// space, uploads do.
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "asset_registry.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/server/asset_store.hpp"
#include "oer/server/shared_lru_cache.hpp"
#include "service_metrics.hpp"
#include "upload_budget.hpp"

namespace oer::server {

struct Environment {
    std::string id;                  // the rig id, or kDefaultPresetId
    std::shared_ptr<const Rig> rig;  // with its lights' pixel masks
    nlohmann::json json;             // rig_to_json: the API's answer
    std::string source_id;           // the map's content id; empty for the preset
};

class EnvironmentRegistry {
  public:
    using Log = std::function<void(std::string_view)>;

    EnvironmentRegistry(AssetStore& store, ServiceMetrics& metrics, UploadBudget& budget, Log log,
                        const ImageLimits& limits, std::size_t cache_bytes);

    // The environment, and whether its rig was there already (nothing was computed).
    using Upload = AssetRegistry<Environment>::Upload;
    // extension: "hdr" or "exr". Throws oer::Error for a map that does not decode (InvalidInput)
    // or is over the limits (LimitExceeded), HttpError 503 when the upload budget has no
    // room for it now (its cost is known from its header, before anything is decoded), and
    // StorageFull when the disk has no room for the map or its rig: the rig is then neither
    // stored nor known, and the map, if it was stored, waits for the upload to be made again.
    // Concurrent uploads of the same bytes and options compute the rig once (AssetRegistry):
    // the later ones wait for it and answer as cached (or with the same error).
    // file_name: what the decoder's errors call the file (upload_file_name).
    Upload upload(std::string_view bytes, const std::string& extension, const RigOptions& options,
                  const std::string& file_name);

    // nullptr when no rig has that id (and none can be recomputed). id: a content id or the
    // preset's.
    std::shared_ptr<const Environment> find(const std::string& id);

    // The map the rig was made from, decoded; nullptr when its source is no longer stored.
    std::shared_ptr<const HdrImage> source_image(const Environment& environment);

    // The rig's residual map prefiltered at default SpecularOptions: from memory, else from the
    // store (a damaged entry is logged, dropped and recomputed), else computed from
    // source_image() and the rig, stored and remembered; the preset's is made at start-up.
    // Concurrent calls for one rig compute it once (AssetRegistry): the later ones wait. nullptr
    // for a Thesis rig (no specular term), or when it must be computed and the source is no
    // longer stored.
    std::shared_ptr<const SpecularEnvironment> specular(const Environment& environment);

    // The uploaded environments (the preset is not listed) with ids after `after` ("" for the
    // first page), at most limit of them, by rig id; each with its map's id, size and format and
    // when its rig was stored.
    ListedPage list(std::string_view after, std::size_t limit);

    // Removes the uploaded environment id (a content id: the preset is not removed) and what
    // was derived from it: its rig, its record of provenance and its specular cube, in the store
    // and in memory, and its map too unless another rig was made from the same map. False when
    // no environment has that id. A crash part way leaves the environment whole (its rig and
    // cube are recomputed from its record and map) or gone (at worst its map stays, unlisted
    // and never served: the next upload of the same bytes uses it).
    bool remove(const std::string& id);

  private:
    // Whether a rig must be stored (an upload's, refused with StorageFull when the disk is
    // full) or is kept in memory when there is no room (one recomputed for a lookup).
    enum class Storing { Required, IfRoom };
    std::shared_ptr<const Environment> load_stored(const std::string& id);
    std::shared_ptr<const Environment> compute(const LoadedImage& loaded, const RigOptions& options,
                                               const std::string& source_id,
                                               const std::string& rig_id, Storing storing);
    void remember(const std::shared_ptr<const Environment>& environment);
    std::shared_ptr<const SpecularEnvironment> load_stored_specular(const std::string& id);
    std::shared_ptr<const SpecularEnvironment> compute_specular(const Environment& environment);
    // prefilter_specular, counted in the metrics and logged with its time and size.
    std::shared_ptr<const SpecularEnvironment> prefilter_timed(const HdrImage& image,
                                                               const Environment& environment);
    std::shared_ptr<const Environment> preprocess(
        std::string_view bytes, const std::string& extension, const RigOptions& options,
        const std::string& source_id, const std::string& rig_id, const std::string& file_name);
    // Whether the record of a rig other than rig_id names source_id as its map.
    bool map_used_by_another_rig(const std::string& source_id, const std::string& rig_id);

    AssetStore& store_;
    ServiceMetrics& metrics_;
    UploadBudget& budget_;
    const Log log_;
    const ImageLimits limits_;
    std::shared_ptr<const HdrImage> preset_image_;
    std::once_flag preset_specular_once_;
    std::shared_ptr<const SpecularEnvironment> preset_specular_;
    AssetRegistry<Environment> rigs_;
    SharedLruCache<HdrImage> images_;
    AssetRegistry<SpecularEnvironment> specular_;
};

}  // namespace oer::server
