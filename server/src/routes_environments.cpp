// POST and GET /v1/environments, GET and DELETE /v1/environments/{id}, .../preview.jpg,
// .../irradiance.exr
#include <algorithm>
#include <iterator>
#include <span>
#include <string_view>

#include "environment_preview.hpp"
#include "http_exchange.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/irradiance_map.hpp"
#include "service_context.hpp"
#include "stored_asset_routes.hpp"

namespace oer::server {

namespace {

// The image formats image_format_of names, each with its media type and the extension it is
// stored under; `map` for those an environment may be uploaded as, so that the decoder is the
// declared one. JPEG and PNG are the panoramas phones make: decoded from sRGB to linear and
// marked in the rig as of low dynamic range (source/dynamic_range "ldr").
struct ImageMediaType {
    std::string_view media_type;
    std::string_view extension;
    std::string_view format;
    bool map;
};
constexpr ImageMediaType kImageMediaTypes[] = {
    {"image/vnd.radiance", "hdr", "hdr", true}, {"image/x-exr", "exr", "openexr", true},
    {"image/jpeg", "jpg", "jpeg", true},        {"image/png", "png", "png", true},
    {"image/tiff", "tif", "tiff", false},
};

const ImageMediaType& map_media_type(const std::string& type) {
    std::string accepted;
    for (const ImageMediaType& known : kImageMediaTypes) {
        if (known.map && type == known.media_type) {
            return known;
        }
        if (known.map) {
            accepted.append(accepted.empty() ? "" : ", ").append(known.media_type);
        }
    }
    throw HttpError(
        problem(ProblemKind::UnsupportedMediaType,
                "an environment is one of " + accepted + ", not '" + api::excerpt(type) + "'"));
}

// 415 when the body's signature is that of another image format than the declared one: a JPEG
// sent as image/x-exr is refused as what it is, not decoded by whichever reader accepts it.
// Bytes of no known signature go on to the declared decoder, whose error says what is wrong.
void check_body_format(const ImageMediaType& declared, const std::string& body) {
    const std::string found = image_format_of(std::as_bytes(std::span(body.data(), body.size())));
    if (found.empty() || found == declared.format) {
        return;
    }
    const auto actual =
        std::find_if(std::begin(kImageMediaTypes), std::end(kImageMediaTypes),
                     [&found](const ImageMediaType& known) { return known.format == found; });
    const std::string_view actual_type =
        actual == std::end(kImageMediaTypes) ? std::string_view(found) : actual->media_type;
    throw HttpError(problem(ProblemKind::UnsupportedMediaType,
                            "the body is " + std::string(actual_type) + ", not " +
                                std::string(declared.media_type) + " as its Content-Type says"));
}

// The media type of a map stored under this extension (nullptr for one no upload makes).
nlohmann::json media_type_of_extension(const std::string& extension) {
    for (const ImageMediaType& known : kImageMediaTypes) {
        if (known.map && known.extension == extension) {
            return known.media_type;
        }
    }
    return nullptr;
}

// The key of an environment's preview in the cache of encoded frames.
std::string preview_key(const std::string& id) {
    return "preview:" + id;
}

const StoredAssetKind kEnvironmentKind{"/v1/environments", "environments", "environment",
                                       "the built-in studio environment"};

// A listing's entry: the map it was made from, when the store still holds it.
nlohmann::json listed_environment(const ListedAsset& entry) {
    return {
        {"source", entry.source_id},
        {"media_type", entry.source ? media_type_of_extension(entry.source->extension) : nullptr},
        {"bytes", entry.source ? nlohmann::json(entry.source->bytes) : nullptr}};
}

std::shared_ptr<const Environment> environment_of(ServiceContext& context,
                                                  const httplib::Request& request) {
    return requested_asset(context.environments, kEnvironmentKind, request);
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
        "/v1/environments",
        RoutePolicy{.needs_api_key = true, .max_body = context.config.max_upload_bytes},
        [](const httplib::Request& request, httplib::Response&) {
            map_media_type(media_type(request));
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            std::map<std::string, std::string> parameters;
            for (const auto& [name, value] : request.params) {
                if (!parameters.emplace(name, value).second) {
                    throw api::InvalidParameter(name, "given more than once");
                }
            }
            // The file's name is for messages; the rest are the rig's options.
            std::map<std::string, std::string> file_name;
            if (const auto given = parameters.find("filename"); given != parameters.end()) {
                file_name.insert(*given);
                parameters.erase(given);
            }
            const RigOptions options = api::parse_rig_options(parameters);
            if (body.empty()) {
                throw api::InvalidParameter("body", "the body must be the map's bytes");
            }
            const ImageMediaType& declared = map_media_type(media_type(request));
            check_body_format(declared, body);
            const std::string extension(declared.extension);
            const auto upload = context.environments.upload(body, extension, options,
                                                            upload_file_name(file_name, extension));
            send_upload(response, upload.asset->json, upload.cached,
                        "/v1/environments/" + upload.asset->id);
        });

    add_asset_listing_route(router, context.environments, kEnvironmentKind, listed_environment);
    add_asset_reading_route(router, context.environments, kEnvironmentKind);
    add_asset_removal_route(
        router, context.environments, kEnvironmentKind,
        [&context](const std::string& id) { context.frames.erase(preview_key(id)); });

    router.get("/v1/environments/{id}/preview.jpg", [&context](const httplib::Request& request,
                                                               httplib::Response& response) {
        single_query(request, {});
        const auto environment = environment_of(context, request);
        const std::string key = preview_key(environment->id);
        auto preview = context.frames.get(key);
        if (!preview) {
            const auto map = context.environments.source_image(*environment);
            if (!map) {
                throw not_found(ProblemKind::MapNotStored,
                                "the map of environment '" + environment->id +
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
