// POST /v1/meshes, GET /v1/meshes/{id}
#include "http_exchange.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/api/parameter_text.hpp"
#include "service_context.hpp"

namespace oer::server {

namespace {

// The format from ?format= when given, else from the media type.
MeshFormat format_of(const httplib::Request& request) {
    const auto query = single_query(request, {"format"});
    if (const auto format = query.find("format"); format != query.end()) {
        return api::parse_enum("format", format->second, api::mesh_format_from_string);
    }
    const std::string type = media_type(request);
    if (type == "model/gltf-binary") {
        return MeshFormat::Glb;
    }
    if (type == "model/gltf+json") {
        return MeshFormat::Gltf;
    }
    if (type == "model/obj") {
        return MeshFormat::Obj;
    }
    if (type == "application/octet-stream") {
        throw HttpError(problem(415, "application/octet-stream needs ?format=glb|gltf|obj"));
    }
    throw HttpError(problem(415,
                            "a mesh is model/gltf-binary, model/gltf+json, model/obj or "
                            "application/octet-stream with ?format=, not '" +
                                api::excerpt(type) + "'"));
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

    router.get("/v1/meshes/{id}",
               [&context](const httplib::Request& request, httplib::Response& response) {
                   single_query(request, {});
                   const std::string& id = request.matches[1];
                   const auto mesh = context.meshes.find(id);
                   if (!mesh) {
                       throw not_found("no mesh with id '" + api::excerpt(id) + "'");
                   }
                   send_json(response, 200, mesh->json);
               });
}

}  // namespace oer::server
