// CORS: which origins are let in (OER_CORS_ORIGINS), and no CORS headers when none are set.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

TEST(Cors, AllowedOriginsAreEchoedOthersNot) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.cors_origins = {"https://shop.example"};
    TestServer server(config);
    auto client = server.client();
    const auto allowed = client->Get("/v1/presets", {{"Origin", "https://shop.example"}});
    ASSERT_TRUE(allowed);
    EXPECT_EQ(allowed->status, 200);
    EXPECT_EQ(allowed->get_header_value("Access-Control-Allow-Origin"), "https://shop.example");
    const auto other = client->Get("/v1/presets", {{"Origin", "https://evil.example"}});
    ASSERT_TRUE(other);
    EXPECT_FALSE(other->has_header("Access-Control-Allow-Origin"))
        << other->get_header_value("Access-Control-Allow-Origin");

    const auto preflight = client->Options(
        "/v1/render", {{"Origin", "https://shop.example"},
                       {"Access-Control-Request-Method", "POST"},
                       {"Access-Control-Request-Headers", "content-type, authorization"}});
    ASSERT_TRUE(preflight);
    EXPECT_TRUE(preflight->status == 200 || preflight->status == 204) << preflight->status;
    EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Origin"), "https://shop.example");
    std::string methods = preflight->get_header_value("Access-Control-Allow-Methods");
    std::string headers = preflight->get_header_value("Access-Control-Allow-Headers");
    for (std::string* text : {&methods, &headers}) {
        std::transform(text->begin(), text->end(), text->begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
    }
    EXPECT_NE(methods.find("post"), std::string::npos) << methods;
    EXPECT_NE(headers.find("content-type"), std::string::npos) << headers;
    EXPECT_NE(headers.find("authorization"), std::string::npos) << headers;

    const auto refused = client->Options("/v1/render", {{"Origin", "https://evil.example"},
                                                        {"Access-Control-Request-Method", "POST"}});
    ASSERT_TRUE(refused);
    EXPECT_FALSE(refused->has_header("Access-Control-Allow-Origin"));
}

TEST(Cors, NoOriginsConfiguredMeansNoCorsHeaders) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const auto result = client->Get("/v1/presets", {{"Origin", "https://shop.example"}});
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200);
    EXPECT_FALSE(result->has_header("Access-Control-Allow-Origin"));
}

// The element's module is public code: any origin may load it, so that on a page the server
// does not allow the element still runs and says why its frames are refused (web/README.md).
TEST(Cors, WebFilesAreReadableFromAnyOrigin) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.cors_origins = {"https://shop.example"};
    TestServer server(config);
    auto client = server.client();
    const auto module = client->Get("/web/oer-viewer.js", {{"Origin", "https://other.example"}});
    ASSERT_TRUE(module);
    EXPECT_EQ(module->status, 200);
    EXPECT_EQ(module->get_header_value("Access-Control-Allow-Origin"), "*");
    const auto allowed = client->Get("/web/oer-viewer.js", {{"Origin", "https://shop.example"}});
    ASSERT_TRUE(allowed);
    EXPECT_EQ(allowed->get_header_value("Access-Control-Allow-Origin"), "https://shop.example");
    EXPECT_EQ(allowed->get_header_value_count("Access-Control-Allow-Origin"), 1U);
    const auto frame = client->Get("/v1/presets", {{"Origin", "https://other.example"}});
    ASSERT_TRUE(frame);
    EXPECT_FALSE(frame->has_header("Access-Control-Allow-Origin"));
}
