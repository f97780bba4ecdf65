// A batch job across three oer-server processes sharing one data folder and one queue (a real
// Debian redis-server on a loopback port in the test's temporary folder, --queue
// redis://...): one replica is killed (kill -9) mid-job, after it has stored frames of its own;
// the job completes through the others, which claim its pending frame once it has been idle
// RedisFrameQueue::kClaimAfter; every frame is stored exactly once over all three (each
// replica logs each frame it stores), so none is rendered more than once more (the killed
// replica's frame in flight, never stored); the survivors both took part.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/socket.h>

#include <filesystem>
#include <map>
#include <regex>
#include <thread>

#include "http_support.hpp"
#include "server_process.hpp"

using namespace oer;
using namespace oer::itest;
using namespace oer::ptest;
namespace fs = std::filesystem;

namespace {

constexpr const char* kRedisServer = "/usr/bin/redis-server";

// A redis-server of its own: no persistence (the test's queue lives as long as the test).
class RedisProcess {
  public:
    explicit RedisProcess(const fs::path& folder) : port_(free_loopback_port()) {
        pid_ = spawn_process({kRedisServer, "--port", std::to_string(port_), "--bind", "127.0.0.1",
                              "--save", "", "--appendonly", "no", "--dir", folder.string()},
                             {}, folder / "redis.out", folder / "redis.err");
        EXPECT_TRUE(eventually(
            [&] {
                const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
                sockaddr_in address{};
                address.sin_family = AF_INET;
                address.sin_port = htons(std::uint16_t(port_));
                address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
                const bool up =
                    ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
                ::close(fd);
                return up;
            },
            std::chrono::seconds(10)))
            << read_text(folder / "redis.out");
    }
    ~RedisProcess() {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            reap_process(pid_, std::chrono::seconds(10));
        }
    }
    RedisProcess(const RedisProcess&) = delete;
    RedisProcess& operator=(const RedisProcess&) = delete;
    std::string url() const { return "redis://127.0.0.1:" + std::to_string(port_); }

  private:
    int port_;
    pid_t pid_ = -1;
};

// The frames a replica's log says it stored, by name, for the job.
std::map<std::string, int> stored_by(const ServerProcess& server, const std::string& job) {
    std::map<std::string, int> frames;
    const std::regex line("jobs: frame (\\S+) of job " + job + " stored");
    const std::string log = server.log();
    for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator();
         ++it) {
        ++frames[(*it)[1]];
    }
    return frames;
}

}  // namespace

TEST(JobReplicas, AJobCompletesAcrossThreeReplicasWhenOneIsKilledMidJob) {
    if (!fs::exists(kRedisServer)) {
        GTEST_SKIP() << "no " << kRedisServer
                     << " (Debian's redis-server: scripts/setup-debian.sh --with-test-data)";
    }
    TempRoot root;
    RedisProcess redis(root.root());
    ASSERT_FALSE(HasFatalFailure());
    std::vector<std::unique_ptr<ServerProcess>> replicas;
    for (int i = 0; i < 3; ++i) {
        ServerLaunch launch(root.data(), root.root());
        launch.options["queue"] = redis.url();
        replicas.push_back(std::make_unique<ServerProcess>(launch));
        ASSERT_FALSE(HasFatalFailure());
    }
    auto client = replicas[0]->client();
    const Json render = {{"environment", "default"},
                         {"objects", Json::array({{{"mesh", "default"}}})},
                         {"width", 128},
                         {"height", 96},
                         {"samples", 4},
                         {"format", "jpeg"}};
    constexpr int kViews = 90;
    const auto submitted =
        post_json(*client, "/v1/jobs", {{"turntable", {{"render", render}, {"views", kViews}}}});
    const Json created = expect_conforms("POST", "/v1/jobs", submitted);
    ASSERT_TRUE(created.is_object());
    const std::string id = created.at("id");

    // Killed once it has stored frames of its own, with others still to come.
    const auto done = [&] {
        return expect_conforms("GET", "/v1/jobs/{id}", client->Get(("/v1/jobs/" + id).c_str()))
            .at("done")
            .get<int>();
    };
    ASSERT_TRUE(
        eventually([&] { return !stored_by(*replicas[1], id).empty(); }, std::chrono::minutes(1)));
    const std::map<std::string, int> by_killed = stored_by(*replicas[1], id);
    replicas[1]->kill();
    const int done_at_kill = done();
    EXPECT_LT(done_at_kill, kViews) << "the job ended before a replica was killed";

    Json status;
    ASSERT_TRUE(eventually(
        [&] {
            status = expect_conforms("GET", "/v1/jobs/{id}",
                                     replicas[2]->client()->Get(("/v1/jobs/" + id).c_str()));
            return status.value("state", "") == "done";
        },
        std::chrono::minutes(2)))
        << status.dump();
    EXPECT_EQ(status.at("done"), kViews);

    std::map<std::string, int> stored = by_killed;
    std::map<std::string, int> by_survivor[2] = {stored_by(*replicas[0], id),
                                                 stored_by(*replicas[2], id)};
    for (const auto& survivor : by_survivor) {
        EXPECT_FALSE(survivor.empty()) << "a surviving replica rendered none of the job";
        for (const auto& [name, count] : survivor) {
            stored[name] += count;
        }
    }
    EXPECT_EQ(stored.size(), std::size_t(kViews));
    for (const auto& [name, count] : stored) {
        EXPECT_EQ(count, 1) << name << " was stored " << count << " times";
    }
    std::printf("[ jobs ] %d frames over 3 replicas: %zu, %zu and %zu (killed at %d done)\n",
                kViews, by_survivor[0].size(), by_killed.size(), by_survivor[1].size(),
                done_at_kill);
}
