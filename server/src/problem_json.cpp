#include "oer/server/problem_json.hpp"

#include <array>

#include "oer/core/error.hpp"

namespace oer::server {

namespace {

// The one table of problem kinds. A type is a relative reference with the full path,
// "/v1/problems/<kind>" (RFC 9457 section 3.1.1 asks relative types to carry the full path): it
// names no host, because the service has no domain of its own (a made-up "https://oer.example/"
// would name someone else's, and a tag: URI needs an authority we do not have), and it resolves
// against whichever server answered, in the API's own path space. Clients compare it as given.
// The types are part of the contract: a kind may be added, never renamed.
constexpr std::array<ProblemType, 19> kProblemTypes{{
    {ProblemKind::MalformedRequest, 400, "/v1/problems/malformed-request", "Malformed request"},
    {ProblemKind::Unauthorized, 401, "/v1/problems/unauthorized", "API key missing or wrong"},
    {ProblemKind::NotFound, 404, "/v1/problems/not-found", "Nothing at this path"},
    {ProblemKind::UnknownId, 404, "/v1/problems/unknown-id", "No environment or mesh has this id"},
    {ProblemKind::MapNotStored, 404, "/v1/problems/map-not-stored",
     "The environment's map is no longer stored"},
    {ProblemKind::MethodNotAllowed, 405, "/v1/problems/method-not-allowed", "Method not allowed"},
    {ProblemKind::PresetNotDeletable, 409, "/v1/problems/preset-not-deletable",
     "The built-in preset cannot be deleted"},
    {ProblemKind::LimitExceeded, 413, "/v1/problems/limit-exceeded", "Over a limit of the server"},
    {ProblemKind::UriTooLong, 414, "/v1/problems/uri-too-long", "Request line too long"},
    {ProblemKind::UnsupportedMediaType, 415, "/v1/problems/unsupported-media-type",
     "Unsupported media type"},
    {ProblemKind::RangeNotSatisfiable, 416, "/v1/problems/range-not-satisfiable",
     "Range not satisfiable"},
    {ProblemKind::InvalidParameter, 422, "/v1/problems/invalid-parameter", "Invalid parameter"},
    {ProblemKind::InvalidContent, 422, "/v1/problems/invalid-content",
     "Content that cannot be used"},
    {ProblemKind::TooManyConnections, 429, "/v1/problems/too-many-connections",
     "Too many connections from this address"},
    {ProblemKind::TooManyRenders, 429, "/v1/problems/too-many-renders",
     "Too many uncached renders from this client"},
    {ProblemKind::HeaderFieldsTooLarge, 431, "/v1/problems/header-fields-too-large",
     "Request header fields too large"},
    {ProblemKind::Internal, 500, "/v1/problems/internal-error", "Internal error"},
    {ProblemKind::Unavailable, 503, "/v1/problems/unavailable", "Unavailable; retry later"},
    // RFC 4918 section 11.5.
    {ProblemKind::InsufficientStorage, 507, "/v1/problems/insufficient-storage",
     "The server's storage is full"},
}};

constexpr bool in_enum_order() {
    for (std::size_t i = 0; i < kProblemTypes.size(); ++i) {
        if (kProblemTypes[i].kind != ProblemKind(i)) {
            return false;
        }
    }
    return kProblemTypes.back().kind == ProblemKind::InsufficientStorage;
}
static_assert(in_enum_order(), "kProblemTypes lists every ProblemKind once, in order");

constexpr std::array<std::string_view, 5> kStandardMembers{"type", "title", "status", "detail",
                                                           "instance"};

}  // namespace

std::span<const ProblemType> problem_types() {
    return kProblemTypes;
}

const ProblemType& problem_type(ProblemKind kind) {
    const auto index = std::size_t(kind);
    if (index >= kProblemTypes.size()) {
        throw Error(ErrorKind::Internal,
                    "problem kind " + std::to_string(index) + " is not in the table of kinds");
    }
    return kProblemTypes[index];
}

nlohmann::json problem_to_json(const Problem& problem) {
    if (!problem.extensions.is_object()) {
        throw Error(ErrorKind::Internal,
                    "problem extensions must be a JSON object, got " + problem.extensions.dump());
    }
    const ProblemType& type = problem_type(problem.kind);
    nlohmann::json body = {
        {"type", type.type},
        {"title", type.title},
        {"status", type.status},
        {"detail", problem.detail},
    };
    if (problem.instance) {
        body["instance"] = *problem.instance;
    }
    for (const auto& [name, value] : problem.extensions.items()) {
        for (const std::string_view standard : kStandardMembers) {
            if (name == standard) {
                throw Error(ErrorKind::Internal, "problem extension member \"" + name +
                                                     "\" would replace the standard "
                                                     "member of that name");
            }
        }
        body[name] = value;
    }
    return body;
}

}  // namespace oer::server
