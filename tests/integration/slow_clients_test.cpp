// Slow clients from one address (slowloris: headers a line a second that never end; slow body: a
// declared body sent a byte a second), 200 and 1000 connections kept open, against a real
// server. Meanwhile another client, from a second loopback address, times /healthz, /readyz and
// an ordinary request on fresh connections, and /readyz on the admin listener: each must answer
// with p99 <= 100 ms. Without the per-client connection limit the attackers hold
// every HTTP thread and the probes wait for the header or request deadline (seconds).
#include <gtest/gtest.h>

#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <thread>

#include "http_support.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::itest;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kOtherClient = "127.0.0.2";
constexpr double kP99BoundSeconds = 0.100;

enum class Attack { Slowloris, SlowBody };
void PrintTo(Attack attack, std::ostream* out) {
    *out << (attack == Attack::Slowloris ? "Slowloris" : "SlowBody");
}

// What the attacker saw.
struct AttackOutcome {
    int opened = 0;       // connections opened, reconnections included
    int refused_429 = 0;  // answered 429 (over the per-client limit)
    // Most connections open and unanswered for over a second at one time: held by the server
    // (a refusal arrives within milliseconds).
    int most_held = 0;
    double held_seconds = 0;  // longest a connection was held before the server cut it
};

// Keeps `connections` connections from 127.0.0.1 busy with the attack until stop, reopening
// each one the server closes a second later (as slowhttptest keeps its count).
class Attacker {
  public:
    Attacker(int port, Attack attack, int connections)
        : port_(port), attack_(attack), slots_(std::size_t(connections)) {
        thread_ = std::thread([this] { run(); });
    }
    ~Attacker() { finish(); }

    AttackOutcome finish() {
        stop_ = true;
        if (thread_.joinable()) {
            thread_.join();
        }
        return outcome_;
    }
    int held() const { return held_.load(); }

  private:
    struct Slot {
        std::unique_ptr<RawSocket> socket;
        Clock::time_point opened{};
        Clock::time_point next_send{};
        Clock::time_point reopen_after{};
        std::string answer;
    };

    std::string opening() const {
        if (attack_ == Attack::Slowloris) {
            return "GET /v1/presets HTTP/1.1\r\nHost: 127.0.0.1\r\n";
        }
        return "POST /v1/environments HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
               "image/x-exr\r\nContent-Length: 1000000\r\n\r\n";
    }
    std::string trickle() const { return attack_ == Attack::Slowloris ? "X-a: b\r\n" : "x"; }

    void open(Slot& slot, Clock::time_point now) {
        slot.socket = std::make_unique<RawSocket>(port_);
        slot.answer.clear();
        slot.opened = now;
        slot.next_send = now + std::chrono::seconds(1);
        ++outcome_.opened;
        if (!slot.socket->ok() || !slot.socket->send_all(opening())) {
            close(slot, now);
        }
    }

    void close(Slot& slot, Clock::time_point now) {
        if (slot.answer.rfind("HTTP/1.1 429", 0) == 0) {
            ++outcome_.refused_429;
        } else {
            outcome_.held_seconds = std::max(
                outcome_.held_seconds, std::chrono::duration<double>(now - slot.opened).count());
        }
        slot.socket.reset();
        slot.reopen_after = now + std::chrono::seconds(1);
    }

    void run() {
        while (!stop_) {
            const auto now = Clock::now();
            int held = 0;
            for (Slot& slot : slots_) {
                if (!slot.socket) {
                    if (now >= slot.reopen_after) {
                        open(slot, now);
                    }
                    continue;
                }
                pollfd fd{slot.socket->fd(), POLLIN, 0};
                if (::poll(&fd, 1, 0) > 0) {
                    char buffer[2048];
                    const ssize_t n = ::recv(fd.fd, buffer, sizeof buffer, MSG_DONTWAIT);
                    if (n > 0) {
                        slot.answer.append(buffer, std::size_t(n));
                    }
                    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) ||
                        slot.answer.find("\r\n\r\n") != std::string::npos) {
                        close(slot, now);
                        continue;
                    }
                }
                if (now >= slot.next_send) {
                    slot.next_send = now + std::chrono::seconds(1);
                    if (!slot.socket->send_all(trickle())) {
                        close(slot, now);
                        continue;
                    }
                }
                held += now - slot.opened > std::chrono::seconds(1);
            }
            held_ = held;
            outcome_.most_held = std::max(outcome_.most_held, held);
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }

    const int port_;
    const Attack attack_;
    std::vector<Slot> slots_;
    AttackOutcome outcome_;
    std::atomic<int> held_{0};
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

