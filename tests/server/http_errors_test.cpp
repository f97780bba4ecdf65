#include <gtest/gtest.h>

#include "http_errors.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/server/asset_store.hpp"
#include "render_pool.hpp"

using namespace oer;
using namespace oer::server;

namespace {

template <typename Exception>
ErrorAnswer answer_to(const Exception& exception) {
    return error_answer(std::make_exception_ptr(exception));
}

std::string header(const ErrorAnswer& answer, const std::string& name) {
    for (const auto& [key, value] : answer.headers) {
        if (key == name) {
            return value;
        }
    }
    return "";
}

}  // namespace

TEST(HttpErrors, MapsEveryErrorKind) {
    EXPECT_EQ(problem_kind_of(ErrorKind::InvalidInput), ProblemKind::InvalidContent);
    EXPECT_EQ(problem_kind_of(ErrorKind::Unsupported), ProblemKind::InvalidContent);
    EXPECT_EQ(problem_kind_of(ErrorKind::LimitExceeded), ProblemKind::LimitExceeded);
    EXPECT_EQ(problem_kind_of(ErrorKind::Io), ProblemKind::Internal);
    EXPECT_EQ(problem_kind_of(ErrorKind::Internal), ProblemKind::Internal);
    EXPECT_EQ(answer_to(Error(ErrorKind::InvalidInput, "not an EXR")).problem.status(), 422);
}

TEST(HttpErrors, MalformedBodiesAre400AndInvalidMembers422NamingThem) {
    const ErrorAnswer malformed = answer_to(api::MalformedRequest("eof"));
    EXPECT_EQ(malformed.problem.kind, ProblemKind::MalformedRequest);
    EXPECT_EQ(malformed.problem.status(), 400);
    const ErrorAnswer invalid = answer_to(api::InvalidParameter("camera/orbit/pitch", "too big"));
    EXPECT_EQ(invalid.problem.kind, ProblemKind::InvalidParameter);
    EXPECT_EQ(invalid.problem.status(), 422);
    EXPECT_EQ(invalid.problem.extensions.at("parameter"), "camera/orbit/pitch");
    EXPECT_NE(invalid.problem.detail.find("too big"), std::string::npos);
}

TEST(HttpErrors, LimitsAre413AndAFullQueue503WithRetryAfter) {
    EXPECT_EQ(answer_to(Error(ErrorKind::LimitExceeded, "too many pixels")).problem.kind,
              ProblemKind::LimitExceeded);
    const ErrorAnswer over =
        answer_to(api::InvalidParameter("width", "must be at most 4096", ErrorKind::LimitExceeded));
    EXPECT_EQ(over.problem.kind, ProblemKind::LimitExceeded);
    EXPECT_EQ(over.problem.extensions.at("parameter"), "width");
    const ErrorAnswer full = answer_to(QueueFull("full"));
    EXPECT_EQ(full.problem.kind, ProblemKind::Unavailable);
    EXPECT_EQ(full.problem.status(), 503);
    EXPECT_EQ(header(full, "Retry-After"), "1");
    EXPECT_EQ(header(answer_to(unavailable("busy")), "Retry-After"), "1");
}

TEST(HttpErrors, RouteAnswersKeepTheirKindAndHeaders) {
    const ErrorAnswer missing =
        answer_to(not_found(ProblemKind::UnknownId, "no mesh", "objects/0/mesh"));
    EXPECT_EQ(missing.problem.kind, ProblemKind::UnknownId);
    EXPECT_EQ(missing.problem.status(), 404);
    EXPECT_EQ(missing.problem.extensions.at("parameter"), "objects/0/mesh");
    EXPECT_FALSE(answer_to(not_found(ProblemKind::NotFound, "no file"))
                     .problem.extensions.contains("parameter"));
    const ErrorAnswer unauthorised = answer_to(
        HttpError(problem(ProblemKind::Unauthorized, "key"), {{"WWW-Authenticate", "Bearer"}}));
    EXPECT_EQ(unauthorised.problem.status(), 401);
    EXPECT_EQ(header(unauthorised, "WWW-Authenticate"), "Bearer");
    EXPECT_FALSE(unauthorised.internal);
}

TEST(HttpErrors, InternalFailuresHideTheirCauseFromTheClient) {
    const ErrorAnswer io = answer_to(Error(ErrorKind::Io, "cannot write /secret/path"));
    EXPECT_EQ(io.problem.kind, ProblemKind::Internal);
    EXPECT_EQ(io.problem.status(), 500);
    EXPECT_TRUE(io.internal);
    EXPECT_EQ(io.problem.detail.find("/secret/path"), std::string::npos);
    EXPECT_NE(io.cause.find("/secret/path"), std::string::npos);
    EXPECT_EQ(answer_to(std::runtime_error("boom")).problem.status(), 500);
}

TEST(HttpErrors, AFullDiskIs507NamingTheEntryNotThePath) {
    const ErrorAnswer full = answer_to(StorageFull(
        "the mesh 3f2a", "No space left on device",
        "asset store: cannot write /secret/meshes/.tmp-3f2a.glb-x: No space left on device"));
    EXPECT_EQ(full.problem.kind, ProblemKind::InsufficientStorage);
    EXPECT_EQ(full.problem.status(), 507);
    EXPECT_NE(full.problem.detail.find("the mesh 3f2a could not be stored"), std::string::npos)
        << full.problem.detail;
    EXPECT_NE(full.problem.detail.find("No space left on device"), std::string::npos);
    EXPECT_NE(full.problem.detail.find("storage is full"), std::string::npos);
    EXPECT_EQ(full.problem.detail.find("/secret"), std::string::npos) << full.problem.detail;
    EXPECT_TRUE(full.internal);
    EXPECT_NE(full.cause.find("/secret/meshes"), std::string::npos);
}
