// POST /v1/render (JSON body) and GET /v1/render (query parameters)
#include <cstdio>

#include "http_exchange.hpp"
#include "oer/api/parameter_text.hpp"
#include "request_state.hpp"
#include "service_context.hpp"

namespace oer::server {

namespace {

// Frames are addressed by their request (ids are content hashes; the ETag holds the version):
// caches may keep them a day, then revalidate with the ETag for a cheap 304.
constexpr const char* kFrameCacheControl = "public, max-age=86400";

// X-Oer-Camera: the camera the frame is seen from, in the query's notation, so that a client
// can continue from the automatic framing (zoom from its distance, say) without a jump:
// `eye=0,1.2,3.4; target=0,0.8,0; up=0,1,0; fov_y=45`.
std::string camera_header(const Camera& camera) {
    const auto vector = [](const glm::vec3& v) {
        char text[64];
        std::snprintf(text, sizeof text, "%.6g,%.6g,%.6g", double(v.x), double(v.y), double(v.z));
        return std::string(text);
    };
    char fov_y[32];
    std::snprintf(fov_y, sizeof fov_y, "%.6g", double(camera.fov_y));
    return "eye=" + vector(camera.eye) + "; target=" + vector(camera.target) +
           "; up=" + vector(camera.up) + "; fov_y=" + fov_y;
}

void answer_frame(ServiceContext& context, const httplib::Request& request,
                  httplib::Response& response, const api::RenderSpec& spec, RequestForm form) {
    const std::string etag = api::render_etag(spec);
    if (etag_matches(request, etag)) {
        response.status = 304;
        response.set_header("Cache-Control", kFrameCacheControl);
        response.set_header("ETag", etag);
        return;
    }
    // The client whose share of uncached rendering a miss is charged to: its address (behind
    // a proxy, the proxy's, which shares out its own clients).
    const EncodedFrame frame =
        context.frame_service.render(spec, etag, form, {request.remote_addr, client_has_gone});
    // Set only now: an error answer (a 503 while the renderer cannot start) must not be kept
    // by caches for a day.
    response.set_header("Cache-Control", kFrameCacheControl);
    response.status = 200;
    response.set_header("ETag", frame.etag);
    response.set_header("X-Oer-Cache", frame.cache_hit ? "hit" : "miss");
    response.set_header("X-Oer-Camera", camera_header(frame.camera));
    if (!frame.server_timing.empty()) {
        response.set_header("Server-Timing", frame.server_timing);
    }
    response.set_content(*frame.bytes, frame.content_type);
}

}  // namespace

void add_render_routes(Router& router, ServiceContext& context) {
    router.post(
        "/v1/render", RoutePolicy{.max_body = context.render_limits.max_body_bytes},
        [](const httplib::Request& request, httplib::Response&) {
            if (const std::string type = media_type(request); type != "application/json") {
                throw HttpError(problem(
                    ProblemKind::UnsupportedMediaType,
                    "a render request is application/json, not '" + api::excerpt(type) + "'"));
            }
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            single_query(request, {});
            answer_frame(context, request, response,
                         api::parse_render_json(body, context.render_limits), RequestForm::Json);
        });

    router.get(
        "/v1/render", [&context](const httplib::Request& request, httplib::Response& response) {
            const std::multimap<std::string, std::string> query(request.params.begin(),
                                                                request.params.end());
            answer_frame(context, request, response,
                         api::parse_render_query(query, context.render_limits), RequestForm::Query);
        });
}

}  // namespace oer::server
