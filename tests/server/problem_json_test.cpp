// RFC 9457 problem bodies: exact members, reason phrases, and misuse caught as bugs.
#include <gtest/gtest.h>

#include "oer/core/error.hpp"
#include "oer/server/problem_json.hpp"

using namespace oer::server;

TEST(ProblemJson, CarriesTheStandardAndExtensionMembers) {
    Problem problem;
    problem.status = 422;
    problem.detail = "width: must be in 1..4096, got 5000";
    problem.instance = "/v1/render";
    problem.extensions["parameter"] = "width";
    EXPECT_EQ(problem_to_json(problem), nlohmann::json::parse(R"({
        "type": "about:blank",
        "title": "Unprocessable Content",
        "status": 422,
        "detail": "width: must be in 1..4096, got 5000",
        "instance": "/v1/render",
        "parameter": "width"
    })"));
    EXPECT_EQ(kProblemContentType, "application/problem+json");
}

TEST(ProblemJson, WithoutAnInstanceThereIsNoInstanceMember) {
    Problem problem;
    problem.status = 404;
    problem.detail = "no environment abc";
    problem.type = "https://oer.example/problems/unknown-asset";
    EXPECT_EQ(problem_to_json(problem).dump(),
              R"({"detail":"no environment abc","status":404,"title":"Not Found",)"
              R"("type":"https://oer.example/problems/unknown-asset"})");
}

TEST(ProblemJson, ReasonPhrases) {
    const std::vector<std::pair<int, std::string_view>> expected{
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
    };
    for (const auto& [status, phrase] : expected) {
        EXPECT_EQ(reason_phrase(status), phrase) << status;
    }
}

TEST(ProblemJson, AStatusTheServiceDoesNotAnswerWithIsABug) {
    for (const int status : {200, 418, 0, 599}) {
        try {
            reason_phrase(status);
            ADD_FAILURE() << status;
        } catch (const oer::Error& error) {
            EXPECT_EQ(error.kind(), oer::ErrorKind::Internal);
        }
    }
}

TEST(ProblemJson, AnExtensionMayNotReplaceAStandardMember) {
    for (const char* member : {"type", "title", "status", "detail", "instance"}) {
        Problem problem;
        problem.status = 400;
        problem.extensions[member] = "x";
        try {
            problem_to_json(problem);
            ADD_FAILURE() << member;
        } catch (const oer::Error& error) {
            EXPECT_EQ(error.kind(), oer::ErrorKind::Internal);
        }
    }
}
