// POST and GET /v1/meshes, GET and DELETE /v1/meshes/{id}, GET /v1/meshes/{id}/preparation and
// its server-sent events
#include <chrono>
#include <cmath>
#include <string_view>
#include <thread>

#include "event_stream.hpp"
#include "http_exchange.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/core/error.hpp"
#include "service_context.hpp"
#include "stored_asset_routes.hpp"

namespace oer::server {

namespace {

// The media type of each mesh format: what an upload declares, and what a listing shows.
struct MeshMediaType {
    std::string_view media_type;
    MeshFormat format;
};
constexpr MeshMediaType kMeshMediaTypes[] = {
    {"model/gltf-binary", MeshFormat::Glb},
    {"model/gltf+json", MeshFormat::Gltf},
    {"model/obj", MeshFormat::Obj},
};

// The format from ?format= when given, else from the media type.
MeshFormat format_of(const httplib::Request& request) {
    const auto query = single_query(request, {"format", "filename"});
    if (const auto format = query.find("format"); format != query.end()) {
        return api::parse_enum("format", format->second, api::mesh_format_from_string);
    }
    const std::string type = media_type(request);
    std::string accepted;
    for (const MeshMediaType& known : kMeshMediaTypes) {
        if (type == known.media_type) {
            return known.format;
        }
        accepted.append(known.media_type).append(", ");
    }
    if (type == "application/octet-stream") {
        throw HttpError(problem(ProblemKind::UnsupportedMediaType,
                                "application/octet-stream needs ?format=glb|gltf|obj"));
    }
    throw HttpError(problem(ProblemKind::UnsupportedMediaType,
                            "a mesh is " + accepted +
                                "or application/octet-stream with ?format=, not '" +
                                api::excerpt(type) + "'"));
}

std::string_view media_type_of(MeshFormat format) {
    for (const MeshMediaType& known : kMeshMediaTypes) {
        if (known.format == format) {
            return known.media_type;
        }
    }
    throw Error(ErrorKind::Internal, "no media type for mesh format " + api::to_string(format));
}

const StoredAssetKind kMeshKind{"/v1/meshes", "meshes", "mesh", "the built-in product"};

// A listing's entry: the mesh file's format and size.
nlohmann::json listed_mesh(const ListedAsset& entry) {
    const MeshFormat format = api::mesh_format_from_string(entry.source->extension);
    return {{"format", api::to_string(format)},
            {"media_type", media_type_of(format)},
            {"bytes", entry.source->bytes}};
}

// Where one scene's bake ahead stands, as GET /v1/meshes/{id}/preparation says it.
nlohmann::json scene_preparation_json(const ScenePreparation& preparation) {
    const auto state = [&] {
        switch (preparation.state) {
            case ScenePreparation::State::Queued:
                return "queued";
            case ScenePreparation::State::Baking:
                return "baking";
            case ScenePreparation::State::Ready:
                return "ready";
            case ScenePreparation::State::NotPrepared:
                break;
        }
        return "not_prepared";
    }();
    nlohmann::json answer = {
        {"state", state}, {"progress", preparation.fraction}, {"seconds_left", nullptr}};
    if (preparation.seconds_left) {
        answer["seconds_left"] = *preparation.seconds_left;
    }
    return answer;
}

// GET /v1/meshes/{id}/preparation's answer: the first frames' scene at the top, the floorless
// one beside it.
nlohmann::json preparation_json(const MeshPreparation& preparation) {
    nlohmann::json answer = scene_preparation_json(preparation.first_frames);
    answer["stage"] = "transfer";
    answer["without_floor"] = scene_preparation_json(preparation.without_floor);
    return answer;
}

// The mesh's preparation as GET /v1/meshes/{id}/preparation answers it; 404 for an unknown id.
nlohmann::json requested_preparation(ServiceContext& context, const std::string& id) {
    const auto preparation = context.frame_service.preparation(id);
    if (!preparation) {
        throw unknown_asset(kMeshKind, id);
    }
    return preparation_json(*preparation);
}

// Whether a scene's bake ahead has ended, one way or the other (ready, or not prepared: refused
// over a budget, failed, or not queued).
bool scene_settled(const nlohmann::json& scene) {
    const std::string state = scene.at("state");
    return state != "queued" && state != "baking";
}

// What of a preparation must change for another event: a state, a whole percent of a bake, a
// whole second of its estimate (the fraction and the estimate change at every look).
std::string preparation_change(const nlohmann::json& preparation) {
    std::string change;
    for (const nlohmann::json* scene : {&preparation, &preparation.at("without_floor")}) {
        const nlohmann::json& left = scene->at("seconds_left");
        change += scene->at("state").get<std::string>() + " " +
                  std::to_string(int(std::floor(100.0 * scene->at("progress").get<double>()))) +
                  "% " + (left.is_null() ? "-" : std::to_string(std::lround(left.get<double>()))) +
                  " s; ";
    }
    return change;
}

// How often the preparation's event stream looks at the bake: its progress is counted by the
// bake's own threads (BakeProgress's atomic counters, in the renderer's library), which signal
// no one, so a stream looks again after this long; a tenth of a second is below what a progress
// bar shows, and a look costs two map lookups under the registry's mutexes.
constexpr std::chrono::milliseconds kPreparationPoll{100};

}  // namespace

void add_mesh_routes(Router& router, ServiceContext& context) {
    router.post(
        "/v1/meshes",
        RoutePolicy{.needs_api_key = true, .max_body = context.config.max_upload_bytes},
        [](const httplib::Request& request, httplib::Response&) { format_of(request); },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            if (body.empty()) {
                throw api::InvalidParameter("body", "the body must be the mesh file's bytes");
            }
            const MeshFormat format = format_of(request);
            const auto upload = context.meshes.upload(
                body, format,
                upload_file_name(single_query(request, {"format", "filename"}),
                                 api::to_string(format)));
            // Its first frames' transfer, baked ahead (GET .../preparation tells how far).
            if (!upload.cached) {
                context.frame_service.prepare(upload.asset->id);
            }
            send_upload(response, upload.asset->json, upload.cached,
                        "/v1/meshes/" + upload.asset->id);
        });