// One probe: a fresh connection from the other client, a GET, the whole answer read.
// Seconds it took, or nullopt when it failed or did not answer 200 within 5 s.
std::optional<double> probe(int port, const std::string& path) {
    const auto start = Clock::now();
    RawSocket socket(port, kOtherClient);
    if (!socket.ok() || !socket.send_all("GET " + path +
                                         " HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                                         "Connection: close\r\n\r\n")) {
        return std::nullopt;
    }
    const auto answer = socket.receive_response(std::chrono::seconds(5));
    if (!answer || answer->rfind("HTTP/1.1 200", 0) != 0) {
        return std::nullopt;
    }
    return std::chrono::duration<double>(Clock::now() - start).count();
}

class SlowClients : public ::testing::TestWithParam<std::tuple<Attack, int>> {
  protected:
    void SetUp() override {
        // Each attacking connection is two descriptors here (the server runs in this process).
        rlimit files{};
        ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &files), 0);
        files.rlim_cur = files.rlim_max;
        ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &files), 0);
        ASSERT_GE(files.rlim_cur, rlim_t(2500)) << "the descriptor limit is too low for 1000 "
                                                   "connections and their server ends";
        server::ServiceConfig config = test_config(root_.data());
        config.admin_port = 0;
        config.access_log = false;
        server_ = std::make_unique<TestServer>(config);
    }

    TempRoot root_;
    std::unique_ptr<TestServer> server_;
};

}  // namespace

TEST_P(SlowClients, SlowAttackersFromOneAddressLeaveOtherClientsServed) {
    const auto [attack, connections] = GetParam();
    const int per_client = server_->config().max_connections_per_client;
    const double header_deadline = server_->config().header_timeout_seconds;
    const long resident_before = oer::testing::resident_kib();
    Attacker attacker(server_->port(), attack, connections);
    // Until the attackers hold what they may (the per-client limit), at most 4 s.
    ASSERT_TRUE(eventually([&] { return attacker.held() >= per_client; }, std::chrono::seconds(4)))
        << "the attack did not get going: " << attacker.held() << " connections held";

    std::map<std::string, std::vector<double>> seconds;
    int failures = 0;
    const struct {
        std::string name;
        int port;
        std::string path;
    } probes[] = {{"/healthz", server_->port(), "/healthz"},
                  {"/readyz", server_->port(), "/readyz"},
                  {"/v1/presets", server_->port(), "/v1/presets"},
                  {"admin /readyz", server_->admin_port(), "/readyz"}};
    const auto end = Clock::now() + std::chrono::seconds(8);  // longer than the header deadline
    while (Clock::now() < end) {
        for (const auto& target : probes) {
            if (const auto took = probe(target.port, target.path)) {
                seconds[target.name].push_back(*took);
            } else {
                ++failures;
                ADD_FAILURE() << target.name << " failed during the attack";
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // pacing
    }
    const long resident_growth_mib = (oer::testing::resident_kib() - resident_before) / 1024;
    const AttackOutcome outcome = attacker.finish();

    for (const auto& [name, taken] : seconds) {
        ASSERT_GE(taken.size(), 50u) << name;
        EXPECT_LE(percentile(taken, 0.99), kP99BoundSeconds)
            << name << " p99 over " << taken.size();
        std::printf("%s: %zu probes, p99 %.1f ms, max %.1f ms\n", name.c_str(), taken.size(),
                    1000 * percentile(taken, 0.99),
                    1000 * *std::max_element(taken.begin(), taken.end()));
    }
    EXPECT_EQ(failures, 0);
    // The attack was real: the server held as many connections as one client may, no more,
    // refused the rest with 429, and cut held slowloris ones at the header deadline.
    EXPECT_EQ(outcome.most_held, per_client);
    EXPECT_GE(outcome.refused_429, connections - per_client);
    if (attack == Attack::Slowloris) {
        EXPECT_LT(outcome.held_seconds, header_deadline + 1.5);
    }
    // From the admin listener: the attackers' connections are still open.
    httplib::Client admin("127.0.0.1", server_->admin_port());
    const Metrics metrics = scrape(admin);
    EXPECT_GE(metrics.sum("oer_http_connections_refused_total"), double(outcome.refused_429));
    EXPECT_LE(resident_growth_mib, 64);
    std::printf(
        "attack: %d connections opened, %d refused 429, at most %d held, held %.1f s at "
        "most; resident memory +%ld MiB\n",
        outcome.opened, outcome.refused_429, outcome.most_held, outcome.held_seconds,
        resident_growth_mib);
}

INSTANTIATE_TEST_SUITE_P(Attacks, SlowClients,
                         ::testing::Combine(::testing::Values(Attack::Slowloris, Attack::SlowBody),
                                            ::testing::Values(200, 1000)),
                         [](const auto& info) {
                             return std::string(std::get<0>(info.param) == Attack::Slowloris
                                                    ? "Slowloris"
                                                    : "SlowBody") +
                                    std::to_string(std::get<1>(info.param));
                         });
