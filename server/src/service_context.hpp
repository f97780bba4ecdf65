#pragma once
// Everything the routes use, owned by the Service and handed to each group of routes.
#include <functional>
#include <string_view>

#include "environment_registry.hpp"
#include "frame_service.hpp"
#include "job_service.hpp"
#include "mesh_registry.hpp"
#include "oer/api/render_request.hpp"
#include "oer/server/byte_lru_cache.hpp"
#include "oer/server/service_config.hpp"
#include "render_pool.hpp"
#include "router.hpp"
#include "service_metrics.hpp"
#include "transfer_registry.hpp"

namespace oer::server {

struct ServiceContext {
    const ServiceConfig& config;
    const api::RenderLimits& render_limits;
    ServiceMetrics& metrics;
    EnvironmentRegistry& environments;
    MeshRegistry& meshes;
    TransferRegistry& transfers;
    ByteLruCache& frames;  // encoded frames, and previews
    RenderPool& pool;
    FrameService& frame_service;
    JobService& jobs;
    std::function<void(std::string_view)> log;
};

// Each registers one group of routes of api/openapi.yaml.
void add_environment_routes(Router& router, ServiceContext& context);
void add_mesh_routes(Router& router, ServiceContext& context);
void add_render_routes(Router& router, ServiceContext& context);
void add_hotspot_routes(Router& router, ServiceContext& context);
void add_job_routes(Router& router, ServiceContext& context);
void add_service_routes(Router& router, ServiceContext& context);  // with the probes
// GET /healthz, /readyz, /metrics: also the whole of the admin listener.
void add_probe_routes(Router& router, ServiceContext& context);
// GET / and /web/{file}: the browser client (web/), embedded at build time.
void add_web_routes(Router& router);

}  // namespace oer::server
