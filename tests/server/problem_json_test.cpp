// RFC 9457 problem bodies: exact members, one type and one status per kind (the one table), the
// table as api/openapi.yaml documents it, and misuse caught as bugs.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>

#include "oer/core/error.hpp"
#include "oer/server/problem_json.hpp"
#include "openapi_spec.hpp"

using namespace oer::server;
using Json = nlohmann::json;

TEST(ProblemJson, CarriesTheStandardAndExtensionMembers) {
    Problem problem;
    problem.kind = ProblemKind::InvalidParameter;
    problem.detail = "width: must be in 1..4096, got 5000";
    problem.instance = "/v1/render";
    problem.extensions["parameter"] = "width";
    EXPECT_EQ(problem_to_json(problem), Json::parse(R"({
        "type": "/v1/problems/invalid-parameter",
        "title": "Invalid parameter",
        "status": 422,
        "detail": "width: must be in 1..4096, got 5000",
        "instance": "/v1/render",
        "parameter": "width"
    })"));
    EXPECT_EQ(problem.status(), 422);
    EXPECT_EQ(kProblemContentType, "application/problem+json");
}

TEST(ProblemJson, WithoutAnInstanceThereIsNoInstanceMember) {
    Problem problem;
    problem.kind = ProblemKind::UnknownId;
    problem.detail = "no environment abc";
    EXPECT_EQ(problem_to_json(problem).dump(),
              R"({"detail":"no environment abc","status":404,)"
              R"("title":"No environment or mesh has this id","type":"/v1/problems/unknown-id"})");
}

// Clients switch on the type: every kind has one, no two kinds share one (nor a title), each a
// path under /v1/problems/ with an error status.
TEST(ProblemJson, EveryKindHasItsOwnTypeTitleAndAnErrorStatus) {
    std::set<std::string_view> types, titles;
    const std::regex path("^/v1/problems/[a-z]+(-[a-z]+)*$");
    std::size_t index = 0;
    for (const ProblemType& type : problem_types()) {
        SCOPED_TRACE(std::string(type.type));
        EXPECT_EQ(std::size_t(type.kind), index++) << "the table is in the order of ProblemKind";
        EXPECT_EQ(&problem_type(type.kind), &type);
        EXPECT_TRUE(std::regex_match(std::string(type.type), path));
        EXPECT_TRUE(types.insert(type.type).second) << "two kinds share this type";
        EXPECT_FALSE(type.title.empty());
        EXPECT_TRUE(titles.insert(type.title).second) << "two kinds share the title " << type.title;
        EXPECT_GE(type.status, 400);
        EXPECT_LE(type.status, 599);
    }
    EXPECT_EQ(std::size_t(ProblemKind::InsufficientStorage) + 1, problem_types().size())
        << "the last kind closes the table";
}

TEST(ProblemJson, AKindOutsideTheTableIsABug) {
    try {
        problem_type(ProblemKind(problem_types().size()));
        ADD_FAILURE() << "no error";
    } catch (const oer::Error& error) {
        EXPECT_EQ(error.kind(), oer::ErrorKind::Internal);
    }
}

TEST(ProblemJson, AnExtensionMayNotReplaceAStandardMember) {
    for (const char* member : {"type", "title", "status", "detail", "instance"}) {
        Problem problem;
        problem.kind = ProblemKind::MalformedRequest;
        problem.extensions[member] = "x";
        try {
            problem_to_json(problem);
            ADD_FAILURE() << member;
        } catch (const oer::Error& error) {
            EXPECT_EQ(error.kind(), oer::ErrorKind::Internal);
        }
    }
}

namespace {

// The types a problem response of the spec allows: its schema's `type` const or enum.
std::set<std::string> allowed_types(const Json& response, const Json& document) {
    const Json* resolved = &response;
    while (resolved->contains("$ref")) {
        resolved =
            &document.at(Json::json_pointer(resolved->at("$ref").get<std::string>().substr(1)));
    }
    std::set<std::string> types;
    if (!resolved->contains("content") ||
        !resolved->at("content").contains("application/problem+json")) {
        return types;
    }
    const Json& schema = resolved->at("content").at("application/problem+json").at("schema");
    for (const Json& part : schema.value("allOf", Json::array())) {
        const Json type = part.value("properties", Json::object()).value("type", Json::object());
        if (type.contains("const")) {
            types.insert(type.at("const").get<std::string>());
        }
        for (const Json& value : type.value("enum", Json::array())) {
            types.insert(value.get<std::string>());
        }
    }
    if (types.empty()) {
        ADD_FAILURE() << "a problem response allows every type: " << resolved->dump();
    }
    return types;
}

}  // namespace

// api/openapi.yaml's ProblemType lists exactly the table's types, each described with its
// status; and every problem response of every operation allows only types of its status.
TEST(ProblemJsonOpenApi, TheSpecDocumentsExactlyTheTable) {
    const Json& document = oer::testing::openapi_spec().json();
    const Json& listed = document.at("components").at("schemas").at("ProblemType").at("oneOf");
    std::map<std::string, int> spec_status;
    for (const Json& entry : listed) {
        const std::string type = entry.at("const");
        const std::string description = entry.at("description");
        EXPECT_TRUE(spec_status.emplace(type, std::stoi(description.substr(0, 3))).second)
            << type << " is listed twice";
        EXPECT_EQ(description.substr(3, 2), ". ") << type << ": " << description;
    }
    std::map<std::string, int> table_status;
    for (const ProblemType& type : problem_types()) {
        table_status.emplace(std::string(type.type), type.status);
    }
    EXPECT_EQ(spec_status, table_status);
    EXPECT_EQ(document.at("components").at("schemas").at("Problem").at("properties").at("type"),
              Json({{"$ref", "#/components/schemas/ProblemType"}}));

    int checked = 0;
    for (const auto& [path, item] : document.at("paths").items()) {
        for (const auto& [method, operation] : item.items()) {
            for (const auto& [status, response] : operation.at("responses").items()) {
                if (status[0] != '4' && status[0] != '5') {
                    continue;
                }
                for (const std::string& type : allowed_types(response, document)) {
                    ++checked;
                    ASSERT_TRUE(table_status.count(type)) << method << " " << path << ": " << type;
                    EXPECT_EQ(std::to_string(table_status.at(type)), status)
                        << method << " " << path << " lists " << type << " under " << status;
                }
            }
        }
    }
    EXPECT_GT(checked, 50);
}
