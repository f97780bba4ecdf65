#include "oer/server/service.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <sstream>
#include <thread>

#include <httplib.h>

#include "access_log.hpp"
#include "bounded_http_server.hpp"
#include "client_work_budget.hpp"
#include "environment_registry.hpp"
#include "frame_service.hpp"
#include "http_exchange.hpp"
#include "job_service.hpp"
#include "job_store.hpp"
#include "listen_backlog.hpp"
#include "mesh_registry.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/version.hpp"
#include "oer/core/error.hpp"
#include "oer/core/size_text.hpp"
#include "oer/server/asset_store.hpp"
#include "oer/server/byte_lru_cache.hpp"
#include "oer/server/metrics.hpp"
#include "redis_frame_queue.hpp"
#include "render_pool.hpp"
#include "request_state.hpp"
#include "router.hpp"
#include "service_context.hpp"
#include "service_metrics.hpp"
#include "transfer_registry.hpp"
#include "upload_budget.hpp"

namespace oer::server {

namespace {

// Decoded maps and meshes held in memory, beside the frame cache: enough for a few large maps
// so that a dressing room switching between them keeps them warm.
constexpr std::size_t kAssetCacheBytes = 1ull << 30;
// Scenes' transfers: about 800 bytes a vertex with one bounce (order 7: 49 direct and 147
// bounce floats), so a few bunny-sized scenes and many small products.
constexpr std::size_t kTransferCacheBytes = 256ull << 20;

// The test frame every worker renders before the service reports ready: small, so start-up
// stays quick, yet through every pass (shadows, ground, background).
constexpr int kTestFrameSize = 64;

// Room for a request's line and headers beside its body.
constexpr std::size_t kMaxHeaderBytes = 64 << 10;

// The admin listener's threads: probes and scrapes are few and quick.
constexpr int kAdminThreads = 4;

// How long a render beyond the workers and the queue waits for a place before its 503
// (render_pool.hpp says why it waits): a client retrying at once then costs two requests a
// second, not thousands, and a place freed meanwhile is taken.
constexpr std::chrono::milliseconds kRenderAdmissionWait(500);
// At most this share of the HTTP threads waits so; the others stay free for everything else.
constexpr int kRenderAdmissionThreadShare = 2;  // one half

}  // namespace

struct Service::Impl {
    Impl(ServiceConfig config_, std::function<void(std::string_view)> log_)
        : config(std::move(config_)),
          log(std::move(log_)),
          store(config.data_dir, log),
          metrics(registry),
          uploads(UploadBudgetLimits{config.upload_memory_bytes, config.max_concurrent_uploads,
                                     config.max_upload_expansion},
                  [this](int busy, std::uint64_t reserved) {
                      metrics.uploads_decoding.set(busy);
                      metrics.upload_reserved_bytes.set(double(reserved));
                  }),
          environments(store, metrics, uploads, log, ImageLimits{config.max_image_pixels, 32768},
                       kAssetCacheBytes),
          meshes(store, metrics, uploads, mesh_limits(config), kAssetCacheBytes / 2),
          transfers(store, metrics, log, kTransferCacheBytes, double(config.transfer_ray_budget),
                    config.transfer_store_bytes),
          jobs_store(config.data_dir, log),
          frames(config.frame_cache_bytes),
          client_work(config.client_render_rate, double(config.max_render_seconds)) {
        render_limits.max_width = config.max_frame_width;
        render_limits.max_height = config.max_frame_height;
    }

    static MeshLimits mesh_limits(const ServiceConfig& config) {
        MeshLimits limits;
        limits.max_bytes = config.max_upload_bytes;
        limits.max_triangles = config.max_triangles;
        return limits;
    }

    void start();
    void stop();
    // Starts the render workers with the test frame; on failure, logs why and keeps trying
    // every kRendererRetrySeconds on a thread of its own until it succeeds or the service
    // stops, renders answering 503 meanwhile.
    void start_renderer();
    void retry_renderer(FrameRequest test_frame);
    // Starts the interactive workers, then the batch jobs' worker, each with the test frame.
    void start_pools(const FrameRequest& test_frame);
    // The queue of batch jobs' frames: --queue's, or this process's own.
    std::unique_ptr<FrameQueue> job_queue();
    // One HTTP listener: its server, its routes, the thread its accept loop runs on.
    struct Listener {
        std::unique_ptr<BoundedHttpServer> http;
        std::unique_ptr<Router> routes;
        std::thread thread;
        int port = -1;
    };
    Listener make_listener(const ConnectionLimits& limits, std::size_t threads);
    void configure_server(httplib::Server& http, const Router& routes, std::size_t threads);
    // Binds the listener to host:port (0: any free port) and serves it from its thread.
    void listen(Listener& listener, int port);
    FrameRequest test_frame_request();