    add_asset_listing_route(router, context.meshes, kMeshKind, listed_mesh);
    // The stored transfers of scenes holding the mesh go with it.
    add_asset_removal_route(router, context.meshes, kMeshKind, [&context](const std::string& id) {
        context.transfers.remove_with_mesh(id);
    });
    add_asset_reading_route(router, context.meshes, kMeshKind);

    router.get("/v1/meshes/{id}/preparation",
               [&context](const httplib::Request& request, httplib::Response& response) {
                   single_query(request, {});
                   send_json(response, 200, requested_preparation(context, request.matches[1]));
               });

    // The same answer as server-sent events: one `progress` event each time it changes, the
    // stream ending after the event in which both scenes' bakes have ended.
    router.get("/v1/meshes/{id}/preparation/events", [&context](const httplib::Request& request,
                                                                httplib::Response& response) {
        single_query(request, {});
        const std::string id = request.matches[1];
        requested_preparation(context, id);  // 404 before the stream starts
        send_progress_events(response,
                             {.status = [&context, id]() -> std::optional<nlohmann::json> {
                                  const auto preparation = context.frame_service.preparation(id);
                                  if (!preparation) {
                                      return std::nullopt;  // deleted meanwhile
                                  }
                                  return preparation_json(*preparation);
                              },
                              .change = preparation_change,
                              .settled =
                                  [](const nlohmann::json& preparation) {
                                      return scene_settled(preparation) &&
                                             scene_settled(preparation.at("without_floor"));
                                  },
                              .wait = [] { std::this_thread::sleep_for(kPreparationPoll); }});
    });
}

}  // namespace oer::server
