// POST and GET /v1/meshes, GET and DELETE /v1/meshes/{id}
#include <string_view>

#include "http_exchange.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/core/error.hpp"
#include "service_context.hpp"

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
    const auto query = single_query(request, {"format"});
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

}  // namespace

void add_mesh_routes(Router& router, ServiceContext& context) {
    router.post(
        "/v1/meshes", context.config.max_upload_bytes,
        [&context](const httplib::Request& request, httplib::Response&) {
            if (!context.config.api_key.empty()) {
                require_api_key(request, context.config.api_key);
            }
            format_of(request);
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            if (body.empty()) {
                throw api::InvalidParameter("body", "the body must be the mesh file's bytes");
            }
            const auto upload = context.meshes.upload(body, format_of(request));
            send_upload(response, upload.asset->json, upload.cached,
                        "/v1/meshes/" + upload.asset->id);
        });

    router.get(
        "/v1/meshes", [&context](const httplib::Request& request, httplib::Response& response) {
            const ListingQuery query = listing_query(request);
            const ListedPage page = context.meshes.list(query.after, query.limit);
            nlohmann::json entries = nlohmann::json::array();
            for (const ListedAsset& entry : page.entries) {
                const MeshFormat format = api::mesh_format_from_string(entry.source->extension);
                entries.push_back({{"id", entry.id},
                                   {"url", "/v1/meshes/" + entry.id},
                                   {"format", api::to_string(format)},
                                   {"media_type", media_type_of(format)},
                                   {"bytes", entry.source->bytes},
                                   {"created", rfc3339(entry.stored)}});
            }
            send_listing(response, "/v1/meshes", "meshes", std::move(entries), page.next_after,
                         query.limit);
        });

    router.del("/v1/meshes/{id}", [&context](const httplib::Request& request,
                                             httplib::Response& response) {
        if (!context.config.api_key.empty()) {
            require_api_key(request, context.config.api_key);
        }
        single_query(request, {});
        const std::string& id = request.matches[1];
        if (id == api::kDefaultPresetId) {
            throw HttpError(problem(ProblemKind::PresetNotDeletable,
                                    "'default' is the built-in product: it is part of the server, "
                                    "not of its store, and cannot be deleted"));
        }
        if (!context.meshes.remove(id)) {
            throw not_found(ProblemKind::UnknownId, "no mesh with id '" + api::excerpt(id) + "'");
        }
        response.status = 204;
    });

    router.get("/v1/meshes/{id}", [&context](const httplib::Request& request,
                                             httplib::Response& response) {
        single_query(request, {});
        const std::string& id = request.matches[1];
        const auto mesh = context.meshes.find(id);
        if (!mesh) {
            throw not_found(ProblemKind::UnknownId, "no mesh with id '" + api::excerpt(id) + "'");
        }
        send_json(response, 200, mesh->json);
    });
}

}  // namespace oer::server
