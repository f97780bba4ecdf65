#pragma once
// The access log line of one request and the method label of its metrics.
#include <cstddef>
#include <string>

namespace oer::server {

// "GET /v1/render?environment=default 200 51234 B 12.3 ms"; the target is cut at 200
// characters, so that a client cannot fill the log with one request.
std::string access_log_line(const std::string& method, const std::string& target, int status,
                            std::size_t bytes, double milliseconds);

// The method as a metric label: the HTTP methods by name, anything else "other" (a client
// must not be able to create series).
std::string method_label(const std::string& method);

}  // namespace oer::server
