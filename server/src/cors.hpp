#pragma once
// Cross-origin access for browsers (the dressing room served from elsewhere): an allowed
// Origin is echoed in Access-Control-Allow-Origin (with Vary: Origin, since the answer depends
// on it), and preflight OPTIONS requests are answered with the route's methods.
#include <string>
#include <vector>

#include <httplib.h>

namespace oer::server {

// Adds the CORS headers to every answer to an allowed origin; origins may hold "*".
void add_cors_headers(const std::vector<std::string>& origins, const httplib::Request& request,
                      httplib::Response& response);

// The answer to OPTIONS on a path whose routes allow `methods` (204; 404 when none).
void answer_preflight(const std::vector<std::string>& methods, httplib::Response& response);

}  // namespace oer::server
