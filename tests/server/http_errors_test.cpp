#include <gtest/gtest.h>

#include "http_errors.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
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
    EXPECT_EQ(status_of(ErrorKind::InvalidInput), 422);
    EXPECT_EQ(status_of(ErrorKind::Unsupported), 422);
    EXPECT_EQ(status_of(ErrorKind::LimitExceeded), 413);
    EXPECT_EQ(status_of(ErrorKind::Io), 500);
    EXPECT_EQ(status_of(ErrorKind::Internal), 500);
}

TEST(HttpErrors, MalformedBodiesAre400AndInvalidMembers422NamingThem) {
    EXPECT_EQ(answer_to(api::MalformedRequest("eof")).problem.status, 400);
    const ErrorAnswer invalid = answer_to(api::InvalidParameter("camera/orbit/pitch", "too big"));
    EXPECT_EQ(invalid.problem.status, 422);
    EXPECT_EQ(invalid.problem.extensions.at("parameter"), "camera/orbit/pitch");
    EXPECT_NE(invalid.problem.detail.find("too big"), std::string::npos);
}

TEST(HttpErrors, LimitsAre413AndAFullQueue503WithRetryAfter) {
    EXPECT_EQ(answer_to(Error(ErrorKind::LimitExceeded, "too many pixels")).problem.status, 413);
    const ErrorAnswer full = answer_to(QueueFull("full"));
    EXPECT_EQ(full.problem.status, 503);
    EXPECT_EQ(header(full, "Retry-After"), "1");
    EXPECT_EQ(header(answer_to(unavailable("busy")), "Retry-After"), "1");
}

TEST(HttpErrors, RouteAnswersKeepTheirStatusAndHeaders) {
    const ErrorAnswer missing = answer_to(not_found("no mesh", "objects/0/mesh"));
    EXPECT_EQ(missing.problem.status, 404);
    EXPECT_EQ(missing.problem.extensions.at("parameter"), "objects/0/mesh");
    const ErrorAnswer unauthorised =
        answer_to(HttpError(problem(401, "key"), {{"WWW-Authenticate", "Bearer"}}));
    EXPECT_EQ(unauthorised.problem.status, 401);
    EXPECT_EQ(header(unauthorised, "WWW-Authenticate"), "Bearer");
    EXPECT_FALSE(unauthorised.internal);
}

TEST(HttpErrors, InternalFailuresHideTheirCauseFromTheClient) {
    const ErrorAnswer io = answer_to(Error(ErrorKind::Io, "cannot write /secret/path"));
    EXPECT_EQ(io.problem.status, 500);
    EXPECT_TRUE(io.internal);
    EXPECT_EQ(io.problem.detail.find("/secret/path"), std::string::npos);
    EXPECT_NE(io.cause.find("/secret/path"), std::string::npos);
    EXPECT_EQ(answer_to(std::runtime_error("boom")).problem.status, 500);
}
