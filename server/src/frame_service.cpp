#include "frame_service.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <thread>

#include "http_errors.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/frame_encoding.hpp"
#include "oer/core/cancellation.hpp"
#include "oer/mesh/camera_rays.hpp"
#include "oer/reference/embree_scene.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "oer/scene/scene_rules.hpp"

namespace oer::server {

namespace {

using Clock = std::chrono::steady_clock;

// How often a thread waiting for its frame looks at the deadline and at its client's
// connection: the most a frame runs on for nobody before it is asked to stop.
constexpr std::chrono::milliseconds kClientPollInterval{50};
// How often a batch frame looks at the interactive pool, before it starts and while it runs:
// about the most an interactive frame shares the cores with a batch frame.
constexpr std::chrono::milliseconds kBatchYieldInterval{2};

double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string timing_entry(const std::string& pass, double ms) {
    char duration[32];
    std::snprintf(duration, sizeof duration, "%.2f", ms);
    return pass + ";dur=" + duration;
}

// W3C Server-Timing: each pass of the frame's, then its encoding.
std::string server_timing(const Frame& frame, double encode_ms) {
    std::string timing;
    for (const auto& [pass, ms] : frame.timings_ms) {
        timing += (timing.empty() ? "" : ", ") + timing_entry(pass, ms);
    }
    return timing + (timing.empty() ? "" : ", ") + timing_entry("encode", encode_ms);
}

}  // namespace

FrameService::FrameService(EnvironmentRegistry& environments, MeshRegistry& meshes,
                           TransferRegistry& transfers, RenderPool& pool, RenderPool& batch_pool,
                           ByteLruCache& frames, ServiceMetrics& metrics,
                           std::chrono::seconds deadline, RenderBudgets budgets,
                           double transfer_rays_per_phase, ClientWorkBudget& client_work,
                           std::function<void(std::string_view)> log)
    : environments_(environments),
      meshes_(meshes),
      transfers_(transfers),
      pool_(pool),
      batch_pool_(batch_pool),
      frames_(frames),
      metrics_(metrics),
      deadline_(deadline),
      budgets_(budgets),
      transfer_rays_per_phase_(transfer_rays_per_phase),
      client_work_(client_work),
      log_(std::move(log)),
      bake_lane_(kBakeLaneNice, kMaxQueuedBakes) {}

FrameRequest FrameService::standard_scene(std::shared_ptr<const Mesh> mesh, bool ground) {
    FrameRequest request;
    request.objects.push_back({std::move(mesh), glm::mat4(1.0f), std::nullopt});
    request.occlusion = true;
    request.bounce = Bounce::One;
    request.ground = ground;
    return request;
}

void FrameService::prepare(const std::string& mesh_id) {
    const auto summary = meshes_.summary(mesh_id);
    const auto environment = environments_.find(std::string(api::kDefaultPresetId));
    if (!summary || !environment) {
        return;
    }
    api::RenderSpec spec;
    spec.objects.push_back({});
    spec.objects.back().mesh = mesh_id;
    try {
        check_render_cost(
            estimate_render_cost(spec, {*summary}, {mesh_id}, environment->rig->lights.size(),
                                 transfer_rays_per_phase_),
            budgets_);
    } catch (const HttpError& over) {
        log_("preparation: mesh " + mesh_id + " not prepared ahead: " + over.what());
        return;
    }
    const auto mesh = meshes_.find(mesh_id);
    if (!mesh) {
        return;
    }
    bake_ahead(std::make_shared<FrameRequest>(standard_scene(mesh->mesh, true)), {mesh_id},
               "mesh " + mesh_id);
    bake_ahead(std::make_shared<FrameRequest>(standard_scene(mesh->mesh, false)), {mesh_id},
               "mesh " + mesh_id + " without the floor");
}

void FrameService::bake_ahead(std::shared_ptr<const FrameRequest> request,
                              std::vector<std::string> mesh_ids, const std::string& what) {
    const std::string id = transfers_.id_of(*request, mesh_ids);
    {
        const std::lock_guard lock(queued_mutex_);
        if (!queued_.insert(id).second) {
            return;  // queued already
        }
    }
    const auto dequeue = [this, id] {
        const std::lock_guard lock(queued_mutex_);
        queued_.erase(id);
    };
    // Kept until the bake has ended, not only until it starts: between the two the registry
    // may not say Baking yet, and a preparation must never read as not prepared meanwhile.
    const bool queued = bake_lane_.submit([this, request, ids = std::move(mesh_ids), what,
                                           dequeue](const std::stop_token& stop) {
        try {
            transfers_.transfer(*request, ids, stop, false);
        } catch (const std::exception& error) {
            log_("preparation: the transfer of " + what + " was not baked ahead: " + error.what());
        }
        dequeue();
    });
    if (!queued) {
        dequeue();
        log_("preparation: the transfer of " + what +
             " was not baked ahead: the bakes' queue is full");
    }
}

std::optional<MeshPreparation> FrameService::preparation(const std::string& mesh_id) {
    const auto summary = meshes_.summary(mesh_id);
    if (!summary) {
        return std::nullopt;
    }
    const auto id_of = [&](bool ground) {
        return transfers_.id_for(standard_scene(nullptr, ground), {mesh_id}, summary->vertices);
    };
    return MeshPreparation{scene_preparation(id_of(true)), scene_preparation(id_of(false))};
}

ScenePreparation FrameService::scene_preparation(const std::string& transfer_id) {
    ScenePreparation answer;
    const TransferPreparation transfer = transfers_.preparation(transfer_id);
    switch (transfer.state) {
        case TransferPreparation::State::Ready:
            answer.state = ScenePreparation::State::Ready;
            answer.fraction = 1.0;
            return answer;
        case TransferPreparation::State::Baking:
            answer.state = ScenePreparation::State::Baking;
            answer.fraction = transfer.fraction;
            if (transfer.fraction > 0.0) {
                answer.seconds_left =
                    transfer.elapsed_seconds * (1.0 - transfer.fraction) / transfer.fraction;
            }
            return answer;
        case TransferPreparation::State::Absent:
            break;
    }
    const std::lock_guard lock(queued_mutex_);
    if (queued_.contains(transfer_id)) {
        answer.state = ScenePreparation::State::Queued;
    }
    return answer;
}

ResolvedRender FrameService::resolve(const api::RenderSpec& spec, RequestForm form) {
    ResolvedRender resolved{spec, nullptr, {}, {}, {}};
    resolved.environment = environments_.find(spec.environment);
    if (!resolved.environment) {
        throw not_found(ProblemKind::UnknownId, "no environment with id '" + spec.environment + "'",
                        "environment");
    }
    const auto unknown_mesh = [&](std::size_t i) {
        return not_found(
            ProblemKind::UnknownId, "no mesh with id '" + spec.objects[i].mesh + "'",
            form == RequestForm::Json ? "objects/" + std::to_string(i) + "/mesh" : "mesh");
    };
    std::vector<MeshSummary> summaries;
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < spec.objects.size(); ++i) {
        const auto summary = meshes_.summary(spec.objects[i].mesh);
        if (!summary) {
            throw unknown_mesh(i);
        }
        summaries.push_back(*summary);
        ids.push_back(spec.objects[i].mesh);
    }
    check_render_cost(
        estimate_render_cost(spec, summaries, ids, resolved.environment->rig->lights.size(),
                             transfer_rays_per_phase_),
        budgets_);
    for (std::size_t i = 0; i < spec.objects.size(); ++i) {
        const auto mesh = meshes_.find(spec.objects[i].mesh);
        if (!mesh) {
            throw unknown_mesh(i);
        }
        // A variant or a material the mesh lacks is the request's error, named as the request
        // gave it.
        const auto named = [&](const std::string& member) {
            return form == RequestForm::Json ? "objects/" + std::to_string(i) + "/" + member
                                             : member;
        };
        api::variant_index(spec.objects[i], *mesh->mesh, named("variant"));
        api::base_color_material_index(spec.objects[i], *mesh->mesh, named("base_color_material"));
        resolved.meshes.push_back(mesh->mesh);
        resolved.mesh_ids.push_back(mesh->id);
    }
    resolved.camera = api::resolved_camera(spec, resolved.meshes);
    return resolved;
}

