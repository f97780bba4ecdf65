#pragma once
// Routes over cpp-httplib, each registered under its pattern as api/openapi.yaml writes it
// ("/v1/environments/{id}"): the pattern names the route in metrics and logs, every failure
// inside a handler becomes a problem+json answer (http_errors), and the table answers which
// methods a path allows (405, CORS preflight). Bodies of POST routes are read here, bounded:
// a body over the route's limit (declared or, for chunked bodies, counted as it arrives) is
// answered 413 without reading the rest, and the connection is closed.
#include <functional>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include <httplib.h>

namespace oer::server {

class Router {
  public:
    using Log = std::function<void(std::string_view)>;
    using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
    using BodyHandler =
        std::function<void(const httplib::Request&, httplib::Response&, const std::string& body)>;

    Router(httplib::Server& server, Log log);

    void get(const std::string& route, Handler handler);
    // DELETE (`delete` is C++'s).
    void del(const std::string& route, Handler handler);
    // before_body runs first (authentication, media type), so that a refused upload is never
    // read; then the body (at most max_body bytes) goes to handler.
    void post(const std::string& route, std::size_t max_body, Handler before_body,
              BodyHandler handler);

    // The methods of the routes whose pattern matches path (empty: no route).
    std::vector<std::string> methods_for(const std::string& path) const;

  private:
    struct Route {
        std::string method;
        std::regex pattern;
    };
    // Adds method and route to the table and returns handler run as route's, for a route whose
    // body (if any) is cpp-httplib's to read.
    httplib::Server::Handler without_body(const std::string& method, const std::string& route,
                                          Handler handler);
    // Runs handler as route's, answering any exception it throws.
    void guarded(const std::string& route, const httplib::Request& request,
                 httplib::Response& response, const std::function<void()>& handler) const;

    httplib::Server& server_;
    const Log log_;
    std::vector<Route> routes_;
};

// "/v1/environments/{id}" -> "/v1/environments/([^/]+)"
std::string route_regex(const std::string& route);

}  // namespace oer::server
