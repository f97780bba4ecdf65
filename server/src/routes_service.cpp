// GET /v1/presets, /v1/info, and the probes: /healthz, /readyz, /metrics
#include "http_exchange.hpp"
#include "oer/api/version.hpp"
#include "service_context.hpp"

namespace oer::server {

namespace {

// Why a pool that has not started cannot render yet.
std::string renderer_state(const RenderPool& pool) {
    const std::string failure = pool.failure();
    return failure.empty() ? "the render workers are not ready yet"
                           : "the renderer could not start: " + failure;
}

}  // namespace

void add_service_routes(Router& router, ServiceContext& context) {
    router.get("/v1/presets", [](const httplib::Request& request, httplib::Response& response) {
        single_query(request, {});
        send_json(response, 200,
                  {{"environments",
                    {{{"id", "default"},
                      {"name", "Studio"},
                      {"description",
                       "A studio with three soft-boxes (key, fill and rim) of "
                       "distinct colors and sizes over a dim gradient"}}}},
                   {"meshes",
                    {{{"id", "default"},
                      {"name", "Dress form"},
                      {"description",
                       "A mannequin torso on a stand and a round base, feet at "
                       "y = 0, about 1.6 units tall, facing +Z"}}}}});
    });

    router.get("/v1/info", [&context](const httplib::Request& request,
                                      httplib::Response& response) {
        single_query(request, {});
        const GlInfo* gl = context.pool.info();
        nlohmann::json renderer = nullptr;
        if (gl) {
            renderer = {
                {"platform", gl->platform},       {"egl_vendor", gl->egl_vendor},
                {"egl_version", gl->egl_version}, {"vendor", gl->vendor},
                {"renderer", gl->renderer},       {"version", gl->version},
                {"max_samples", gl->max_samples}, {"max_texture_size", gl->max_texture_size}};
        }
        const api::RenderLimits& limits = context.render_limits;
        nlohmann::json info = {{"version", api::kVersion},
                               {"renderer", renderer},
                               {"limits",
                                {{"max_width", limits.max_width},
                                 {"max_height", limits.max_height},
                                 {"samples", api::kSampleCounts},
                                 {"max_samples_per_frame", context.pool.limits().max_samples_total},
                                 {"max_objects", limits.max_objects},
                                 {"max_lights", limits.max_lights},
                                 {"max_shadow_resolution", limits.max_shadow_resolution},
                                 {"max_body_bytes", limits.max_body_bytes},
                                 {"max_upload_bytes", context.config.max_upload_bytes}}}};
        if (!gl) {
            info["renderer_error"] = renderer_state(context.pool);
        }
        send_json(response, 200, info);
    });

    add_probe_routes(router, context);
}

void add_probe_routes(Router& router, ServiceContext& context) {
    // Liveness: no GL, no store, no lock another request may hold.
    router.get("/healthz", [](const httplib::Request&, httplib::Response& response) {
        send_json(response, 200, {{"status", "ok"}});
    });

    router.get("/readyz", [&context](const httplib::Request&, httplib::Response& response) {
        if (!context.pool.started()) {
            throw unavailable(renderer_state(context.pool), kRendererRetrySeconds);
        }
        if (context.pool.waiting() >= std::size_t(context.config.max_queue_depth)) {
            throw unavailable("the render queue is full", kRetryAfterSeconds);
        }
        send_json(response, 200, {{"status", "ready"}});
    });

    router.get("/metrics", [&context](const httplib::Request&, httplib::Response& response) {
        response.status = 200;
        response.set_content(context.metrics.registry().render_prometheus_text(),
                             "text/plain; version=0.0.4");
    });
}

}  // namespace oer::server