FrameRequest FrameService::frame_request(const ResolvedRender& resolved) {
    const api::RenderSpec& spec = resolved.spec;
    const Environment& environment = *resolved.environment;
    std::shared_ptr<const HdrImage> map;
    if (spec.background.kind == BackgroundKind::Environment) {
        map = environments_.source_image(environment);
        if (!map) {
            throw not_found(ProblemKind::MapNotStored,
                            "the map of environment '" + spec.environment +
                                "' is no longer stored; upload it again",
                            "environment");
        }
    }
    FrameRequest request =
        api::to_frame_request(spec, resolved.camera, environment.rig, map, resolved.meshes);
    if (needs_specular(request)) {
        request.specular = environments_.specular(environment);
        if (!request.specular) {
            throw not_found(ProblemKind::MapNotStored,
                            "the map of environment '" + spec.environment +
                                "' is no longer stored, and its glossy materials need it; "
                                "upload it again",
                            "environment");
        }
    }
    return request;
}

Frame FrameService::rendered(std::shared_ptr<FrameRequest> request,
                             const std::vector<std::string>& mesh_ids, const Client& client) {
    if (client.lane == Lane::Interactive) {
        return rendered_once(std::move(request), mesh_ids, client).value();
    }
    // A batch frame starts only while no interactive frame is in flight, and yields to the
    // next one: stopped between its passes (or bake chunks), it starts again once the
    // interactive frames are done. A worker of its own at nice 19 alone was not enough: with
    // a batch frame rendering, interactive frames took 1.6 to 1.7 times as long (256x256, 4
    // samples, on 2 shared cores: tests/integration/jobs_test.cpp); yielding, 0.99 to 1.11
    // (docs/jobs.md).
    for (;;) {
        while (!pool_.idle()) {
            if (client.gone && client.gone()) {
                throw unavailable("the job's frame was stopped", kRetryAfterSeconds);
            }
            std::this_thread::sleep_for(kBatchYieldInterval);
        }
        if (auto frame = rendered_once(request, mesh_ids, client)) {
            return std::move(*frame);
        }
        metrics_.batch_frames_yielded.increment();
    }
}

