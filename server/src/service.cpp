#include "oer/server/service.hpp"

#include <atomic>
#include <chrono>
#include <sstream>
#include <thread>

#include <httplib.h>

#include "access_log.hpp"
#include "bounded_http_server.hpp"
#include "cors.hpp"
#include "environment_registry.hpp"
#include "frame_service.hpp"
#include "http_exchange.hpp"
#include "listen_backlog.hpp"
#include "mesh_registry.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/version.hpp"
#include "oer/core/error.hpp"
#include "oer/server/asset_store.hpp"
#include "oer/server/byte_lru_cache.hpp"
#include "oer/server/metrics.hpp"
#include "render_pool.hpp"
#include "request_state.hpp"
#include "router.hpp"
#include "service_context.hpp"
#include "service_metrics.hpp"
#include "transfer_registry.hpp"

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

std::string mebibytes(std::uint64_t bytes) {
    std::ostringstream text;
    text << double(bytes) / double(1 << 20) << " MiB";
    return text.str();
}

}  // namespace

struct Service::Impl {
    Impl(ServiceConfig config_, std::function<void(std::string_view)> log_)
        : config(std::move(config_)),
          log(std::move(log_)),
          store(config.data_dir, log),
          metrics(registry),
          environments(store, metrics, log, ImageLimits{config.max_image_pixels, 32768},
                       kAssetCacheBytes),
          meshes(store, metrics, mesh_limits(config), kAssetCacheBytes / 2),
          transfers(store, metrics, log, kTransferCacheBytes, double(config.transfer_ray_budget)),
          frames(config.frame_cache_bytes) {
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
    void configure_server();
    FrameRequest test_frame_request();

    const ServiceConfig config;
    const std::function<void(std::string_view)> log;
    AssetStore store;
    MetricsRegistry registry;
    ServiceMetrics metrics;
    EnvironmentRegistry environments;
    MeshRegistry meshes;
    TransferRegistry transfers;
    ByteLruCache frames;
    api::RenderLimits render_limits;
    std::atomic<bool> ready{false};

    std::unique_ptr<RenderPool> pool;
    std::unique_ptr<FrameService> frame_service;
    std::unique_ptr<httplib::Server> server;
    std::unique_ptr<Router> router;
    std::unique_ptr<ServiceContext> context;
    std::thread listener;
    int port = -1;
};

// The default scene (the preset environment and product, untransformed, on the ground, with
// occlusion and one bounce): its transfer is the default frame's, so baking it here, before the
// service is ready, spares the first user frame the bake.
FrameRequest Service::Impl::test_frame_request() {
    const std::string preset(api::kDefaultPresetId);
    const auto environment = environments.find(preset);
    FrameRequest request;
    request.rig = environment->rig;
    request.environment_map = environments.source_image(*environment);
    request.specular = environments.specular(*environment);  // the default product is glossy
    request.objects.push_back({meshes.find(preset)->mesh, glm::mat4(1.0f), std::nullopt});
    request.occlusion = true;
    request.transfer = transfers.transfer(request, {preset});
    request.width = kTestFrameSize;
    request.height = kTestFrameSize;
    request.samples = 1;
    request.shadows.resolution = 256;
    return request;
}

void Service::Impl::start() {
    if (server) {
        throw Error(ErrorKind::Internal, "Service::start: already started");
    }
    FrameLimits frame_limits;
    frame_limits.max_width = config.max_frame_width;
    frame_limits.max_height = config.max_frame_height;
    pool = std::make_unique<RenderPool>(
        config.render_workers, config.max_queue_depth, frame_limits,
        [this](std::size_t waiting) { metrics.render_queue_depth.set(double(waiting)); });
    const FrameRequest test_frame = test_frame_request();
    pool->run_on_every_worker(
        [&test_frame](FrameRenderer& renderer) { return renderer.render(test_frame); });
    ready = true;
    metrics.render_workers_ready.set(pool->worker_count());

    frame_service =
        std::make_unique<FrameService>(environments, meshes, transfers, *pool, frames, metrics,
                                       std::chrono::seconds(config.request_timeout_seconds));
    const std::size_t max_body =
        std::max<std::size_t>(config.max_upload_bytes, render_limits.max_body_bytes);
    server = std::make_unique<BoundedHttpServer>(ConnectionLimits{
        max_body + kMaxHeaderBytes, std::chrono::seconds(config.request_timeout_seconds)});
    router = std::make_unique<Router>(*server, log);
    context = std::make_unique<ServiceContext>(ServiceContext{config, render_limits, metrics,
                                                              environments, meshes, frames, *pool,
                                                              *frame_service, ready, log});
    configure_server();
    add_environment_routes(*router, *context);
    add_mesh_routes(*router, *context);
    add_render_routes(*router, *context);
    add_service_routes(*router, *context);
    add_web_routes(*router);

    if (config.port == 0) {
        port = server->bind_to_any_port(config.host);
    } else {
        port = server->bind_to_port(config.host, config.port) ? config.port : -1;
    }
    if (port < 0) {
        const std::string where = config.host + ":" + std::to_string(config.port);
        stop();
        throw Error(ErrorKind::Io, "cannot listen on " + where);
    }
    if (!widen_listen_backlog(port)) {
        log("warning: the listen backlog stays at cpp-httplib's 5 (its socket was not found)");
    }
    listener = std::thread([this] { server->listen_after_bind(); });
    // cpp-httplib's stop() does nothing until the listening loop has begun, so a service stopped
    // right after it started would wait on that loop for ever. Start returns once it runs.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!server->is_running()) {
        if (std::chrono::steady_clock::now() > deadline) {
            stop();
            throw Error(ErrorKind::Internal, "the HTTP listener did not start within 10 s");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

void Service::Impl::configure_server() {
    const std::size_t threads = std::size_t(std::max(config.http_threads, 1));
    server->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    // The largest body any route reads; each route bounds its own below that.
    server->set_payload_max_length(
        std::max<std::size_t>(config.max_upload_bytes, render_limits.max_body_bytes));
    // A sender that pauses longer than the idle timeout mid-request is dropped, so that slow
    // clients cannot hold the HTTP threads.
    server->set_read_timeout(config.idle_timeout_seconds);
    server->set_write_timeout(config.request_timeout_seconds);
    server->set_keep_alive_timeout(config.idle_timeout_seconds);
    // Headers and body leave in separate writes: without TCP_NODELAY, Nagle's algorithm holds
    // the body until the client's delayed ACK (about 40 ms on Linux), even for a cached frame.
    server->set_tcp_nodelay(true);
    server->set_keep_alive_max_count(std::size_t(std::max(config.keep_alive_max_count, 1)));

    server->set_pre_routing_handler(
        [this](const httplib::Request& request, httplib::Response& response) {
            RequestState& state = current_request();
            state = RequestState{};
            state.start = std::chrono::steady_clock::now();
            add_cors_headers(config.cors_origins, request, response);
            if (request.method == "OPTIONS") {
                state.route = "preflight";
                answer_preflight(router->methods_for(request.path), response);
                return httplib::Server::HandlerResponse::Handled;
            }
            return httplib::Server::HandlerResponse::Unhandled;
        });

    // Answers that cpp-httplib makes itself (no route, a malformed request) and routes that
    // set a status without a body become problem+json too.
    server->set_error_handler(httplib::Server::HandlerWithResponse(
        [this](const httplib::Request& request, httplib::Response& response) {
            if (!response.body.empty()) {
                return httplib::Server::HandlerResponse::Unhandled;
            }
            if (response.status == 404 && current_request().route == "unmatched") {
                const std::vector<std::string> methods = router->methods_for(request.path);
                if (methods.empty()) {
                    send_problem(response, {problem(404, "no route has this path"), {}, false, ""});
                } else {
                    std::string allow;
                    for (const std::string& method : methods) {
                        allow += (allow.empty() ? "" : ", ") + method;
                    }
                    send_problem(
                        response,
                        {problem(405, "this path allows " + allow), {{"Allow", allow}}, false, ""});
                }
            } else if (response.status == 413) {
                send_problem(response,
                             {problem(413, "the body is over the server's limit"), {}, false, ""});
            } else {
                // Other statuses cpp-httplib answers with (414, 431, ...) mean a malformed request.
                send_problem(response, {problem(400, "the request could not be read (HTTP " +
                                                         std::to_string(response.status) + ")"),
                                        {},
                                        false,
                                        ""});
            }
            return httplib::Server::HandlerResponse::Handled;
        }));

    server->set_exception_handler([this](const httplib::Request& request,
                                         httplib::Response& response, std::exception_ptr error) {
        const ErrorAnswer answer = error_answer(error);
        if (answer.internal) {
            log("error: " + request.method + " " + current_request().route + ": " + answer.cause);
        }
        send_problem(response, answer);
    });

    server->set_post_routing_handler([](const httplib::Request&, httplib::Response& response) {
        if (current_request().close_connection) {
            response.set_header("Connection", "close");
        }
    });

    server->set_logger([this](const httplib::Request& request, const httplib::Response& response) {
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
    if (server) {
        server->stop();
    }
    if (listener.joinable()) {
        listener.join();
    }
    context.reset();
    router.reset();
    server.reset();
    // The pool first: a frame whose client timed out may still be running, and its job uses
    // the frame service.
    pool.reset();
    frame_service.reset();
    ready = false;
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
    return impl_->port;
}

std::string Service::url() const {
    return "http://" + impl_->config.host + ":" + std::to_string(impl_->port);
}

std::string Service::banner() const {
    const ServiceConfig& c = impl_->config;
    std::ostringstream text;
    text << "oer-server " << api::kVersion << " listening on " << url() << "\n";
    if (impl_->pool) {
        const GlInfo& gl = impl_->pool->info();
        text << "  renderer: " << gl.vendor << ", " << gl.renderer << ", OpenGL " << gl.version
             << " (" << gl.platform << "), " << impl_->pool->worker_count() << " worker(s)\n";
    } else {
        text << "  renderer: not started\n";
    }
    text << "  data folder: " << c.data_dir.string() << "\n";
    text << "  limits: upload " << mebibytes(c.max_upload_bytes) << ", image " << c.max_image_pixels
         << " pixels, " << c.max_triangles << " triangles, frame " << c.max_frame_width << "x"
         << c.max_frame_height << ", queue " << c.max_queue_depth << ", request timeout "
         << c.request_timeout_seconds << " s, idle timeout " << c.idle_timeout_seconds
         << " s, keep-alive " << c.keep_alive_max_count << " requests, " << c.http_threads
         << " HTTP threads, frame cache " << mebibytes(c.frame_cache_bytes) << "\n";
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
