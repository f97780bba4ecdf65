#pragma once
// Error bodies of the HTTP API in the shape of RFC 9457 ("Problem Details for HTTP APIs"), so
// that every client reads every failure the same way: a machine-readable status and type, a
// human-readable title and detail, and extra members such as the offending "parameter".
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace oer::server {

inline constexpr std::string_view kProblemContentType = "application/problem+json";

// The reason phrase of the statuses the service answers with (400, 401, 404, 405, 409, 413,
// 415, 422, 429, 500, 503); any other status is a bug in the caller and throws oer::Error
// (ErrorKind::Internal).
std::string_view reason_phrase(int status);

struct Problem {
    int status = 500;
    std::string detail;
    // "about:blank" means the problem has no meaning beyond its status (RFC 9457 section 4.2.1).
    std::string type = "about:blank";
    std::optional<std::string> instance;  // the request's path, when it identifies the failure
    // Extension members, e.g. {"parameter": "width"}. They may not reuse a standard member's
    // name (type, title, status, detail, instance): that throws oer::Error (Internal).
    nlohmann::json extensions = nlohmann::json::object();
};

// {"type", "title" (the status's reason phrase), "status", "detail", "instance"?, extensions...}
nlohmann::json problem_to_json(const Problem& problem);

}  // namespace oer::server
