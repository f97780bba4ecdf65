#include "cors.hpp"

#include <algorithm>

#include "http_errors.hpp"
#include "http_exchange.hpp"

namespace oer::server {

void add_cors_headers(const std::vector<std::string>& origins, const httplib::Request& request,
                      httplib::Response& response) {
    if (origins.empty()) {
        return;
    }
    response.set_header("Vary", "Origin");
    const std::string origin = request.get_header_value("Origin");
    const bool allowed = std::find(origins.begin(), origins.end(), "*") != origins.end() ||
                         std::find(origins.begin(), origins.end(), origin) != origins.end();
    if (origin.empty() || !allowed) {
        return;
    }
    response.set_header("Access-Control-Allow-Origin", origin);
    response.set_header("Access-Control-Expose-Headers",
                        "ETag, Server-Timing, X-Oer-Cache, X-Oer-Camera, X-Oer-Preliminary, "
                        "Preference-Applied");
}

void answer_preflight(const std::vector<std::string>& methods, httplib::Response& response) {
    if (methods.empty()) {
        send_problem(response,
                     {problem(ProblemKind::NotFound, "no route has this path"), {}, false, ""});
        return;
    }
    std::string allow = "OPTIONS";
    for (const std::string& method : methods) {
        allow += ", " + method;
    }
    response.status = 204;
    response.set_header("Allow", allow);
    response.set_header("Access-Control-Allow-Methods", allow);
    response.set_header("Access-Control-Allow-Headers",
                        "Authorization, Content-Type, If-None-Match, Prefer");
    response.set_header("Access-Control-Max-Age", "600");
}

}  // namespace oer::server