std::optional<Frame> FrameService::rendered_once(std::shared_ptr<FrameRequest> request,
                                                 const std::vector<std::string>& mesh_ids,
                                                 const Client& client) {
    // Requested once this request stops waiting: a worker that reaches the frame afterwards
    // skips it, and one under way stops it (its answer, a 503, has gone already, or nobody
    // reads it).
    std::stop_source stop;
    const bool batch = client.lane == Lane::Batch;
    RenderPool& pool = batch ? batch_pool_ : pool_;
    std::future<Frame> pending = pool.submit(
        [this, request, ids = mesh_ids, stop = stop.get_token()](FrameRenderer& renderer) {
            if (stop.stop_requested()) {
                metrics_.renders_skipped.increment();
                throw_if_stopped(stop, "the frame");
            }
            try {
                double transfer_ms = 0.0;
                if (request->occlusion) {
                    const auto transfer_start = Clock::now();
                    request->transfer = transfers_.transfer(*request, ids, stop);
                    transfer_ms = milliseconds_since(transfer_start);
                }
                const auto start = Clock::now();
                Frame frame = renderer.render(*request, stop);
                metrics_.render_seconds.observe(
                    std::chrono::duration<double>(Clock::now() - start).count());
                if (request->occlusion) {
                    frame.timings_ms["transfer"] = transfer_ms;
                }
                return frame;
            } catch (const Error& error) {
                if (error.kind() == ErrorKind::Cancelled) {
                    metrics_.renders_stopped.increment();
                }
                throw;
            }
        });
    return awaited(pending, stop, client);
}

std::optional<Frame> FrameService::awaited(std::future<Frame>& pending, std::stop_source& stop,
                                           const Client& client) {
    const bool batch = client.lane == Lane::Batch;
    const auto deadline = Clock::now() + deadline_;
    bool yielded = false;
    while (pending.wait_for(batch ? kBatchYieldInterval : kClientPollInterval) !=
           std::future_status::ready) {
        if (batch && !yielded && !pool_.idle()) {
            stop.request_stop();
            yielded = true;
        }
        if (!batch && Clock::now() >= deadline) {
            stop.request_stop();
            throw unavailable(
                "the frame was not rendered within " + std::to_string(deadline_.count()) + " s",
                kRetryAfterSeconds);
        }
        if (client.gone && client.gone()) {
            stop.request_stop();
            throw unavailable("the client closed its connection; the frame was stopped",
                              kRetryAfterSeconds);
        }
    }
    if (!yielded) {
        return pending.get();
    }
    try {
        return pending.get();  // finished before it saw the stop
    } catch (const Error& error) {
        if (error.kind() != ErrorKind::Cancelled) {
            throw;
        }
        return std::nullopt;
    }
}

