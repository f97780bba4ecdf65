// The policies a route declares when it is registered (the API key, the body's limit) and the
// router's CORS, applied before any handler runs, over a real socket.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <httplib.h>

#include "request_state.hpp"
#include "router.hpp"

using namespace oer::server;

namespace {

// A router on a loopback port, its routes added by the test before start().
class RouterServer {
  public:
    explicit RouterServer(RouterPolicies policies)
        : router(
              server, [](std::string_view) {}, std::move(policies)) {
        server.set_pre_routing_handler(
            [this](const httplib::Request& request, httplib::Response& response) {
                current_request() = RequestState{};
                return router.before_routing(request, response);
            });
    }
    ~RouterServer() {
        server.stop();
        if (thread.joinable()) {
            thread.join();
        }
    }
    std::unique_ptr<httplib::Client> start() {
        const int port = server.bind_to_any_port("127.0.0.1");
        thread = std::thread([this] { server.listen_after_bind(); });
        while (!server.is_running()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return std::make_unique<httplib::Client>("127.0.0.1", port);
    }

    httplib::Server server;
    Router router;
    std::thread thread;
};

void answer_ok(const httplib::Request&, httplib::Response& response) {
    response.set_content("ok", "text/plain");
}

}  // namespace

TEST(Router, ARouteThatNeedsTheKeyRefusesBeforeItsHandlerRuns) {
    RouterServer routes(RouterPolicies{"s3cret", {}});
    int handled = 0;
    routes.router.del(
        "/things/{id}",
        [&handled](const httplib::Request& request, httplib::Response& response) {
            ++handled;
            answer_ok(request, response);
        },
        RoutePolicy{.needs_api_key = true});
    routes.router.get("/things/{id}", answer_ok);
    auto client = routes.start();

    const auto refused = client->Delete("/things/a");
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 401);
    EXPECT_EQ(refused->get_header_value("WWW-Authenticate"), "Bearer");
    EXPECT_EQ(handled, 0);
    const auto open = client->Get("/things/a");
    ASSERT_TRUE(open);
    EXPECT_EQ(open->status, 200) << "a route without the policy needs no key";
    const auto allowed = client->Delete("/things/a", {{"Authorization", "Bearer s3cret"}});
    ASSERT_TRUE(allowed);
    EXPECT_EQ(allowed->status, 200);
    EXPECT_EQ(handled, 1);
}

TEST(Router, WithoutAKeyConfiguredTheKeyPolicyLetsEveryRequestThrough) {
    RouterServer routes(RouterPolicies{});
    routes.router.del("/things/{id}", answer_ok, RoutePolicy{.needs_api_key = true});
    auto client = routes.start();
    const auto result = client->Delete("/things/a");
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200);
}

TEST(Router, APostChecksTheKeyThenBeforeBodyThenTheBodysLimit) {
    RouterServer routes(RouterPolicies{"s3cret", {}});
    std::vector<std::string> steps;
    routes.router.post(
        "/uploads", RoutePolicy{.needs_api_key = true, .max_body = 4},
        [&steps](const httplib::Request&, httplib::Response&) { steps.push_back("before_body"); },
        [&steps](const httplib::Request&, httplib::Response& response, const std::string& body) {
            steps.push_back("body " + body);
            response.set_content("ok", "text/plain");
        });
    auto client = routes.start();
    const httplib::Headers key{{"Authorization", "Bearer s3cret"}};

    const auto refused = client->Post("/uploads", "abc", "text/plain");
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 401);
    EXPECT_TRUE(steps.empty());
    const auto too_large = client->Post("/uploads", key, "abcdef", "text/plain");
    ASSERT_TRUE(too_large);
    EXPECT_EQ(too_large->status, 413);
    EXPECT_EQ(steps, std::vector<std::string>{"before_body"});
    steps.clear();
    const auto read = client->Post("/uploads", key, "abcd", "text/plain");
    ASSERT_TRUE(read);
    EXPECT_EQ(read->status, 200);
    EXPECT_EQ(steps, (std::vector<std::string>{"before_body", "body abcd"}));
}

TEST(Router, CorsCoversRoutesAndPreflights) {
    RouterServer routes(RouterPolicies{"", {"https://shop.example"}});
    routes.router.get("/things", answer_ok);
    auto client = routes.start();
    const httplib::Headers origin{{"Origin", "https://shop.example"}};

    const auto answer = client->Get("/things", origin);
    ASSERT_TRUE(answer);
    EXPECT_EQ(answer->get_header_value("Access-Control-Allow-Origin"), "https://shop.example");
    const auto preflight = client->Options("/things", origin);
    ASSERT_TRUE(preflight);
    EXPECT_EQ(preflight->status, 204);
    EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Origin"), "https://shop.example");
    EXPECT_EQ(preflight->get_header_value("Allow"), "OPTIONS, GET");
}
