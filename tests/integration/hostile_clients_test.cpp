// Clients that try to exhaust the server: a chunked body that never ends, a very slow sender,
// many idle keep-alive connections. None may stop /healthz from answering promptly, and the
// process's memory stays bounded. Also CORS: which origins are let in.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include <poll.h>
#include <sys/socket.h>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;
using Clock = std::chrono::steady_clock;

namespace {

// Bound on the growth of this process's resident memory over the hostile tests. ASan keeps
// freed memory in quarantine (256 MiB by default), so its bound is wider.
#if defined(__SANITIZE_ADDRESS__)
constexpr long kResidentGrowthBoundKib = 400 << 10;
#else
constexpr long kResidentGrowthBoundKib = 96 << 10;
#endif

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Seconds /healthz took on a fresh connection, or a large number if it failed.
double health_seconds(const TestServer& server) {
    auto client = server.client(5);
    const auto start = Clock::now();
    const auto result = client->Get("/healthz");
    return result && result->status == 200 ? seconds_since(start) : 1e9;
}

class HostileClients : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        root_ = new TempRoot();
        server::ServiceConfig config = test_config(root_->data());
        config.max_upload_bytes = 1 << 20;
        config.access_log = false;
        server_ = new TestServer(config);
        resident_before_ = resident_kib();  // after the server's start (its GL context)
    }
    static void TearDownTestSuite() {
        delete server_;
        delete root_;
    }

    static inline long resident_before_ = 0;
    static inline TempRoot* root_ = nullptr;
    static inline TestServer* server_ = nullptr;
};

}  // namespace

TEST_F(HostileClients, AChunkedUploadThatNeverEndsIsCutOff) {
    RawSocket socket(server_->port());
    ASSERT_TRUE(socket.ok());
    ASSERT_TRUE(
        socket.send_all("POST /v1/environments HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                        "Content-Type: image/x-exr\r\nTransfer-Encoding: chunked\r\n\r\n"));
    const std::string chunk = "10000\r\n" + std::string(0x10000, 'x') + "\r\n";
    std::atomic<bool> done{false};
    std::string answer;
    bool closed = false;
    std::size_t sent = 0;
    double cut_after = -1.0;
    std::thread flood([&] {
        const auto start = Clock::now();
        std::size_t offset = 0;
        while (seconds_since(start) < 20.0) {
            pollfd fd{socket.fd(), POLLIN | POLLOUT, 0};
            if (::poll(&fd, 1, 100) <= 0) {
                continue;
            }
            if (fd.revents & (POLLIN | POLLHUP | POLLERR)) {
                char buffer[4096];
                const ssize_t n = ::recv(socket.fd(), buffer, sizeof buffer, MSG_DONTWAIT);
                if (n > 0) {
                    answer.append(buffer, std::size_t(n));
                } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) {
                    closed = true;
                }
                if (closed || answer.find("\r\n\r\n") != std::string::npos) {
                    cut_after = seconds_since(start);
                    break;
                }
            }
            if (fd.revents & POLLOUT) {
                const ssize_t n = ::send(socket.fd(), chunk.data() + offset, chunk.size() - offset,
                                         MSG_NOSIGNAL | MSG_DONTWAIT);
                if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
                    closed = true;
                    cut_after = seconds_since(start);
                    break;
                }
                if (n > 0) {
                    sent += std::size_t(n);
                    offset = (offset + std::size_t(n)) % chunk.size();
                }
            }
        }
        done = true;
    });
    // /healthz keeps answering while the flood runs.
    int probes = 0;
    while (!done && probes < 10) {
        EXPECT_LT(health_seconds(*server_), 1.0) << "during the chunked flood";
        ++probes;
    }
    flood.join();
    ASSERT_GE(cut_after, 0.0) << "the never-ending upload was still accepted after 20 s ("
                              << sent / (1 << 20) << " MiB sent)";
    EXPECT_LT(cut_after, 5.0);
    if (!answer.empty()) {
        EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0u) << answer.substr(0, 200);
    }
    // Sent: at most the limit plus what socket buffers hold.
    EXPECT_LT(sent, std::size_t(32) << 20);
    EXPECT_LT(health_seconds(*server_), 1.0) << "after the chunked flood";
}

TEST_F(HostileClients, VerySlowSendersDoNotBlockHealth) {
    std::atomic<bool> stop{false};
    std::vector<std::thread> senders;
    for (int i = 0; i < 2; ++i) {
        senders.emplace_back([&] {
            RawSocket socket(server_->port());
            const std::string request =
                "GET /v1/presets HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Padding: " +
                std::string(200, 'p') + "\r\n\r\n";
            for (std::size_t i = 0; i < request.size() && !stop; ++i) {
                if (!socket.send_all(request.substr(i, 1))) {
                    break;
                }
                std::this_thread::sleep_for(std::chrono::milliseconds(200));
            }
        });
    }
    const auto start = Clock::now();
    while (seconds_since(start) < 3.0) {
        EXPECT_LT(health_seconds(*server_), 1.0) << "with slow senders at " << seconds_since(start);
        std::this_thread::sleep_for(std::chrono::milliseconds(250));  // pacing, not synchronisation
    }
    stop = true;
    for (std::thread& sender : senders) {
        sender.join();
    }
}

TEST_F(HostileClients, IdleKeepAliveConnectionsDoNotBlockHealth) {
    std::vector<std::unique_ptr<RawSocket>> idle;
    for (int i = 0; i < 32; ++i) {
        idle.push_back(std::make_unique<RawSocket>(server_->port()));
        ASSERT_TRUE(idle.back()->ok());
        ASSERT_TRUE(idle.back()->send_all("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    }
    int answered = 0;
    for (auto& socket : idle) {
        const auto response = socket->receive_response(std::chrono::milliseconds(100));
        answered += response && response->rfind("HTTP/1.1 200", 0) == 0;
    }
    // The 32 connections stay open and idle; new clients are still served within a second.
    for (int i = 0; i < 3; ++i) {
        EXPECT_LT(health_seconds(*server_), 1.0)
            << "with 32 idle keep-alive connections (" << answered << " answered at once)";
    }
}

TEST_F(HostileClients, ResidentMemoryStaysBounded) {
    const long growth = resident_kib() - resident_before_;
    RecordProperty("resident_growth_kib", std::to_string(growth));
    EXPECT_LT(growth, kResidentGrowthBoundKib)
        << "resident memory grew by " << growth / 1024 << " MiB over the hostile clients";
}

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
