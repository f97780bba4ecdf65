#pragma once
// Error bodies of the HTTP API in the shape of RFC 9457 ("Problem Details for HTTP APIs"), so
// that every client reads every failure the same way: a problem type to switch on, its status,
// a human-readable title and detail, and extra members such as the offending "parameter".
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace oer::server {

inline constexpr std::string_view kProblemContentType = "application/problem+json";

// What went wrong, in the terms a client acts on. Each kind has one status and one type URI
// (problem_types(), the one table; api/openapi.yaml's ProblemType documents it).
enum class ProblemKind {
    MalformedRequest,      // 400: the request or its body cannot be read
    Unauthorized,          // 401: the API key is missing or wrong
    NotFound,              // 404: nothing is at this path (no route, no web file)
    UnknownId,             // 404: no environment or mesh has that id
    MapNotStored,          // 404: the environment's map is no longer stored
    MethodNotAllowed,      // 405: the path exists, not with this method
    PresetNotDeletable,    // 409: the built-in preset cannot be deleted
    LimitExceeded,         // 413: over a size limit of the server
    UriTooLong,            // 414: the request line is longer than the server reads
    UnsupportedMediaType,  // 415: a Content-Type the route does not read, or a body of another
    RangeNotSatisfiable,   // 416: a Range header's only range starts past the end
    InvalidParameter,      // 422: a member or parameter is invalid (`parameter` names it)
    InvalidContent,        // 422: well-formed, yet its content cannot be used (an upload that
                           //      does not decode, a scene the renderer refuses)
    TooManyConnections,    // 429: the client's address holds as many connections as it may
    TooManyRenders,        // 429: the client's share of uncached rendering is used up
    HeaderFieldsTooLarge,  // 431: a header line is longer than the server reads
    Internal,              // 500: the server's fault; its log has the cause
    Unavailable,           // 503: try again after Retry-After
    InsufficientStorage,   // 507: the server's storage is full; nothing of the request was kept
};

struct ProblemType {
    ProblemKind kind;
    int status;
    // A relative reference with the full path (RFC 9457 section 3.1.1), e.g.
    // "/v1/problems/unknown-id"; compare it as given.
    std::string_view type;
    std::string_view title;  // the same for every occurrence of the kind (section 3.1.3)
};

// Every kind, once each, in the order of ProblemKind.
std::span<const ProblemType> problem_types();
const ProblemType& problem_type(ProblemKind kind);

struct Problem {
    ProblemKind kind = ProblemKind::Internal;
    std::string detail;
    std::optional<std::string> instance;  // the request's path, when it identifies the failure
    // Extension members, e.g. {"parameter": "width"}. They may not reuse a standard member's
    // name (type, title, status, detail, instance): that throws oer::Error (Internal).
    nlohmann::json extensions = nlohmann::json::object();

    int status() const { return problem_type(kind).status; }
};

// {"type", "title", "status" (the kind's), "detail", "instance"?, extensions...}
nlohmann::json problem_to_json(const Problem& problem);

}  // namespace oer::server