void FrameService::hold_past_share(const Client& client) {
    // A batch job's frames were bounded when it was submitted (job_spec.hpp), not here.
    if (client.lane != Lane::Interactive) {
        return;
    }
    if (const auto wait = client_work_.wait_before_work(client.address)) {
        // Held first (client_work_budget.hpp), in slices that watch for the client leaving.
        const auto held_until =
            Clock::now() +
            std::min(
                std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(*wait)),
                std::chrono::duration_cast<Clock::duration>(ClientWorkBudget::kRefusalHold));
        while (Clock::now() < held_until && !(client.gone && client.gone())) {
            std::this_thread::sleep_for(
                std::min<Clock::duration>(kClientPollInterval, held_until - Clock::now()));
        }
        const double left =
            *wait - std::chrono::duration<double>(ClientWorkBudget::kRefusalHold).count();
        const int seconds = std::max(1, int(std::ceil(left)));
        throw HttpError(problem(ProblemKind::TooManyRenders,
                                "this client's share of uncached rendering is used up for " +
                                    std::to_string(seconds) +
                                    " s; frames already rendered are served meanwhile"),
                        {{"Retry-After", std::to_string(seconds)}});
    }
}

api::RenderSpec FrameService::geometry_only(const api::RenderSpec& spec) {
    api::RenderSpec geometry = spec;
    geometry.occlusion = false;
    geometry.samples = 1;
    geometry.shadows.enabled = false;
    geometry.background = Background{BackgroundKind::Color, glm::vec3(0.0f)};
    return geometry;
}

HotspotPlacements FrameService::place_hotspots(const api::HotspotRequest& hotspots,
                                               RequestForm form, const Client& client) {
    const api::RenderSpec spec = geometry_only(hotspots.render);
    const ResolvedRender resolved = resolve(spec, form);
    hold_past_share(client);
    const auto points = std::make_shared<const std::vector<ScenePoint>>(
        api::hotspot_points(hotspots, resolved.meshes, form == RequestForm::Query));
    const auto request = std::make_shared<const FrameRequest>(frame_request(resolved));
    auto placements = std::make_shared<std::vector<PointPlacement>>();
    auto work_ms = std::make_shared<double>(0.0);
    std::stop_source stop;
    // The pool's jobs make frames; this one's products are the placements and the time it
    // took, which the client's share of render work (client_work_budget.hpp) pays for.
    std::future<Frame> pending = pool_.submit(
        [request, points, placements, work_ms, stop = stop.get_token()](FrameRenderer& renderer) {
            const auto start = Clock::now();
            *placements = renderer.place_points(*request, *points, stop);
            *work_ms = milliseconds_since(start);
            return Frame{};
        });
    awaited(pending, stop, client);
    client_work_.charge(client.address, *work_ms / 1000.0);
    return {resolved.camera, std::move(*placements)};
}

PickedSurface FrameService::pick(const api::PickRequest& pick, RequestForm form,
                                 const Client& client) {
    const api::RenderSpec spec = geometry_only(pick.render);
    const ResolvedRender resolved = resolve(spec, form);
    // Its work (the scene's ray-tracing structure, built for this request) is the client's, as
    // a frame's is: held past its share, and charged.
    hold_past_share(client);
    const auto start = Clock::now();
    // The surfaces alone: neither the map nor a specular cube, which frame_request would fetch.
    const FrameRequest request = api::to_frame_request(
        spec, resolved.camera, resolved.environment->rig, nullptr, resolved.meshes);
    const reference::EmbreeScene scene(request, scene_bounds(request.objects),
                                       reference::GroundTracing::PlaneOnly);
    const CameraRays rays = camera_rays(resolved.camera, spec.width, spec.height);
    PickedSurface picked{resolved.camera, std::nullopt, {}};
    const auto hit = scene.intersect(rays.eye, rays.direction(pick.pixel.x, pick.pixel.y), 0.0,
                                     reference::GroundReach::Drawn);
    if (hit && !hit->ground) {
        const api::SurfaceSpot spot{
            hit->object, hit->primitive, hit->triangle, {1.0 - hit->u - hit->v, hit->u, hit->v}};
        picked.point = api::surface_point(*resolved.meshes.at(spot.object),
                                          request.objects.at(spot.object).transform, spot);
        picked.spot = spot;
    }
    client_work_.charge(client.address, milliseconds_since(start) / 1000.0);
    return picked;
}

