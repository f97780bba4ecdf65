// Range requests against a real server (server/src/byte_ranges.hpp, RFC 9110 section 14): one
// satisfiable range of a GET answer is a 206 with its slice and Content-Range, a range past the
// end a 416 giving the length, and anything else the whole 200, so that no answer is larger
// than the representation and no 200 carries part of it.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

// A small frame of the built-in scene, cached by the first request of each test.
constexpr const char* kFramePath =
    "/v1/render?environment=default&mesh=default&width=64&height=48&samples=1&format=png";

class ByteRanges : public ::testing::Test {
  protected:
    void SetUp() override {
        server_ = std::make_unique<TestServer>(test_config(root_.data()));
        client_ = server_->client();
        const auto whole = client_->Get(kFramePath);
        ASSERT_TRUE(whole);
        ASSERT_EQ(whole->status, 200) << whole->body;
        EXPECT_EQ(whole->get_header_value("Accept-Ranges"), "bytes");
        frame_ = whole->body;
        etag_ = whole->get_header_value("ETag");
        ASSERT_GT(frame_.size(), 100u);
        ASSERT_FALSE(etag_.empty());
    }

    httplib::Result get(const std::string& range, const std::string& if_range = "") {
        httplib::Headers headers{{"Range", range}};
        if (!if_range.empty()) {
            headers.emplace("If-Range", if_range);
        }
        return client_->Get(kFramePath, headers);
    }

    TempRoot root_;
    std::unique_ptr<TestServer> server_;
    std::unique_ptr<httplib::Client> client_;
    std::string frame_;
    std::string etag_;
};

}  // namespace

TEST_F(ByteRanges, OneRangeIsA206WithItsSliceAndContentRange) {
    const std::size_t n = frame_.size();
    struct Case {
        std::string range;
        std::size_t begin, end;  // the slice [begin, end) of the frame
    };
    const Case cases[] = {
        {"bytes=0-10", 0, 11},
        {"bytes=5-", 5, n},
        {"bytes=-7", n - 7, n},
        {"bytes=3-999999999", 3, n},
        {"bytes=-999999999", 0, n},
        {"bytes=" + std::to_string(n - 1) + "-" + std::to_string(n - 1), n - 1, n},
    };
    for (const Case& c : cases) {
        const auto result = get(c.range);
        ASSERT_TRUE(result) << c.range;
        EXPECT_EQ(result->status, 206) << c.range;
        EXPECT_EQ(result->body, frame_.substr(c.begin, c.end - c.begin)) << c.range;
        EXPECT_EQ(result->get_header_value("Content-Range"), "bytes " + std::to_string(c.begin) +
                                                                 "-" + std::to_string(c.end - 1) +
                                                                 "/" + std::to_string(n))
            << c.range;
        EXPECT_EQ(result->get_header_value("ETag"), etag_) << c.range;
        expect_conforms("GET", "/v1/render", result);
    }
}

TEST_F(ByteRanges, ARangePastTheEndIs416GivingTheLength) {
    const std::size_t n = frame_.size();
    for (const std::string& range : {"bytes=" + std::to_string(n) + "-", std::string("bytes=-0")}) {
        const auto result = get(range);
        ASSERT_TRUE(result) << range;
        EXPECT_EQ(result->status, 416) << range;
        EXPECT_EQ(result->get_header_value("Content-Range"), "bytes */" + std::to_string(n));
        EXPECT_FALSE(result->has_header("ETag")) << "a 416 is not the frame";
        EXPECT_EQ(Json::parse(result->body).at("type"), "/v1/problems/range-not-satisfiable");
    }
}

// 400 ranges in a 1.6 KB header once made the HTTP library build a 400-part body (2.1 GB for
// a large frame): now they get the frame once.
TEST_F(ByteRanges, SeveralRangesGetTheWholeFrameNeverMore) {
    std::string many = "bytes=0-";
    for (int i = 1; i < 400; ++i) {
        many += ",0-";
    }
    for (const std::string& range : {many, std::string("bytes=0-1,2-3")}) {
        const auto result = get(range);
        ASSERT_TRUE(result);
        EXPECT_EQ(result->status, 200);
        EXPECT_EQ(result->body.size(), frame_.size());
        EXPECT_EQ(result->body, frame_);
        EXPECT_FALSE(result->has_header("Content-Range"));
    }
}

TEST_F(ByteRanges, IfRangeWithAnotherTagGetsTheWholeFrame) {
    const auto stale = get("bytes=0-10", "\"0000\"");
    ASSERT_TRUE(stale);
    EXPECT_EQ(stale->status, 200);
    EXPECT_EQ(stale->body, frame_);
    const auto current = get("bytes=0-10", etag_);
    ASSERT_TRUE(current);
    EXPECT_EQ(current->status, 206);
    EXPECT_EQ(current->body, frame_.substr(0, 11));
}

// Ranges belong to GET (RFC 9110 section 14.2): a POST's frame comes whole; every GET route is
// cut alike (the API's contract here).
TEST_F(ByteRanges, PostIgnoresRangesAndOtherGetRoutesAreCut) {
    const Json body = {{"environment", "default"},
                       {"objects", {{{"mesh", "default"}}}},
                       {"width", 64},
                       {"height", 48},
                       {"format", "png"},
                       {"samples", 1}};
    const auto posted = post_json(*client_, "/v1/render", body, {{"Range", "bytes=0-10"}});
    ASSERT_TRUE(posted);
    EXPECT_EQ(posted->status, 200);
    EXPECT_EQ(posted->body, frame_);

    const auto spec = client_->Get("/v1/openapi.yaml");
    ASSERT_TRUE(spec);
    ASSERT_EQ(spec->status, 200);
    const auto part = client_->Get("/v1/openapi.yaml", {{"Range", "bytes=100-199"}});
    ASSERT_TRUE(part);
    EXPECT_EQ(part->status, 206);
    EXPECT_EQ(part->body, spec->body.substr(100, 100));
}
