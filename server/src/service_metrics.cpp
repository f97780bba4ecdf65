#include "service_metrics.hpp"

namespace oer::server {

namespace {

constexpr const char* kRequestsHelp = "HTTP requests answered, by route pattern, method and status";
constexpr const char* kRequestSecondsHelp = "Time to answer an HTTP request, by route pattern";
constexpr const char* kHitsHelp = "Cache hits, by cache";
constexpr const char* kMissesHelp = "Cache misses, by cache";
constexpr const char* kInProgressHelp =
    "Computations running now: rigs (a map decoded and preprocessed), specular cubes, scene "
    "transfers";

const char* name_of(CacheName cache) {
    switch (cache) {
        case CacheName::Frame:
            return "frame";
        case CacheName::Rig:
            return "rig";
        case CacheName::Mesh:
            return "mesh";
        case CacheName::Environment:
            return "environment";
        case CacheName::Specular:
            return "specular";
        case CacheName::Transfer:
            return "transfer";
    }
    return "unknown";
}

}  // namespace

ServiceMetrics::ServiceMetrics(MetricsRegistry& registry)
    : render_seconds(registry.histogram(
          "oer_render_seconds", "GL time of one frame on a render worker", kLatencyBucketsSeconds)),
      renders_skipped(registry.counter("oer_renders_skipped_total",
                                       "Frames not started because their request had stopped "
                                       "waiting (its deadline passed or its client went)")),
      renders_stopped(registry.counter("oer_renders_stopped_total",
                                       "Frames (and their transfer bakes) stopped part way because "
                                       "their request had stopped waiting")),
      job_frames_stored(registry.counter(
          "oer_job_frames_stored_total",
          "Batch jobs' frames rendered (or taken from the frame cache) and stored")),
      job_frames_skipped(registry.counter(
          "oer_job_frames_skipped_total",
          "Batch jobs' queued frames found stored already, and not rendered again")),
      batch_frames_yielded(registry.counter(
          "oer_batch_frames_yielded_total",
          "Batch jobs' frames stopped part way to let interactive frames go first, and started "
          "again")),
      preprocess_seconds(registry.histogram("oer_preprocess_seconds",
                                            "Time to decode an environment and build its rig",
                                            kLatencyBucketsSeconds)),
      rigs_computed(registry.counter("oer_rigs_computed_total",
                                     "Rigs computed (preprocessing runs; cache hits excluded)")),
      specular_seconds(registry.histogram(
          "oer_specular_seconds", "Time to prefilter a rig's residual map into its specular cube",
          kLatencyBucketsSeconds)),
      specular_computed(registry.counter(
          "oer_specular_computed_total",
          "Specular cubes computed (prefiltering runs; memory and store hits excluded)")),
      transfer_seconds(registry.histogram(
          "oer_transfer_seconds",
          "Time to bake a scene's transfer (occlusion and one bounce of the residual map)",
          kLatencyBucketsSeconds)),
      transfers_computed(
          registry.counter("oer_transfers_computed_total",
                           "Scene transfers baked (bake runs; memory and store hits excluded)")),
      transfers_evicted(registry.counter(
          "oer_transfers_evicted_total",
          "Stored transfers removed, least recently used first, over --transfer-store-bytes")),
      transfer_store_bytes(registry.gauge("oer_transfer_store_bytes",
                                          "Bytes of the stored transfers this process knows of")),
      meshes_loaded(
          registry.counter("oer_meshes_loaded_total",
                           "Meshes decoded from uploads or from the store (cache hits excluded)")),
      rigs_in_progress(registry.gauge("oer_computations_in_progress", kInProgressHelp,
                                      {{"computation", "rig"}})),
      specular_in_progress(registry.gauge("oer_computations_in_progress", kInProgressHelp,
                                          {{"computation", "specular"}})),
      transfers_in_progress(registry.gauge("oer_computations_in_progress", kInProgressHelp,
                                           {{"computation", "transfer"}})),
      render_queue_depth(
          registry.gauge("oer_render_queue_depth", "Frames waiting for a render worker")),
      render_workers_ready(registry.gauge(
          "oer_render_workers_ready", "Render workers with a GL context and a test frame done")),
      uploads_decoding(registry.gauge(
          "oer_uploads_decoding", "Uploads being decoded and preprocessed (upload budget slots)")),
      upload_reserved_bytes(registry.gauge(
          "oer_upload_reserved_bytes", "Memory reserved by the uploads being decoded, in bytes")),
      connections_refused(registry.counter(
          "oer_http_connections_refused_total",
          "Connections answered 429 because their client address held as many as it may")),
      registry_(registry) {
    for (const CacheName cache :
         {CacheName::Frame, CacheName::Rig, CacheName::Mesh, CacheName::Environment,
          CacheName::Specular, CacheName::Transfer}) {
        registry.counter("oer_cache_hits_total", kHitsHelp, {{"cache", name_of(cache)}});
        registry.counter("oer_cache_misses_total", kMissesHelp, {{"cache", name_of(cache)}});
    }
}

void ServiceMetrics::request(const std::string& route, const std::string& method, int status,
                             double seconds) {
    registry_
        .counter("oer_http_requests_total", kRequestsHelp,
                 {{"route", route}, {"method", method}, {"status", std::to_string(status)}})
        .increment();
    registry_
        .histogram("oer_http_request_seconds", kRequestSecondsHelp, kLatencyBucketsSeconds,
                   {{"route", route}})
        .observe(seconds);
}

void ServiceMetrics::cache(CacheName cache, bool hit) {
    registry_
        .counter(hit ? "oer_cache_hits_total" : "oer_cache_misses_total",
                 hit ? kHitsHelp : kMissesHelp, {{"cache", name_of(cache)}})
        .increment();
}

}  // namespace oer::server
