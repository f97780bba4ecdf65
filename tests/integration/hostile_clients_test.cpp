// Clients that try to exhaust the server: a chunked body that never ends, a very slow sender,
// many idle keep-alive connections. None may stop /healthz from answering promptly, and the
// process's memory stays bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <thread>

#include <poll.h>
#include <sys/socket.h>

#include "http_support.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::itest;
using Clock = std::chrono::steady_clock;

namespace {

// Bound on the growth of the live heap over 64 attacks, each of which sends the server more than
// its 1 MiB upload limit: keeping a sixteenth of each one's limit would exceed it.
constexpr std::size_t kLiveHeapGrowthBound = std::size_t(4) << 20;

// Seconds /healthz took on a fresh connection, or a large number if it failed.
double health_seconds(const TestServer& server) {
    auto client = server.client(5);
    const auto start = Clock::now();
    const auto result = client->Get("/healthz");
    return result && result->status == 200 ? seconds_since(start) : 1e9;
}

// What the server did to a chunked upload that never ends.
struct FloodOutcome {
    double cut_after = -1.0;     // seconds until the server answered or closed; -1: never (20 s)
    std::size_t sent = 0;        // bytes the server took before that
    std::string answer;          // what it answered, if anything
    int slow_health_probes = 0;  // /healthz probes during the flood that took 1 s or more
};

// Sends chunks of 64 KiB for up to 20 s, probing /healthz meanwhile.
FloodOutcome flood_with_endless_chunked_upload(const TestServer& server) {
    RawSocket socket(server.port());
    FloodOutcome outcome;
    if (!socket.ok() ||
        !socket.send_all("POST /v1/environments HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                         "Content-Type: image/x-exr\r\nTransfer-Encoding: chunked\r\n\r\n")) {
        return outcome;
    }
    const std::string chunk = "10000\r\n" + std::string(0x10000, 'x') + "\r\n";
    std::atomic<bool> done{false};
    std::thread flood([&] {
        const auto start = Clock::now();
        std::size_t offset = 0;
        bool closed = false;
        while (seconds_since(start) < 20.0) {
            pollfd fd{socket.fd(), POLLIN | POLLOUT, 0};
            if (::poll(&fd, 1, 100) <= 0) {
                continue;
            }
            if (fd.revents & (POLLIN | POLLHUP | POLLERR)) {
                char buffer[4096];
                const ssize_t n = ::recv(socket.fd(), buffer, sizeof buffer, MSG_DONTWAIT);
                if (n > 0) {
                    outcome.answer.append(buffer, std::size_t(n));
                } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) {
                    closed = true;
                }
                if (closed || outcome.answer.find("\r\n\r\n") != std::string::npos) {
                    outcome.cut_after = seconds_since(start);
                    break;
                }
            }
            if (fd.revents & POLLOUT) {
                const ssize_t n = ::send(socket.fd(), chunk.data() + offset, chunk.size() - offset,
                                         MSG_NOSIGNAL | MSG_DONTWAIT);
                if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
                    outcome.cut_after = seconds_since(start);
                    break;
                }
                if (n > 0) {
                    outcome.sent += std::size_t(n);
                    offset = (offset + std::size_t(n)) % chunk.size();
                }
            }
        }
        done = true;
    });
    for (int probes = 0; !done && probes < 10; ++probes) {
        outcome.slow_health_probes += health_seconds(server) >= 1.0;
    }
    flood.join();
    return outcome;
}

// Opens 32 keep-alive connections that each make one request and then stay idle; returns how
// many of the 3 /healthz probes made meanwhile on fresh connections took 1 s or more.
int slow_health_probes_with_idle_connections(const TestServer& server) {
    std::vector<std::unique_ptr<RawSocket>> idle;
    for (int i = 0; i < 32; ++i) {
        idle.push_back(std::make_unique<RawSocket>(server.port()));
        if (!idle.back()->ok() ||
            !idle.back()->send_all("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")) {
            ADD_FAILURE() << "idle connection " << i << " could not be opened";
            return 3;
        }
    }
    for (auto& socket : idle) {
        socket->receive_response(std::chrono::milliseconds(100));
    }
    int slow = 0;
    for (int i = 0; i < 3; ++i) {
        slow += health_seconds(server) >= 1.0;
    }
    return slow;
}

