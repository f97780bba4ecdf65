// POST /v1/render (JSON body) and GET /v1/render (query parameters)
#include <optional>
#include <string>

#include "http_exchange.hpp"
#include "request_state.hpp"
#include "service_context.hpp"

namespace oer::server {

namespace {

// Frames are addressed by their request (ids are content hashes; the ETag holds the version):
// caches may keep them a day, then revalidate with the ETag for a cheap 304.
constexpr const char* kFrameCacheControl = "public, max-age=86400";

// The client's `Prefer: wait=N` (RFC 7240 section 4.3: it would rather have an answer within N
// seconds than the full work), as its seconds; nullopt without one. Other preferences are left
// alone, as the RFC says a server may; a malformed wait is no preference.
std::optional<long> preferred_wait(const httplib::Request& request) {
    const std::string header = request.get_header_value("Prefer");
    std::size_t start = 0;
    while (start < header.size()) {
        std::size_t end = header.find_first_of(",;", start);
        end = end == std::string::npos ? header.size() : end;
        std::string token = header.substr(start, end - start);
        token.erase(0, token.find_first_not_of(" \t"));
        token.erase(token.find_last_not_of(" \t") + 1);
        if (token.size() > 5 &&
            (token.compare(0, 5, "wait=") == 0 || token.compare(0, 5, "WAIT=") == 0)) {
            const std::string digits = token.substr(5);
            if (digits.size() <= 9 && digits.find_first_not_of("0123456789") == std::string::npos) {
                return std::stol(digits);
            }
        }
        start = end + 1;
    }
    return std::nullopt;
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
    // A client that prefers a quick answer gets, while its scene's transfer is baked, the frame
    // without it, marked preliminary (X-Oer-Preliminary), for no client to keep and without an
    // ETag (it is not the representation the request names); it asks again for the whole one,
    // and meanwhile gets the same preliminary frame from the server's memory.
    const std::optional<long> wait = preferred_wait(request);
    const EncodedFrame frame = context.frame_service.render(
        spec, etag, form, {request.remote_addr, client_has_gone}, wait.has_value());
    response.status = 200;
    if (frame.preliminary) {
        response.set_header("Cache-Control", "no-store");
        response.set_header("Preference-Applied", "wait=" + std::to_string(*wait));
        response.set_header("X-Oer-Preliminary", "transfer");
    } else {
        // Set only now: an error answer (a 503 while the renderer cannot start) must not be
        // kept by caches for a day.
        response.set_header("Cache-Control", kFrameCacheControl);
        response.set_header("ETag", frame.etag);
    }
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
            require_json_body(request, "a render request");
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
