#pragma once
// Routes over cpp-httplib, each registered under its pattern as api/openapi.yaml writes it
// ("/v1/environments/{id}"): the pattern names the route in metrics and logs, every failure
// inside a handler becomes a problem+json answer (http_errors), and the table answers which
// methods a path allows (405, CORS preflight). What cuts across routes is the router's, applied
// before a handler runs, as middleware (imgproxy's withSecret and withCORS): a route declares
// its RoutePolicy when it is registered, and no handler checks the API key or bounds its body
// itself. Bodies of POST routes are read here, bounded: a body over the route's limit (declared
// or, for chunked bodies, counted as it arrives) is answered 413 without reading the rest, and
// the connection is closed. CORS covers every answer of the listener, preflights and answers of
// no route included, so it is the router's, not a route's.
#include <functional>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include <httplib.h>

namespace oer::server {

// What a route declares when it is registered.
struct RoutePolicy {
    // Writes (uploads, deletions): "Authorization: Bearer <key>" when the service has a key,
    // checked before anything else of the request (a refused upload is never read).
    bool needs_api_key = false;
    // POST: the most bytes its body may hold.
    std::size_t max_body = 0;
};

// What the router's policies check requests against, from the service's configuration.
struct RouterPolicies {
    std::string api_key;                    // empty: no route needs a key
    std::vector<std::string> cors_origins;  // the origins answered with CORS headers (cors.hpp)
};

class Router {
  public:
    using Log = std::function<void(std::string_view)>;
    using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
    using BodyHandler =
        std::function<void(const httplib::Request&, httplib::Response&, const std::string& body)>;

    Router(httplib::Server& server, Log log, RouterPolicies policies);

    void get(const std::string& route, Handler handler, RoutePolicy policy = {});
    // DELETE (`delete` is C++'s).
    void del(const std::string& route, Handler handler, RoutePolicy policy = {});
    // before_body runs after the policy's checks (the media type, say), so that a refused
    // upload is never read; then the body (at most policy.max_body bytes) goes to handler.
    void post(const std::string& route, RoutePolicy policy, Handler before_body,
              BodyHandler handler);

    // The methods of the routes whose pattern matches path (empty: no route).
    std::vector<std::string> methods_for(const std::string& path) const;

    // For cpp-httplib's pre-routing: adds the CORS headers to the answer, and answers a
    // preflight (OPTIONS) itself.
    httplib::Server::HandlerResponse before_routing(const httplib::Request& request,
                                                    httplib::Response& response) const;

  private:
    struct Route {
        std::string method;
        std::regex pattern;
    };
    // Adds method and route to the table and returns handler run as route's, for a route whose
    // body (if any) is cpp-httplib's to read.
    httplib::Server::Handler without_body(const std::string& method, const std::string& route,
                                          Handler handler, RoutePolicy policy);
    // Throws 401 when the policy needs the API key and the request lacks it.
    void authorize(const RoutePolicy& policy, const httplib::Request& request) const;
    // Runs handler as route's, answering any exception it throws.
    void guarded(const std::string& route, const httplib::Request& request,
                 httplib::Response& response, const std::function<void()>& handler) const;

    httplib::Server& server_;
    const Log log_;
    const RouterPolicies policies_;
    std::vector<Route> routes_;
};

// "/v1/environments/{id}" -> "/v1/environments/([^/]+)"
std::string route_regex(const std::string& route);

}  // namespace oer::server