    const ServiceConfig config;
    const std::function<void(std::string_view)> log;
    AssetStore store;
    MetricsRegistry registry;
    ServiceMetrics metrics;
    UploadBudget uploads;
    EnvironmentRegistry environments;
    MeshRegistry meshes;
    TransferRegistry transfers;
    JobStore jobs_store;
    ByteLruCache frames;
    ClientWorkBudget client_work;
    api::RenderLimits render_limits;

    std::unique_ptr<RenderPool> pool;
    std::unique_ptr<RenderPool> batch_pool;  // batch jobs' frames, below the interactive ones
    std::unique_ptr<FrameService> frame_service;
    std::unique_ptr<JobService> jobs;
    Listener api;
    Listener admin;  // no http when config.admin_port < 0
    std::unique_ptr<ServiceContext> context;

    std::thread renderer_retries;
    std::mutex stopping_mutex;
    std::condition_variable stopping_changed;
    bool stopping = false;
};

// The renderer's test frame. Warm (config.warm_default_scene): the default scene (the preset
// environment and product, untransformed, on the ground, with occlusion and one bounce), whose
// transfer is the default frame's and whose product is glossy, so that making this frame
// spares the first user frame the bake and the studio's prefilter. Otherwise a matte copy of
// the default product without occlusion, which needs neither.
FrameRequest Service::Impl::test_frame_request() {
    const std::string preset(api::kDefaultPresetId);
    const auto environment = environments.find(preset);
    FrameRequest request;
    request.rig = environment->rig;
    request.environment_map = environments.source_image(*environment);
    std::shared_ptr<const Mesh> product = meshes.find(preset)->mesh;
    if (config.warm_default_scene) {
        request.specular = environments.specular(*environment);
    } else {
        auto matte = std::make_shared<Mesh>(*product);
        for (Material& material : matte->materials) {
            material.model = ShadingModel::Lambertian;
        }
        product = std::move(matte);
    }
    request.objects.push_back({product, glm::mat4(1.0f), std::nullopt});
    request.occlusion = config.warm_default_scene;
    if (request.occlusion) {
        request.transfer = transfers.transfer(request, {preset});
    }
    request.width = kTestFrameSize;
    request.height = kTestFrameSize;
    request.samples = 1;
    request.shadows.resolution = 256;
    return request;
}

void Service::Impl::start() {
    if (api.http) {
        throw Error(ErrorKind::Internal, "Service::start: already started");
    }
    FrameLimits frame_limits;
    frame_limits.max_width = config.max_frame_width;
    frame_limits.max_height = config.max_frame_height;
    pool = std::make_unique<RenderPool>(
        config.render_workers, config.max_queue_depth, frame_limits,
        [this](std::size_t waiting) { metrics.render_queue_depth.set(double(waiting)); },
        RenderAdmission{kRenderAdmissionWait, std::size_t(std::max(config.http_threads, 1) /
                                                          kRenderAdmissionThreadShare)});
    // One worker with one frame waiting: a job's runner submits one frame at a time.
    batch_pool = std::make_unique<RenderPool>(1, 1, frame_limits, RenderPool::DepthObserver{},
                                              RenderAdmission{}, kBatchNice);
    frame_service = std::make_unique<FrameService>(
        environments, meshes, transfers, *pool, *batch_pool, frames, metrics,
        std::chrono::seconds(config.request_timeout_seconds),
        RenderBudgets{config.max_render_memory_bytes, double(config.max_render_seconds),
                      config.max_transfer_bytes},
        double(config.transfer_ray_budget), client_work, log);
    start_renderer();
    jobs = std::make_unique<JobService>(
        jobs_store, *frame_service, job_queue(), render_limits,
        JobBounds{api::JobLimits{config.job_max_frames, config.job_max_pixels},
                  config.client_job_frames, config.client_job_pixels},
        std::chrono::hours(config.job_retention_hours), metrics, log);

    const std::size_t max_body =
        std::max<std::size_t>(config.max_upload_bytes, render_limits.max_body_bytes);
    ConnectionLimits limits;
    limits.request_bytes = max_body + kMaxHeaderBytes;
    limits.read_deadline = std::chrono::seconds(config.request_timeout_seconds);
    limits.header_deadline = std::chrono::seconds(config.header_timeout_seconds);
    limits.max_connections_per_client = std::size_t(config.max_connections_per_client);
    api = make_listener(limits, std::size_t(std::max(config.http_threads, 1)));
    context = std::make_unique<ServiceContext>(
        ServiceContext{config, render_limits, metrics, environments, meshes, transfers, frames,
                       *pool, *frame_service, *jobs, log});
    add_environment_routes(*api.routes, *context);
    add_mesh_routes(*api.routes, *context);
    add_render_routes(*api.routes, *context);
    add_hotspot_routes(*api.routes, *context);
    add_job_routes(*api.routes, *context);
    add_service_routes(*api.routes, *context);
    add_web_routes(*api.routes);
    if (config.admin_port >= 0) {
        // Probes carry no body: the headers' room is all a request needs.
        ConnectionLimits admin_limits = limits;
        admin_limits.request_bytes = kMaxHeaderBytes;
        admin_limits.max_connections_per_client = 0;
        admin = make_listener(admin_limits, kAdminThreads);
        add_probe_routes(*admin.routes, *context);
    }

    listen(api, config.port);
    if (admin.http) {
        listen(admin, config.admin_port);
    }
}

void Service::Impl::start_renderer() {
    FrameRequest test_frame = test_frame_request();
    try {
        start_pools(test_frame);
    } catch (const std::exception& error) {
        log(std::string("error: the renderer could not start: ") + error.what() +
            "; renders answer 503 and /readyz is false until it does; trying again every " +
            std::to_string(kRendererRetrySeconds) + " s");
        renderer_retries =
            std::thread([this, test_frame = std::move(test_frame)] { retry_renderer(test_frame); });
    }
}

std::unique_ptr<FrameQueue> Service::Impl::job_queue() {
    if (config.queue.empty()) {
        return std::make_unique<LocalFrameQueue>();
    }
    // This replica's name among the queue's consumers: its host (a pod's name) and process.
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    auto queue = std::make_unique<RedisFrameQueue>(
        config.queue, std::string(host) + "-" + std::to_string(::getpid()));
    log("jobs: frames shared through the queue at " + config.queue);
    return queue;
}

void Service::Impl::start_pools(const FrameRequest& test_frame) {
    const RenderPool::Job test = [&test_frame](FrameRenderer& renderer) {
        return renderer.render(test_frame);
    };
    pool->start(test);
    batch_pool->start(test);
    metrics.render_workers_ready.set(pool->worker_count());
}

void Service::Impl::retry_renderer(FrameRequest test_frame) {
    std::string last_failure = pool->failure();
    for (int attempt = 2;; ++attempt) {
        {
            std::unique_lock lock(stopping_mutex);
            if (stopping_changed.wait_for(lock, std::chrono::seconds(kRendererRetrySeconds),
                                          [this] { return stopping; })) {
                return;
            }
        }
        try {
            start_pools(test_frame);
            log("the renderer started at attempt " + std::to_string(attempt));
            return;
        } catch (const std::exception& error) {
            // Each new cause once, not one line every few seconds.
            if (error.what() != last_failure) {
                last_failure = error.what();
                log("error: the renderer could not start (attempt " + std::to_string(attempt) +
                    "): " + last_failure);
            }
        }
    }
}

Service::Impl::Listener Service::Impl::make_listener(const ConnectionLimits& limits,
                                                     std::size_t threads) {
    Listener listener;
    listener.http = std::make_unique<BoundedHttpServer>(
        limits, [this](const std::string&) { metrics.connections_refused.increment(); });
    listener.routes = std::make_unique<Router>(*listener.http, log,
                                               RouterPolicies{config.api_key, config.cors_origins});
    configure_server(*listener.http, *listener.routes, threads);
    return listener;
}

void Service::Impl::listen(Listener& listener, int wanted_port) {
    httplib::Server& http = *listener.http;
    const int bound = wanted_port == 0
                          ? http.bind_to_any_port(config.host)
                          : (http.bind_to_port(config.host, wanted_port) ? wanted_port : -1);
    if (bound < 0) {
        // bind(2)'s own reason, which the HTTP library keeps in errno ("Address already in
        // use": another server has the port).
        const std::string reason = std::strerror(errno);
        const std::string where = config.host + ":" + std::to_string(wanted_port);
        stop();
        throw Error(ErrorKind::Io, "cannot listen on " + where + ": " + reason);
    }
    if (!widen_listen_backlog(bound)) {
        log("warning: the listen backlog of port " + std::to_string(bound) +
            " stays at cpp-httplib's 5 (its socket was not found)");
    }
    listener.port = bound;
    listener.thread = std::thread([&http] { http.listen_after_bind(); });
    // cpp-httplib's stop() does nothing until the listening loop has begun, so a service stopped
    // right after it started would wait on that loop for ever. Listening returns once it runs.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!http.is_running()) {
        if (std::chrono::steady_clock::now() > deadline) {
            stop();
            throw Error(ErrorKind::Internal, "the HTTP listener did not start within 10 s");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

void Service::Impl::configure_server(httplib::Server& http, const Router& routes,
                                     std::size_t threads) {
    http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    // SO_REUSEADDR alone, not cpp-httplib's SO_REUSEPORT: with it a second server started on a
    // port in use bound it too, and the kernel split the connections between two processes
    // (and two data folders). SO_REUSEADDR still lets a restart take the port while the last
    // run's connections linger in TIME_WAIT.
    http.set_socket_options([](socket_t sock) {
        const int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    // The largest body any route reads; each route bounds its own below that.
    http.set_payload_max_length(
        std::max<std::size_t>(config.max_upload_bytes, render_limits.max_body_bytes));
    // A sender that pauses longer than the idle timeout mid-request is dropped, so that slow
    // clients cannot hold the HTTP threads.
    http.set_read_timeout(config.idle_timeout_seconds);
    http.set_write_timeout(config.request_timeout_seconds);
    http.set_keep_alive_timeout(config.idle_timeout_seconds);
    // Headers and body leave in separate writes: without TCP_NODELAY, Nagle's algorithm holds
    // the body until the client's delayed ACK (about 40 ms on Linux), even for a cached frame.
    http.set_tcp_nodelay(true);
    http.set_keep_alive_max_count(std::size_t(std::max(config.keep_alive_max_count, 1)));

    http.set_pre_routing_handler(
        [&routes](const httplib::Request& request, httplib::Response& response) {
            // A new request's state, on the connection BoundedHttpServer set (its socket).
            RequestState& state = current_request();
            const int socket = state.socket;
            state = RequestState{};
            state.socket = socket;
            state.start = std::chrono::steady_clock::now();
            return routes.before_routing(request, response);
        });

    // Answers that cpp-httplib makes itself (no route, a malformed request) and routes that
    // set a status without a body become problem+json too.
    http.set_error_handler(httplib::Server::HandlerWithResponse([&routes](
                                                                    const httplib::Request& request,
                                                                    httplib::Response& response) {
        if (!response.body.empty()) {
            return httplib::Server::HandlerResponse::Unhandled;
        }
        if (response.status == 404 && current_request().route == "unmatched") {
            const std::vector<std::string> methods = routes.methods_for(request.path);
            if (methods.empty()) {
                send_problem(
                    response,
                    {problem(ProblemKind::NotFound, "no route has this path"), {}, false, ""});
            } else {
                std::string allow;
                for (const std::string& method : methods) {
                    allow += (allow.empty() ? "" : ", ") + method;
                }
                send_problem(response,
                             {problem(ProblemKind::MethodNotAllowed, "this path allows " + allow),
                              {{"Allow", allow}},
                              false,
                              ""});
            }
        } else if (response.status == 413) {
            send_problem(response, {problem(ProblemKind::LimitExceeded,
                                            "the body is over the server's limit"),
                                    {},
                                    false,
                                    ""});
        } else if (response.status == 414 ||
                   current_request().oversized_line == OversizedLine::HeaderLine) {
            // A line over the limits: cpp-httplib's own 414, or the 400 it answers when the
            // connection's stream stopped reading a header line (bounded_http_server.hpp).
            // The rest of the request is unread, so the connection closes.
            const bool request_line = response.status == 414;
            current_request().close_connection = true;
            send_problem(
                response,
                {problem(request_line ? ProblemKind::UriTooLong : ProblemKind::HeaderFieldsTooLarge,
                         request_line ? request_line_too_long() : header_line_too_long()),
                 {{"Connection", "close"}},
                 false,
                 ""});
        } else {
            // Other statuses cpp-httplib answers with mean a malformed request.
            send_problem(response, {problem(ProblemKind::MalformedRequest,
                                            "the request could not be read (HTTP " +
                                                std::to_string(response.status) + ")"),
                                    {},
                                    false,
                                    ""});
        }
        return httplib::Server::HandlerResponse::Handled;
    }));

    http.set_exception_handler([this](const httplib::Request& request, httplib::Response& response,
                                      std::exception_ptr error) {
        const ErrorAnswer answer = error_answer(error);
        if (answer.internal) {
            log("error: " + request.method + " " + current_request().route + ": " + answer.cause);
        }
        send_problem(response, answer);
    });

    http.set_post_routing_handler([](const httplib::Request&, httplib::Response& response) {
        if (current_request().close_connection) {
            response.set_header("Connection", "close");
        }
    });

    http.set_logger([this](const httplib::Request& request, const httplib::Response& response) {
        RequestState& state = current_request();
        const auto now = std::chrono::steady_clock::now();
        const double seconds = state.start == std::chrono::steady_clock::time_point{}
                                   ? 0.0
                                   : std::chrono::duration<double>(now - state.start).count();
        metrics.request(state.route, method_label(request.method), response.status, seconds);
        if (config.access_log) {
            log(access_log_line(request.method, request.target, response.status,
                                response.body.size(), seconds * 1000.0));
        }
    });
}

void Service::Impl::stop() {
    {
        const std::lock_guard lock(stopping_mutex);
        stopping = true;
    }
    stopping_changed.notify_all();
    if (renderer_retries.joinable()) {
        renderer_retries.join();
    }
    for (Listener* listener : {&api, &admin}) {
        if (listener->http) {
            listener->http->stop();
        }
        if (listener->thread.joinable()) {
            listener->thread.join();
        }
    }
    context.reset();
    api = Listener{};
    admin = Listener{};
    // Before the pools: its runner's frame in flight is stopped, left to the next start.
    jobs.reset();
    // The pool first: a frame whose client timed out may still be running, and its job uses
    // the frame service.
    pool.reset();
    batch_pool.reset();
    frame_service.reset();
    metrics.render_workers_ready.set(0);
}

Service::Service(ServiceConfig config, std::function<void(std::string_view)> log)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(log))) {}

Service::~Service() {
    stop();
}

void Service::start() {
    impl_->start();
}

void Service::stop() {
    impl_->stop();
}

int Service::port() const {
    return impl_->api.port;
}

int Service::admin_port() const {
    return impl_->admin.port;
}

std::string Service::url() const {
    return "http://" + impl_->config.host + ":" + std::to_string(impl_->api.port);
}

std::string Service::banner() const {
    const ServiceConfig& c = impl_->config;
    std::ostringstream text;
    text << "oer-server " << api::kVersion << " listening on " << url() << "\n";
    if (const GlInfo* gl = impl_->pool ? impl_->pool->info() : nullptr) {
        text << "  renderer: " << gl->vendor << ", " << gl->renderer << ", OpenGL " << gl->version
             << " (" << gl->platform << "), " << impl_->pool->worker_count() << " worker(s)\n";
    } else {
        text << "  renderer: not running (" << (impl_->pool ? impl_->pool->failure() : "")
             << "); renders answer 503 until it starts\n";
    }
    if (impl_->admin.port >= 0) {
        text << "  admin listener (/healthz, /readyz, /metrics): http://" << c.host << ":"
             << impl_->admin.port << "\n";
    }
    text << "  data folder: " << c.data_dir.string() << "\n";
    text << "  limits: upload " << mebibytes(c.max_upload_bytes) << ", image " << c.max_image_pixels
         << " pixels, " << c.max_triangles << " triangles, frame " << c.max_frame_width << "x"
         << c.max_frame_height << ", queue " << c.max_queue_depth << ", request timeout "
         << c.request_timeout_seconds << " s, header timeout " << c.header_timeout_seconds
         << " s, idle timeout " << c.idle_timeout_seconds << " s, keep-alive "
         << c.keep_alive_max_count << " requests, " << c.http_threads << " HTTP threads, "
         << c.max_connections_per_client << " connections per client (0: any), frame cache "
         << mebibytes(c.frame_cache_bytes) << "\n";
    text << "  uploads: " << (c.api_key.empty() ? "open (no API key)" : "need the API key")
         << "; CORS origins: ";
    if (c.cors_origins.empty()) {
        text << "none";
    }
    for (std::size_t i = 0; i < c.cors_origins.size(); ++i) {
        text << (i ? ", " : "") << c.cors_origins[i];
    }
    // Last, so that scripts/run.sh ends with the page to open.
    text << "\n  open the dressing room: " << url() << "/";
    return text.str();
}

}  // namespace oer::server
