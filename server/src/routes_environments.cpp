// POST /v1/environments, GET /v1/environments/{id}, .../preview.jpg, .../irradiance.exr
#include "environment_preview.hpp"
#include "http_exchange.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/lighting/irradiance_map.hpp"
#include "service_context.hpp"

namespace oer::server {

namespace {

// The map formats an upload may be, by media type.
std::string extension_of_media_type(const std::string& type) {
    if (type == "image/vnd.radiance") {
        return "hdr";
    }
    if (type == "image/x-exr") {
        return "exr";
    }
    throw HttpError(problem(415, "an environment is image/vnd.radiance or image/x-exr, not '" +
                                     api::excerpt(type) + "'"));
}

std::shared_ptr<const Environment> environment_of(ServiceContext& context,
                                                  const httplib::Request& request) {
    const std::string& id = request.matches[1];
    auto environment = context.environments.find(id);
    if (!environment) {
        throw not_found("no environment with id '" + api::excerpt(id) + "'");
    }
    return environment;
}

void send_image(httplib::Response& response, const std::string& bytes, const char* type) {
    response.status = 200;
    // The answer depends only on the id, which is content-addressed.
    response.set_header("Cache-Control", "public, max-age=86400");
    response.set_content(bytes, type);
}

}  // namespace

void add_environment_routes(Router& router, ServiceContext& context) {
    router.post(
        "/v1/environments", context.config.max_upload_bytes,
        [&context](const httplib::Request& request, httplib::Response&) {
            if (!context.config.api_key.empty()) {
                require_api_key(request, context.config.api_key);
            }
            extension_of_media_type(media_type(request));
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            std::map<std::string, std::string> parameters;
            for (const auto& [name, value] : request.params) {
                if (!parameters.emplace(name, value).second) {
                    throw api::InvalidParameter(name, "given more than once");
                }
            }
            const RigOptions options = api::parse_rig_options(parameters);
            if (body.empty()) {
                throw api::InvalidParameter("body", "the body must be the map's bytes");
            }
            const auto upload = context.environments.upload(
                body, extension_of_media_type(media_type(request)), options);
            send_upload(response, upload.asset->json, upload.cached,
                        "/v1/environments/" + upload.asset->id);
        });

    router.get("/v1/environments/{id}",
               [&context](const httplib::Request& request, httplib::Response& response) {
                   single_query(request, {});
                   send_json(response, 200, environment_of(context, request)->json);
               });

    router.get("/v1/environments/{id}/preview.jpg", [&context](const httplib::Request& request,
                                                               httplib::Response& response) {
        single_query(request, {});
        const auto environment = environment_of(context, request);
        const std::string key = "preview:" + environment->id;
        auto preview = context.frames.get(key);
        if (!preview) {
            const auto map = context.environments.source_image(*environment);
            if (!map) {
                throw not_found("the map of environment '" + environment->id +
                                "' is no longer stored; upload it again");
            }
            preview = std::make_shared<const std::string>(preview_jpeg(*map, *environment->rig));
            context.frames.put(key, preview);
        }
        send_image(response, *preview, "image/jpeg");
    });

    router.get("/v1/environments/{id}/irradiance.exr", [&context](const httplib::Request& request,
                                                                  httplib::Response& response) {
        const auto query = single_query(request, {"lights", "width", "height"});
        const auto value = [&query](const std::string& name) -> std::optional<std::string> {
            const auto found = query.find(name);
            return found == query.end() ? std::nullopt : std::optional(found->second);
        };
        const int width = int(api::parse_integer("width", value("width").value_or("128"), 1, 1024));
        const int height =
            int(api::parse_integer("height", value("height").value_or("64"), 1, 512));
        const auto environment = environment_of(context, request);
        const Rig& rig = *environment->rig;
        const std::vector<double> visibility =
            api::parse_light_switches(value("lights"), rig.lights.size());
        const HdrImage map = irradiance_map_from_sh(
            irradiance_coefficients(visibility_coefficients(rig.sh, visibility), rig.window), width,
            height);
        std::vector<float> rgba(map.pixel_count() * 4, 1.0f);
        for (std::size_t i = 0; i < map.pixel_count(); ++i) {
            std::copy_n(&map.pixels[i * 3], 3, &rgba[i * 4]);
        }
        const std::vector<std::uint8_t> exr = encode_exr(width, height, rgba);
        send_image(response, std::string(exr.begin(), exr.end()), "image/x-exr");
    });
}

}  // namespace oer::server
