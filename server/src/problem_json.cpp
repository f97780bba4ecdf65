#include "oer/server/problem_json.hpp"

#include <array>
#include <utility>

#include "oer/core/error.hpp"

namespace oer::server {

namespace {

constexpr std::array<std::pair<int, std::string_view>, 11> kReasonPhrases{{
    {400, "Bad Request"},
    {401, "Unauthorized"},
    {404, "Not Found"},
    {405, "Method Not Allowed"},
    {409, "Conflict"},
    {413, "Content Too Large"},
    {415, "Unsupported Media Type"},
    {422, "Unprocessable Content"},
    {429, "Too Many Requests"},
    {500, "Internal Server Error"},
    {503, "Service Unavailable"},
}};

constexpr std::array<std::string_view, 5> kStandardMembers{"type", "title", "status", "detail",
                                                           "instance"};

}  // namespace

std::string_view reason_phrase(int status) {
    for (const auto& [code, phrase] : kReasonPhrases) {
        if (code == status) {
            return phrase;
        }
    }
    throw Error(ErrorKind::Internal,
                "no reason phrase for HTTP status " + std::to_string(status) +
                    " (the service answers only with the statuses listed in problem_json.hpp)");
}

nlohmann::json problem_to_json(const Problem& problem) {
    if (!problem.extensions.is_object()) {
        throw Error(ErrorKind::Internal,
                    "problem extensions must be a JSON object, got " + problem.extensions.dump());
    }
    nlohmann::json body = {
        {"type", problem.type},
        {"title", reason_phrase(problem.status)},
        {"status", problem.status},
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
