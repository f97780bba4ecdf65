#pragma once
// The service's configuration from command-line flags and environment variables. Every flag
// --name is also the variable OER_NAME (upper case, dashes as underscores), so a container
// can be configured without a command line; a flag wins over its variable. One table of
// options in service_config.cpp drives parsing (CLI11 reads the command line, the table's own
// parsers check each value), the defaults and the --help text (a CLI11 formatter).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace oer::server {

struct ServiceConfig {
    std::string host = "127.0.0.1";
    int port = 8080;  // 0: the system picks a free port
    // The admin listener (same host): /healthz, /readyz and /metrics only, on threads of their
    // own, so that probes and scrapes never queue behind client traffic (as Envoy's admin
    // port). -1: none; 0: the system picks a free port.
    int admin_port = -1;
    std::filesystem::path data_dir = "./oer-data";
    std::string api_key;                    // empty: no key required
    std::vector<std::string> cors_origins;  // empty: no CORS headers; "*" allows any origin
    std::uint64_t max_upload_bytes = 256ull << 20;
    // A real 8k equirectangular map, 8192 x 4096 (384 MiB as the loaded float image); more with
    // --max-image-pixels.
    std::uint64_t max_image_pixels = 8192ull * 4096;
    std::uint64_t max_triangles = 5'000'000;
    // Uploads decoded and preprocessed at once, the memory they may hold together (estimated
    // before decoding: upload_budget.hpp), and how many times its own size one upload may
    // expand to (0: any). Over the first two: 503 with Retry-After; over the last: 413.
    int max_concurrent_uploads = 2;
    std::uint64_t upload_memory_bytes = 2ull << 30;
    std::uint64_t max_upload_expansion = 200;
    int max_frame_width = 4096;
    int max_frame_height = 4096;
    // Render requests waiting for a worker; more wait up to 0.5 s for a place, then are
    // answered 503 (render_pool.hpp).
    int max_queue_depth = 16;
    int render_workers = 1;
    int request_timeout_seconds = 30;
    int idle_timeout_seconds = 5;  // keep-alive connections idle longer are closed
    // From a request's first byte to the end of its headers (slowloris: a client that sends
    // its headers a byte at a time holds a thread at most this long). Bodies keep the longer
    // request timeout, and the idle timeout between two reads.
    int header_timeout_seconds = 5;
    int keep_alive_max_count = 100;
    // A connection holds a thread for its whole life, idle keep-alive time included; an idle
    // thread costs a few pages of stack, so there are many. Slow and idle clients of one
    // address hold at most max_connections_per_client of them, which leaves the rest to
    // everyone else (tests/integration/slow_clients_test.cpp measures it).
    int http_threads = 256;
    // Connections one client address may hold at once; more are answered 429 and closed.
    // 0: no limit (behind a proxy, whose address every connection has, and which limits
    // clients itself: docker/README.md).
    int max_connections_per_client = 64;
    std::uint64_t frame_cache_bytes = 256ull << 20;  // 0: no frame cache
    // Rays per phase of a scene's transfer bake, shared by its points (transfer_bake.hpp's
    // kTransferRayBudget: the bunny in under 2 s on 2 cores with one bounce).
    std::uint64_t transfer_ray_budget = 6'000'000;
    // A render's estimated cost before any of it runs (render_cost.hpp): its peak memory, its
    // time on the slowest renderer the service runs on, and the stored size of its occlusion
    // transfer. Over any: 413, naming the estimate and the budget.
    std::uint64_t max_render_memory_bytes = 2ull << 30;
    int max_render_seconds = 30;
    std::uint64_t max_transfer_bytes = 64ull << 20;
    // The stored transfers together (transfer_registry.hpp): past it, the least recently used
    // are removed (they are baked again when a frame needs them).
    std::uint64_t transfer_store_bytes = 1ull << 30;
    // Each client address's share of uncached rendering: the seconds of render work it earns a
    // second, saved up to max_render_seconds, each uncached frame costing the work it took
    // (client_work_budget.hpp); past it, 429 with Retry-After. 0: no per-client limit (behind
    // a proxy that shares out its own clients).
    double client_render_rate = 1.0;
    // Batch jobs (docs/jobs.md): the frames and pixels of one job (413 past them), and of a
    // client's unfinished jobs together (429).
    std::size_t job_max_frames = 1000;
    std::uint64_t job_max_pixels = 256ull << 20;
    std::size_t client_job_frames = 2000;
    std::uint64_t client_job_pixels = 512ull << 20;
    // A settled job (done, failed, cancelled) whose files are unchanged this long is removed
    // from the data folder (job_service.hpp); 0: jobs are kept until their owner removes them.
    int job_retention_hours = 168;
    // The queue replicas share a job's frames through: "redis://HOST:PORT" (a Redis stream,
    // redis_frame_queue.hpp); empty: this process's own queue, its jobs in its own store.
    std::string queue;
    bool access_log = true;  // one line per request on stderr
    // Before the service is ready, the default scene's transfer is baked and the built-in
    // studio's reflection cube prefiltered (both by the renderer's test frame), so that the
    // dressing room's first frame waits for neither. Off: the test frame is a matte copy of the
    // default product without occlusion, and the first default frame makes both (a replica
    // that serves only uploads; the tests' servers, which start by the hundred).
    bool warm_default_scene = true;
};

// The value of an environment variable, or nullopt when it is not set. Tests pass a map's
// lookup; the service passes process_environment.
using EnvironmentLookup = std::function<std::optional<std::string>(const std::string& name)>;
std::optional<std::string> process_environment(const std::string& name);

// "data-dir" -> "OER_DATA_DIR".
std::string environment_variable_of(const std::string& flag);

struct ServiceCommandLine {
    bool help = false;  // --help (or -h) was given: print service_help_text() and exit
    ServiceConfig config;
};

// arguments: argv without the program name; "--name value" or "--name=value", the last one
// given counts. Unknown flags, missing values and invalid values (from a flag or a variable)
// throw oer::api::InvalidParameter naming the flag or the variable and the problem, e.g.
// --port: expected an integer 0..65535, got "abc"
ServiceCommandLine parse_service_command_line(const std::vector<std::string>& arguments,
                                              const EnvironmentLookup& environment);

// Usage, then every option with its value, meaning, variable and default.
std::string service_help_text();

}  // namespace oer::server
