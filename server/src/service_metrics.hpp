#pragma once
// The service's metric families, by their fixed names (the integration tests and dashboards
// rely on them), registered at start-up so that every one appears in /metrics from the first
// scrape. No label carries an asset id: series stay few however many assets are uploaded.
#include <string>

#include "oer/server/metrics.hpp"

namespace oer::server {

// Counts one computation in progress on a gauge for as long as it lives.
class InProgress {
  public:
    explicit InProgress(Gauge& gauge) : gauge_(gauge) { gauge_.add(1.0); }
    ~InProgress() { gauge_.add(-1.0); }
    InProgress(const InProgress&) = delete;
    InProgress& operator=(const InProgress&) = delete;

  private:
    Gauge& gauge_;
};

// The caches whose hits and misses are counted.
enum class CacheName { Frame, Rig, Mesh, Environment, Specular, Transfer };

class ServiceMetrics {
  public:
    explicit ServiceMetrics(MetricsRegistry& registry);

    MetricsRegistry& registry() { return registry_; }

    // One request answered: route is the route's pattern ("/v1/environments/{id}", or
    // "unmatched"), status the HTTP status.
    void request(const std::string& route, const std::string& method, int status, double seconds);
    void cache(CacheName cache, bool hit);

    Histogram& render_seconds;  // GL time of one frame
    // Frames a worker skipped, or stopped part way, because their request had stopped waiting
    // (its deadline passed or its client went).
    Counter& renders_skipped;
    Counter& renders_stopped;
    // Batch jobs' frames (job_service.hpp): rendered (or taken from the frame cache) and stored,
    // and queued frames found stored already (by another replica, or before a restart).
    Counter& job_frames_stored;
    Counter& job_frames_skipped;
    Counter& batch_frames_yielded;  // batch frames stopped to let interactive frames go first
    Histogram& preprocess_seconds;  // decoding a map and building its rig
    Counter& rigs_computed;         // each rig actually computed, never a cache hit
    Histogram& specular_seconds;    // prefiltering a rig's residual map (specular cube)
    Counter& specular_computed;     // each specular cube actually computed, never a hit
    Histogram& transfer_seconds;    // baking a scene's transfer
    Counter& transfers_computed;    // each transfer actually baked, never a memory or store hit
    Counter& transfers_evicted;     // stored transfers removed over the store's quota
    Gauge& transfer_store_bytes;    // the stored transfers this process knows of
    Counter& meshes_loaded;         // each mesh actually decoded (upload or store), never a hit
    // Computations running now (an operator sees what a slow request waits for; a test sees
    // the moment one is under way): rigs (decoding the map and preprocessing it), specular
    // cubes, scene transfers.
    Gauge& rigs_in_progress;
    Gauge& specular_in_progress;
    Gauge& transfers_in_progress;
    Gauge& render_queue_depth;     // frames waiting for a render worker
    Gauge& render_workers_ready;   // workers with a GL context that rendered a test frame
    Gauge& uploads_decoding;       // uploads holding a slot of the upload budget
    Gauge& upload_reserved_bytes;  // memory they reserved
    // Connections answered 429 because their address held max_connections_per_client.
    Counter& connections_refused;

  private:
    MetricsRegistry& registry_;
};

}  // namespace oer::server