class HostileClients : public ::testing::Test {
  protected:
    void SetUp() override {
        server::ServiceConfig config = test_config(root_.data());
        config.max_upload_bytes = 1 << 20;
        config.access_log = false;
        server_ = std::make_unique<TestServer>(config);
    }

    TempRoot root_;
    std::unique_ptr<TestServer> server_;
};

}  // namespace

TEST_F(HostileClients, AChunkedUploadThatNeverEndsIsCutOff) {
    const FloodOutcome outcome = flood_with_endless_chunked_upload(*server_);
    EXPECT_EQ(outcome.slow_health_probes, 0) << "/healthz was slow during the chunked flood";
    ASSERT_GE(outcome.cut_after, 0.0) << "the never-ending upload was still accepted after 20 s ("
                                      << outcome.sent / (1 << 20) << " MiB sent)";
    EXPECT_LT(outcome.cut_after, 5.0);
    if (!outcome.answer.empty()) {
        EXPECT_EQ(outcome.answer.rfind("HTTP/1.1 413", 0), 0u) << outcome.answer.substr(0, 200);
    }
    // Sent: at most the limit plus what socket buffers hold.
    EXPECT_LT(outcome.sent, std::size_t(32) << 20);
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
    // The 32 connections stay open and idle; new clients are still served within a second.
    EXPECT_EQ(slow_health_probes_with_idle_connections(*server_), 0);
}

// The hostile clients again and again: after a first round (caches, thread-local state), further
// rounds must not grow the heap: nothing they send is kept.
TEST_F(HostileClients, LiveHeapStaysBoundedOverRepeatedAttacks) {
    flood_with_endless_chunked_upload(*server_);
    slow_health_probes_with_idle_connections(*server_);
    const std::size_t before = oer::testing::live_heap_bytes();
    std::size_t sent = 0;
    for (int round = 0; round < 64; ++round) {
        const FloodOutcome outcome = flood_with_endless_chunked_upload(*server_);
        ASSERT_GE(outcome.cut_after, 0.0) << "round " << round;
        sent += outcome.sent;
        slow_health_probes_with_idle_connections(*server_);
    }
    const std::size_t after = oer::testing::live_heap_bytes();
    const long growth_kib = (long(after) - long(before)) / 1024;
    RecordProperty("live_heap_growth_kib", std::to_string(growth_kib));
    std::printf("64 more rounds sent %zu MiB; the live heap went from %zu to %zu KiB\n", sent >> 20,
                before >> 10, after >> 10);
    EXPECT_LT(after, before + kLiveHeapGrowthBound)
        << "the live heap grew by " << growth_kib << " KiB over 64 rounds";
}

// A request line or a header line longer than the server reads is answered, never just
// dropped: 414 (cpp-httplib's own limit of 8 KiB for the request line, or the connection's
// 16 KiB for any line) and 431, as problem+json, with the connection closed after it.
TEST_F(HostileClients, OverlongLinesAreAnswered414Or431) {
    struct Case {
        std::string request;
        std::string status_line;
        std::string type;
    };
    const std::string get = "GET /v1/render?environment=default&mesh=default&pad=";
    const Case cases[] = {
        {get + std::string(10 << 10, 'a') + " HTTP/1.1\r\nHost: x\r\n\r\n", "HTTP/1.1 414",
         "uri-too-long"},
        {get + std::string(70 << 10, 'a') + " HTTP/1.1\r\nHost: x\r\n\r\n", "HTTP/1.1 414",
         "uri-too-long"},
        {"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Pad: " + std::string(20 << 10, 'a') + "\r\n\r\n",
         "HTTP/1.1 431", "header-fields-too-large"},
        {"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Pad: " + std::string(70 << 10, 'a') + "\r\n\r\n",
         "HTTP/1.1 431", "header-fields-too-large"},
    };
    for (const Case& c : cases) {
        RawSocket socket(server_->port());
        ASSERT_TRUE(socket.ok());
        socket.send_all(c.request);  // the server may stop reading (and close) part way
        const std::optional<std::string> answer =
            socket.receive_response(std::chrono::milliseconds(2000));
        ASSERT_TRUE(answer) << c.request.size() << " bytes: no answer";
        EXPECT_EQ(answer->substr(0, c.status_line.size()), c.status_line) << *answer;
        EXPECT_NE(answer->find("/v1/problems/" + c.type), std::string::npos) << *answer;
        EXPECT_NE(answer->find("Connection: close"), std::string::npos) << *answer;
    }
    EXPECT_LT(health_seconds(*server_), 1.0);
}