EncodedFrame FrameService::render(const api::RenderSpec& spec, const std::string& etag,
                                  RequestForm form, const Client& client,
                                  bool preliminary_allowed) {
    EncodedFrame result;
    result.etag = etag;
    result.content_type = api::content_type_of(spec.format);
    // The environment and meshes are found before the cache, so that a frame of one removed
    // since (DELETE) is 404, never served from the cache; and a cached frame names its camera
    // too (a few map lookups).
    const ResolvedRender resolved = resolve(spec, form);
    result.camera = resolved.camera;
    if (auto cached = frames_.get(result.etag)) {
        metrics_.cache(CacheName::Frame, true);
        result.bytes = std::move(cached);
        result.cache_hit = true;
        return result;
    }
    metrics_.cache(CacheName::Frame, false);
    const bool interactive = client.lane == Lane::Interactive;
    hold_past_share(client);
    // The work charged to the client: its frame's preparation on this thread (a specular cube,
    // as long as it took) and its work on the worker (its transfer and the frame's "total", not
    // the time it waited in the queue behind other clients' frames).
    class ChargeOnExit {
      public:
        ChargeOnExit(ClientWorkBudget& budget, const std::string& client, bool charged)
            : budget_(budget), client_(client), charged_(charged) {}
        ~ChargeOnExit() {
            if (!charged_) {
                return;
            }
            budget_.charge(
                client_,
                (preparation_ms.value_or(milliseconds_since(start_)) + render_ms) / 1000.0);
        }
        Clock::time_point start() const { return start_; }
        std::optional<double> preparation_ms;  // set once the frame request is made
        double render_ms = 0.0;

      private:
        ClientWorkBudget& budget_;
        const std::string& client_;
        const bool charged_;
        const Clock::time_point start_ = Clock::now();
    } work(client_work_, client.address, interactive);
    auto request = std::make_shared<FrameRequest>(frame_request(resolved));
    // The preliminary frame is kept under its own key while the transfer bakes: the viewer asks
    // again every 0.5 s until the whole frame comes, and drawing it again each time would take
    // the cores from the bake it waits for (the bake lane runs at the lowest priority).
    const std::string preliminary_key = result.etag + " preliminary";
    if (interactive && preliminary_allowed && request->occlusion &&
        !transfers_.ready(transfers_.id_of(*request, resolved.mesh_ids))) {
        if (auto kept = frames_.get(preliminary_key)) {
            result.bytes = std::move(kept);
            result.cache_hit = true;
            result.preliminary = true;
            return result;
        }
        // Baked ahead for the frames to come; this one is drawn without it, now.
        bake_ahead(std::make_shared<const FrameRequest>(*request), resolved.mesh_ids,
                   "a frame's scene");
        request->occlusion = false;
        result.preliminary = true;
    }
    work.preparation_ms = milliseconds_since(work.start());
    const Frame frame = rendered(std::move(request), resolved.mesh_ids, client);
    for (const char* part : {"transfer", "total"}) {
        if (const auto ms = frame.timings_ms.find(part); ms != frame.timings_ms.end()) {
            work.render_ms += ms->second;
        }
    }
    const auto encode_start = Clock::now();
    const std::vector<std::uint8_t> bytes = api::encode(frame, spec.format, spec.quality);
    result.server_timing = server_timing(frame, milliseconds_since(encode_start));
    result.bytes = std::make_shared<const std::string>(bytes.begin(), bytes.end());
    if (result.preliminary) {
        frames_.put(preliminary_key, result.bytes);
    } else {
        frames_.put(result.etag, result.bytes);
        frames_.erase(preliminary_key);
    }
    return result;
}

}  // namespace oer::server
