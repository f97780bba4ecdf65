#include "router.hpp"

#include <cstdlib>

#include "byte_ranges.hpp"
#include "cors.hpp"
#include "http_errors.hpp"
#include "http_exchange.hpp"
#include "request_state.hpp"

namespace oer::server {

namespace {

HttpError too_large(std::size_t limit) {
    current_request().close_connection = true;
    return HttpError(problem(ProblemKind::LimitExceeded, "the body is over this route's limit of " +
                                                             std::to_string(limit) + " bytes"));
}

// The body of a POST, read as it arrives and bounded by max_body: 413 at the first byte over
// (or at once, when Content-Length says so), without reading the rest.
std::string bounded_body(const httplib::Request& request, const httplib::ContentReader& read,
                         std::size_t max_body) {
    if (request.has_header("Content-Length") &&
        std::strtoull(request.get_header_value("Content-Length").c_str(), nullptr, 10) > max_body) {
        throw too_large(max_body);
    }
    std::string body;
    bool over = false;
    const bool complete = read([&](const char* data, std::size_t length) {
        if (body.size() + length > max_body) {
            over = true;
            return false;
        }
        body.append(data, length);
        return true;
    });
    if (over) {
        throw too_large(max_body);
    }
    if (!complete) {
        throw HttpError(
            problem(ProblemKind::MalformedRequest, "the body could not be read to its end"));
    }
    return body;
}

}  // namespace

std::string route_regex(const std::string& route) {
    return std::regex_replace(route, std::regex(R"(\{[a-z_]+\})"), "([^/]+)");
}

Router::Router(httplib::Server& server, Log log, RouterPolicies policies)
    : server_(server), log_(std::move(log)), policies_(std::move(policies)) {}

void Router::authorize(const RoutePolicy& policy, const httplib::Request& request) const {
    if (policy.needs_api_key && !policies_.api_key.empty()) {
        require_api_key(request, policies_.api_key);
    }
}

httplib::Server::HandlerResponse Router::before_routing(const httplib::Request& request,
                                                        httplib::Response& response) const {
    add_cors_headers(policies_.cors_origins, request, response);
    current_request().ranges = take_byte_ranges(request);
    if (request.method != "OPTIONS") {
        return httplib::Server::HandlerResponse::Unhandled;
    }
    current_request().route = "preflight";
    answer_preflight(methods_for(request.path), response);
    return httplib::Server::HandlerResponse::Handled;
}

void Router::guarded(const std::string& route, const httplib::Request& request,
                     httplib::Response& response, const std::function<void()>& handler) const {
    current_request().route = route;
    try {
        handler();
    } catch (...) {
        const ErrorAnswer answer = error_answer(std::current_exception());
        if (answer.internal) {
            log_("error: " + request.method + " " + route + ": " + answer.cause);
        }
        send_problem(response, answer);
    }
}

void Router::get(const std::string& route, Handler handler, RoutePolicy policy) {
    server_.Get(route_regex(route), without_body("GET", route, std::move(handler), policy));
}

void Router::del(const std::string& route, Handler handler, RoutePolicy policy) {
    server_.Delete(route_regex(route), without_body("DELETE", route, std::move(handler), policy));
}

httplib::Server::Handler Router::without_body(const std::string& method, const std::string& route,
                                              Handler handler, RoutePolicy policy) {
    routes_.push_back({method, std::regex(route_regex(route))});
    return [this, route, handler, policy](const httplib::Request& request,
                                          httplib::Response& response) {
        guarded(route, request, response, [&] {
            authorize(policy, request);
            handler(request, response);
        });
        // HEAD reaches GET's handlers; RFC 9110 section 14.2 gives ranges to GET alone.
        if (request.method == "GET") {
            answer_byte_ranges(current_request().ranges, request, response);
        }
    };
}

void Router::post(const std::string& route, RoutePolicy policy, Handler before_body,
                  BodyHandler handler) {
    routes_.push_back({"POST", std::regex(route_regex(route))});
    server_.Post(route_regex(route),
                 [this, route, policy, before_body, handler](const httplib::Request& request,
                                                             httplib::Response& response,
                                                             const httplib::ContentReader& read) {
                     guarded(route, request, response, [&] {
                         // Until the body is read whole, an early answer leaves it on the
                         // connection.
                         current_request().close_connection = true;
                         authorize(policy, request);
                         before_body(request, response);
                         const std::string body = bounded_body(request, read, policy.max_body);
                         current_request().close_connection = false;
                         handler(request, response, body);
                     });
                 });
    // A POST without a body (no Content-Length, not chunked) reaches the plain handlers only.
    server_.Post(route_regex(route),
                 [this, route, policy, before_body, handler](const httplib::Request& request,
                                                             httplib::Response& response) {
                     guarded(route, request, response, [&] {
                         authorize(policy, request);
                         before_body(request, response);
                         handler(request, response, request.body);
                     });
                 });
}

std::vector<std::string> Router::methods_for(const std::string& path) const {
    std::vector<std::string> methods;
    for (const Route& route : routes_) {
        if (std::regex_match(path, route.pattern)) {
            methods.push_back(route.method);
        }
    }
    return methods;
}

}  // namespace oer::server
