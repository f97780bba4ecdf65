// Replicas: three real oer-server processes sharing one data folder behind Debian's nginx, which
// runs the deployment's own docker/nginx/nginx.conf (its "# DEPLOYMENT:" lines made this test's:
// loopback ports, folders under the test's temporary folder, the workers' user). What an upload
// through nginx stores, every replica serves alike, byte for byte; concurrent uploads of the
// same bytes through two replicas leave one entry; a replica killed in the middle of an upload
// (its body half sent, its map being preprocessed) leaves nothing damaged that another replica
// would serve, and restarting it does not disturb another replica's write in progress (the
// store's start-up spares young temporary files: asset_store.hpp); nginx caches frames and
// answers If-None-Match itself. The figures (uploads through nginx, each replica's first frame,
// frames/s of a small crowd through nginx to one replica and to all) are printed for
// docker/README.md.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>
#include <fstream>
#include <latch>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "http_support.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/mesh/material_spheres.hpp"
#include "server_process.hpp"

using namespace oer;
using namespace oer::itest;
using namespace oer::ptest;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

constexpr int kReplicas = 3;
constexpr const char* kNginx = "/usr/sbin/nginx";

long long milliseconds_since(Clock::time_point start) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start).count();
}

// docker/nginx/nginx.conf with each line marked "# DEPLOYMENT: <what>" made this test's. The
// file and this test must agree on what a deployment changes: a marker this test does not know,
// or one of its markers missing from the file, fails the test.
std::string deployment_config(const fs::path& folder, int port, const std::vector<int>& replicas) {
    const std::string config_path = std::string(OER_DOCKER_DIR) + "/nginx/nginx.conf";
    const std::string original = read_text(config_path);
    EXPECT_FALSE(original.empty()) << config_path;
    const auto replaced = [](std::string line, const std::string& from, const fs::path& to) {
        const std::size_t at = line.find(from);
        if (at == std::string::npos) {
            ADD_FAILURE() << "expected " << from << " in: " << line;
            return line;
        }
        return line.replace(at, from.size(), to.string());
    };
    const std::string marker = "# DEPLOYMENT: ";
    std::istringstream lines(original);
    std::string config;
    std::set<std::string> seen;
    for (std::string line; std::getline(lines, line);) {
        const std::size_t at = line.find(marker);
        const bool comment = line.find_first_not_of(' ') == line.find('#');
        if (at == std::string::npos || comment) {
            config += line + "\n";
            continue;
        }
        std::string what;
        std::istringstream(line.substr(at + marker.size())) >> what;
        seen.insert(what);
        if (what == "user") {
            // As root, workers of another user could not enter the test's folder; as anyone
            // else, nginx cannot switch users.
            config += ::geteuid() == 0 ? "user root;\n" : "\n";
        } else if (what == "spool" || what == "cache") {
            config += replaced(line, "/var/lib/nginx", folder) + "\n";
        } else if (what == "upstream") {
            for (const int replica : replicas) {
                config += "server 127.0.0.1:" + std::to_string(replica) + ";\n";
            }
        } else if (what == "listen") {
            config += "listen 127.0.0.1:" + std::to_string(port) + ";\n";
        } else {
            ADD_FAILURE() << "a DEPLOYMENT line this test does not know: " << line;
        }
    }
    EXPECT_EQ(seen, (std::set<std::string>{"cache", "listen", "spool", "upstream", "user"}));
    return config;
}

// Debian's nginx in the foreground on deployment_config, with its prefix, pid file, spool, cache
// and logs (its error log is its stderr, its access log its stdout) in folder; ready once it
// answers /healthz through a replica; stopped with SIGTERM.
class Nginx {
  public:
    Nginx(const fs::path& folder, const std::vector<int>& replicas) : folder_(folder) {
        if (!fs::exists(kNginx)) {
            ADD_FAILURE() << kNginx
                          << " is missing: install Debian's nginx (scripts/setup-debian.sh "
                             "--with-test-data)";
            return;
        }
        fs::create_directories(folder_);
        // Another process may take the free port before nginx binds it: then again.
        for (int attempt = 0; attempt < 3; ++attempt) {
            port_ = free_loopback_port();
            const fs::path config = folder_ / "nginx.conf";
            std::ofstream(config) << deployment_config(folder_, port_, replicas);
            pid_ = spawn_process(
                {kNginx, "-p", folder_.string() + "/", "-c", config.string(), "-e", "stderr", "-g",
                 "daemon off; pid " + (folder_ / "nginx.pid").string() + ";"},
                {}, folder_ / "nginx.out", folder_ / "nginx.err");
            if (pid_ < 0) {
                return;
            }
            int status = -1;
            const bool ready = eventually(
                [&] {
                    status = reap_process(pid_, 0ms);
                    if (status >= 0) {
                        return true;
                    }
                    const auto health = client(5)->Get("/healthz");
                    return health && health->status == 200;
                },
                20s);
            if (ready && status < 0) {
                return;
            }
            if (status < 0) {
                ADD_FAILURE() << "nginx did not proxy /healthz within 20 s:\n" << error_log();
                stop();
                return;
            }
            pid_ = -1;
            if (error_log().find("Address already in use") == std::string::npos) {
                ADD_FAILURE() << "nginx ended with status " << status << ":\n" << error_log();
                return;
            }
        }
        ADD_FAILURE() << "nginx found no free port:\n" << error_log();
    }

    ~Nginx() {
        stop();
        if (::testing::Test::HasFailure() && fs::exists(folder_ / "nginx.err")) {
            std::cerr << "nginx (" << folder_.string() << "):\n"
                      << error_log() << read_text(folder_ / "nginx.out") << "\n";
        }
    }
    Nginx(const Nginx&) = delete;
    Nginx& operator=(const Nginx&) = delete;

    int port() const { return port_; }

    std::unique_ptr<httplib::Client> client(int read_timeout_seconds = 120) const {
        auto result = std::make_unique<httplib::Client>("127.0.0.1", port_);
        result->set_connection_timeout(5, 0);
        result->set_read_timeout(read_timeout_seconds, 0);
        result->set_write_timeout(30, 0);
        return result;
    }

    std::string error_log() const { return read_text(folder_ / "nginx.err"); }

  private:
    void stop() {
        if (pid_ < 0) {
            return;
        }
        // SIGTERM: the master stops its workers, then itself.
        ::kill(pid_, SIGTERM);
        const int status = reap_process(pid_, 10s);
        if (status < 0) {
            ADD_FAILURE() << "nginx did not stop within 10 s of SIGTERM";
            ::kill(pid_, SIGKILL);
            reap_process(pid_, 10s);
        }
        pid_ = -1;
    }

    fs::path folder_;
    pid_t pid_ = -1;
    int port_ = -1;
};

// A frame of one object with occlusion: its first frame on a replica needs the rig, the mesh,
// the scene's transfer and (for a glossy mesh) the rig's specular cube, each read from the
// shared store or computed.
Json frame_request(const std::string& environment, const std::string& mesh) {
    return {{"environment", environment},
            {"objects", {{{"mesh", mesh}}}},
            {"camera", {{"orbit", {{"yaw", 35}, {"pitch", 20}, {"distance", 3}}}}},
            {"width", 192},
            {"height", 144},
            {"occlusion", true},
            {"format", "png"}};
}

// The files under folder (paths relative to it, sorted) whose name starts with prefix.
std::vector<std::string> files_named(const fs::path& folder, const std::string& prefix) {
    std::vector<std::string> found;
    for (const auto& entry : fs::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file() && entry.path().filename().string().starts_with(prefix)) {
            found.push_back(fs::relative(entry.path(), folder).string());
        }
    }
    std::sort(found.begin(), found.end());
    return found;
}

Json without(Json document, const std::vector<std::string>& members) {
    for (const std::string& member : members) {
        document.erase(member);
    }
    return document;
}

class Replicas : public ::testing::Test {
  protected:
    void SetUp() override {
        // Started together, as a deployment's replicas are: their stores open the folder at
        // once, and each stores the default scene's transfer at start-up.
        replicas_.resize(kReplicas);
        std::vector<std::thread> starting;
        for (int i = 0; i < kReplicas; ++i) {
            starting.emplace_back([this, i] { start(i); });
        }
        for (std::thread& thread : starting) {
            thread.join();
        }
        ASSERT_FALSE(HasFatalFailure());
        nginx_ = std::make_unique<Nginx>(root_.root() / "nginx", ports());
        ASSERT_FALSE(HasFailure());
    }

    // Replica i, (re)started on the shared folder. Behind nginx every connection has nginx's
    // address: oer's cap per address is off, as docker/nginx/nginx.conf says.
    void start(int i) {
        ServerLaunch launch(root_.data(), root_.root());
        launch.options["max-connections-per-client"] = "0";
        launch.options["client-render-rate"] = "0";
        replicas_[i].reset();
        replicas_[i] = std::make_unique<ServerProcess>(launch);
    }

    std::vector<int> ports() const {
        std::vector<int> result;
        for (const auto& replica : replicas_) {
            result.push_back(replica->port());
        }
        return result;
    }

    // A metric summed over the replicas that run.
    double total(const std::string& name, const std::map<std::string, std::string>& labels = {}) {
        double sum = 0.0;
        for (const auto& replica : replicas_) {
            if (replica->running()) {
                sum += admin_metric(*replica, name, labels);
            }
        }
        return sum;
    }

    TempRoot root_;
    std::vector<std::unique_ptr<ServerProcess>> replicas_;
    std::unique_ptr<Nginx> nginx_;
};

}  // namespace

TEST_F(Replicas, EveryReplicaServesWhatWasUploadedThroughNginxByteForByte) {
    const std::string map = hdr_bytes(three_disc_environment(1024, 512).image);
    const std::string spheres(as_text(material_spheres_glb({.rings = 12})));
    auto via_nginx = nginx_->client();
    auto start = Clock::now();
    Json rig = upload_environment(*via_nginx, map, "image/vnd.radiance", "light_count=3");
    const long long map_ms = milliseconds_since(start);
    start = Clock::now();
    Json mesh = upload_mesh(*via_nginx, spheres, "model/gltf-binary");
    const long long mesh_ms = milliseconds_since(start);
    ASSERT_TRUE(rig.is_object() && mesh.is_object());
    std::cerr << "through nginx: a 1024x512 Radiance map (" << map.size()
              << " bytes) uploaded and preprocessed in " << map_ms << " ms, a glTF mesh ("
              << spheres.size() << " bytes) in " << mesh_ms << " ms\n";
    // A 15 MB upload (a mesh with a noise texture), other bytes each way so that neither is
    // stored already: nginx takes the whole body (spooled to disk) before a replica sees it.
    const std::string direct_mesh = noise_box_glb(11, kTextureSide);
    const std::string proxied_mesh = noise_box_glb(12, kTextureSide);
    start = Clock::now();
    ASSERT_TRUE(upload_mesh(*replicas_[0]->client(), direct_mesh, "model/gltf-binary").is_object());
    const long long direct_ms = milliseconds_since(start);
    start = Clock::now();
    ASSERT_TRUE(upload_mesh(*via_nginx, proxied_mesh, "model/gltf-binary").is_object());
    std::cerr << "a " << proxied_mesh.size() << "-byte mesh uploaded and loaded in " << direct_ms
              << " ms directly, " << milliseconds_since(start) << " ms through nginx\n";

    const std::string rig_id = rig.at("id");
    const std::string mesh_id = mesh.at("id");
    rig.erase("cached");
    mesh.erase("cached");

    // Each replica reads back the rig and the mesh the one nginx chose stored, as it answered
    // them (the rig with its timings: read, not computed again).
    for (int i = 0; i < kReplicas; ++i) {
        SCOPED_TRACE("replica " + std::to_string(i));
        auto client = replicas_[i]->client();
        const auto got_rig = client->Get(("/v1/environments/" + rig_id).c_str());
        const auto got_mesh = client->Get(("/v1/meshes/" + mesh_id).c_str());
        ASSERT_TRUE(got_rig && got_rig->status == 200 && got_mesh && got_mesh->status == 200);
        EXPECT_EQ(Json::parse(got_rig->body), rig);
        EXPECT_EQ(Json::parse(got_mesh->body), mesh);
    }

    // The same frame from every replica directly, each its first of the scene.
    const Json request = frame_request(rig_id, mesh_id);
    std::vector<Answer> frames;
    for (int i = 0; i < kReplicas; ++i) {
        const double gl_before = admin_metric(*replicas_[i], "oer_render_seconds_sum");
        start = Clock::now();
        frames.push_back(answer_of(post_json(*replicas_[i]->client(), "/v1/render", request)));
        const long long frame_ms = milliseconds_since(start);
        ASSERT_EQ(frames.back().status, 200) << frames.back().body;
        std::cerr << "replica " << i << ": its first 192x144 frame of the scene in " << frame_ms
                  << " ms (GL "
                  << std::lround(
                         (admin_metric(*replicas_[i], "oer_render_seconds_sum") - gl_before) *
                         1000.0)
                  << " ms)\n";
        EXPECT_EQ(frames[i].etag, frames[0].etag);
        EXPECT_TRUE(frames[i].body == frames[0].body)
            << "replica " << i << "'s frame differs from replica 0's";
    }
    const Answer through_nginx = answer_of(post_json(*via_nginx, "/v1/render", request));
    ASSERT_EQ(through_nginx.status, 200) << through_nginx.body;
    EXPECT_TRUE(through_nginx.body == frames[0].body) << "the frame through nginx differs";
    EXPECT_EQ(through_nginx.etag, frames[0].etag);
}

TEST_F(Replicas, ConcurrentUploadsOfTheSameBytesLeaveOneEntry) {
    struct Upload {
        std::string path;
        std::string bytes;
        std::string content_type;
    };
    const std::string map = exr_bytes(three_disc_environment(1024, 512).image);
    const std::string map_id = api::sha256_hex(map);
    const std::string grid = grid_obj(150);
    for (const Upload& upload : {Upload{"/v1/environments?light_count=2", map, "image/x-exr"},
                                 Upload{"/v1/meshes", grid, "model/obj"}}) {
        SCOPED_TRACE(upload.path);
        // Released together, each to its own replica.
        std::latch ready(2);
        std::array<Answer, 2> answers;
        std::vector<std::thread> clients;
        for (int i = 0; i < 2; ++i) {
            clients.emplace_back([&, i, client = replicas_[i]->client()] {
                ready.arrive_and_wait();
                answers[i] = answer_of(
                    client->Post(upload.path.c_str(), upload.bytes, upload.content_type.c_str()));
            });
        }
        for (std::thread& thread : clients) {
            thread.join();
        }
        ASSERT_TRUE(answers[0].status == 201 || answers[0].status == 200) << answers[0].body;
        ASSERT_TRUE(answers[1].status == 201 || answers[1].status == 200) << answers[1].body;
        const Json first = without(Json::parse(answers[0].body), {"cached"});
        const Json second = without(Json::parse(answers[1].body), {"cached"});
        // Both stored it (neither found the other's entry first): the writes overlapped.
        EXPECT_EQ(answers[0].status, 201);
        EXPECT_EQ(answers[1].status, 201);
        ASSERT_EQ(first.at("id"), second.at("id"));
        const std::string id = first.at("id");

        // One file per entry, where each writer renamed its own temporary file, and no
        // temporary file left.
        EXPECT_EQ(temporary_files(root_.data()), std::vector<fs::path>{});
        if (upload.path.starts_with("/v1/environments")) {
            EXPECT_EQ(files_named(root_.data(), map_id),
                      std::vector<std::string>{"environments/" + map_id + ".exr"});
            EXPECT_EQ(files_named(root_.data(), id),
                      (std::vector<std::string>{"rig-sources/" + id + ".sealed",
                                                "rigs/" + id + ".sealed"}));
            // Each computed the rig: the same but for its timings.
            EXPECT_EQ(without(first, {"timings_ms"}), without(second, {"timings_ms"}));
        } else {
            // The mesh and its summary (what a render's cost is estimated from).
            EXPECT_EQ(files_named(root_.data(), id),
                      (std::vector<std::string>{"mesh-summaries/" + id + ".sealed",
                                                "meshes/" + id + ".obj"}));
            EXPECT_EQ(first, second);
        }

        // The third replica reads what the last rename left: one of the two, whole.
        const std::string path =
            (upload.path.starts_with("/v1/environments") ? "/v1/environments/" : "/v1/meshes/") +
            id;
        const auto read = replicas_[2]->client()->Get(path.c_str());
        ASSERT_TRUE(read && read->status == 200);
        const Json stored = Json::parse(read->body);
        EXPECT_TRUE(stored == first || stored == second) << stored.dump();
    }
    const Answer frame = answer_of(
        post_json(*replicas_[2]->client(), "/v1/render",
                  frame_request(api::rig_id(map_id, api::parse_rig_options({{"light_count", "2"}})),
                                api::sha256_hex(grid))));
    EXPECT_EQ(frame.status, 200) << frame.body;
}

TEST_F(Replicas, AReplicaKilledMidUploadLeavesNothingDamagedAndItsRestartSparesOthersWrites) {
    // Lists the environments a replica knows (the first page: this test stores few).
    const auto listed = [](const ServerProcess& replica) {
        std::set<std::string> ids;
        const auto page = replica.client()->Get("/v1/environments?limit=100");
        EXPECT_TRUE(page && page->status == 200);
        if (page && page->status == 200) {
            // Named: a range-for over a member of a temporary would outlive the temporary.
            const Json listing = Json::parse(page->body);
            for (const Json& entry : listing.at("environments")) {
                ids.insert(entry.at("id").get<std::string>());
            }
        }
        return ids;
    };
    const std::map<std::string, std::string> two_lights{{"light_count", "2"}};

    {
        SCOPED_TRACE("killed with half the body sent");
        const std::string map = exr_bytes(three_disc_environment(384, 192).image);
        const std::string map_id = api::sha256_hex(map);
        const std::string rig_id = api::rig_id(map_id, api::parse_rig_options(two_lights));
        RawSocket socket(replicas_[0]->port());
        ASSERT_TRUE(socket.ok());
        ASSERT_TRUE(socket.send_all(
            "POST /v1/environments?light_count=2 HTTP/1.1\r\nHost: 127.0.0.1\r\n"
            "Content-Type: image/x-exr\r\nContent-Length: " +
            std::to_string(map.size()) + "\r\n\r\n" + map.substr(0, map.size() / 2)));
        EXPECT_EQ(socket.receive(200ms), std::string()) << "answered before its body was whole";
        replicas_[0]->kill();
        for (int i = 1; i < kReplicas; ++i) {
            expect_problem("GET", "/v1/environments/{id}",
                           replicas_[i]->client()->Get(("/v1/environments/" + rig_id).c_str()),
                           server::ProblemKind::UnknownId);
            EXPECT_EQ(listed(*replicas_[i]).count(rig_id), 0u);
        }
        EXPECT_EQ(files_named(root_.data(), map_id), std::vector<std::string>{});
        // Through nginx, which may try the dead replica first and then another.
        const Json rig = upload_environment(*nginx_->client(), map, "image/x-exr", "light_count=2");
        ASSERT_TRUE(rig.is_object());
        EXPECT_EQ(rig.at("id"), rig_id);
        EXPECT_EQ(rig.at("cached"), false);
        const Answer frame = answer_of(
            post_json(*replicas_[2]->client(), "/v1/render", frame_request(rig_id, "default")));
        EXPECT_EQ(frame.status, 200) << frame.body;
    }

    {
        SCOPED_TRACE("killed while it preprocesses");
        start(0);
        ASSERT_FALSE(HasFatalFailure());
        const std::string map =
            exr_bytes(three_disc_environment(kLargeMapWidth, kLargeMapWidth / 2).image);
        const std::string rig_id =
            api::rig_id(api::sha256_hex(map), api::parse_rig_options(two_lights));
        Answer answer;
        std::thread upload([&, client = replicas_[0]->client()] {
            answer = answer_of(client->Post("/v1/environments?light_count=2", map, "image/x-exr"));
        });
        const bool computing = computation_started(*replicas_[0], "rig");
        std::this_thread::sleep_for(100ms);
        const bool still_computing = admin_metric(*replicas_[0], "oer_computations_in_progress",
                                                  {{"computation", "rig"}}) >= 1.0;
        replicas_[0]->kill();
        upload.join();
        ASSERT_TRUE(computing) << "its preprocessing never started";
        EXPECT_TRUE(still_computing) << "the kill came after the preprocessing";
        EXPECT_EQ(answer.status, 0) << "answered before the kill";

        // Unknown to the others, or (had it stored the rig before the kill) whole: the rig an
        // uninterrupted upload gives, listed.
        std::vector<Json> seen;
        for (int i = 1; i < kReplicas; ++i) {
            const auto lookup = replicas_[i]->client()->Get(("/v1/environments/" + rig_id).c_str());
            ASSERT_TRUE(lookup && (lookup->status == 200 || lookup->status == 404));
            EXPECT_EQ(listed(*replicas_[i]).count(rig_id), lookup->status == 200 ? 1u : 0u);
            if (lookup->status == 200) {
                seen.push_back(without(Json::parse(lookup->body), {"timings_ms"}));
            }
        }
        const Json rig =
            upload_environment(*replicas_[1]->client(), map, "image/x-exr", "light_count=2");
        ASSERT_TRUE(rig.is_object());
        EXPECT_EQ(rig.at("id"), rig_id);
        for (const Json& before : seen) {
            EXPECT_EQ(before, without(rig, {"cached", "timings_ms"}));
        }
        std::cerr << "killed " << kLargeMapWidth << "x" << kLargeMapWidth / 2
                  << " map's preprocessing: known to " << seen.size()
                  << " of the other replicas afterwards\n";
        const Answer frame = answer_of(
            post_json(*replicas_[2]->client(), "/v1/render", frame_request(rig_id, "default")));
        EXPECT_EQ(frame.status, 200) << frame.body;
    }

    {
        // Replica 0 restarts while replica 1 writes a mesh to the store: the write is held in
        // its middle (SIGSTOP as soon as its temporary file appears) until the restarted
        // replica is up, so that its store opens the folder exactly then.
        SCOPED_TRACE("restarted during another replica's write");
        bool caught = false;
        for (unsigned seed = 1; seed <= 3 && !caught; ++seed) {
            const std::string mesh = noise_box_glb(seed, kTextureSide);
            const std::string id = api::sha256_hex(mesh);
            FolderWatch watch(root_.data() / "meshes", IN_CREATE);
            Answer answer;
            std::thread upload([&, client = replicas_[1]->client()] {
                answer = answer_of(client->Post("/v1/meshes", mesh, "model/gltf-binary"));
            });
            const auto created = watch.wait(".tmp-" + id, 60s);
            if (created) {
                ::kill(replicas_[1]->pid(), SIGSTOP);
            }
            const fs::path temporary = root_.data() / "meshes" / created.value_or("none");
            caught = created && fs::exists(temporary);
            bool spared = false;
            if (caught) {
                start(0);
                spared = fs::exists(temporary);
            }
            ::kill(replicas_[1]->pid(), SIGCONT);
            upload.join();
            ASSERT_FALSE(HasFatalFailure());
            ASSERT_TRUE(created) << "replica 1 made no temporary file for the mesh within 60 s";
            if (!caught) {
                std::cerr << "the write of " << mesh.size()
                          << " bytes ended before it was stopped; again with other bytes\n";
                continue;
            }
            EXPECT_TRUE(spared) << "the restarted replica removed another's write in progress";
            EXPECT_NE(replicas_[0]->log().find("writes in progress"), std::string::npos)
                << replicas_[0]->log();
            ASSERT_EQ(answer.status, 201) << answer.body;
            // The restarted replica serves and draws the mesh the other stored meanwhile.
            const auto lookup = replicas_[0]->client()->Get(("/v1/meshes/" + id).c_str());
            ASSERT_TRUE(lookup && lookup->status == 200);
            EXPECT_EQ(Json::parse(lookup->body), without(Json::parse(answer.body), {"cached"}));
            const Answer frame = answer_of(
                post_json(*replicas_[0]->client(), "/v1/render", frame_request("default", id)));
            EXPECT_EQ(frame.status, 200) << frame.body;
        }
        EXPECT_TRUE(caught) << "no write was caught in its middle in 3 tries";
    }
}

TEST_F(Replicas, NginxServesRepeatedFramesFromItsCacheAndAnswersIfNoneMatch) {
    auto via_nginx = nginx_->client();
    // Requests of /v1/render that reached a replica, and frames the replicas rendered. A
    // replica counts a request once its answer is written: the count may trail the answer by
    // a moment, so each expectation waits for it, and a stray request shows in the next one.
    const auto requests = [&] {
        return total("oer_http_requests_total", {{"route", "/v1/render"}});
    };
    const auto renders = [&] { return total("oer_render_seconds_count"); };
    double asked = requests();
    double rendered = renders();
    const auto expect_reached = [&](double more_requests, std::optional<double> more_renders,
                                    const std::string& after) {
        asked += more_requests;
        rendered += more_renders.value_or(0.0);
        const bool settled = eventually(
            [&] { return requests() == asked && (!more_renders || renders() == rendered); }, 2s);
        EXPECT_TRUE(settled) << after << ": the replicas counted " << requests() << " requests and "
                             << renders() << " renders, expected " << asked << " and " << rendered;
        asked = requests();
        rendered = renders();
    };
    const std::string frame = "/v1/render?environment=default&mesh=default&width=96&height=64";

    // The first asks a replica, which renders it; the second is nginx's.
    const auto first = via_nginx->Get((frame + "&yaw=11").c_str());
    ASSERT_TRUE(first && first->status == 200);
    EXPECT_EQ(first->get_header_value("X-Proxy-Cache"), "MISS");
    expect_reached(1, 1, "a new frame");
    const std::string etag = first->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    const auto second = via_nginx->Get((frame + "&yaw=11").c_str());
    ASSERT_TRUE(second && second->status == 200);
    EXPECT_EQ(second->get_header_value("X-Proxy-Cache"), "HIT");
    EXPECT_TRUE(second->body == first->body);
    EXPECT_EQ(second->get_header_value("ETag"), etag);

    // If-None-Match: 304 from nginx when it matches the cached ETag (weakly too), the frame
    // when it does not; none of these reaches a replica.
    const auto unchanged = via_nginx->Get((frame + "&yaw=11").c_str(), {{"If-None-Match", etag}});
    ASSERT_TRUE(unchanged);
    EXPECT_EQ(unchanged->status, 304);
    EXPECT_EQ(unchanged->get_header_value("ETag"), etag);
    EXPECT_TRUE(unchanged->body.empty());
    const auto weak = via_nginx->Get((frame + "&yaw=11").c_str(), {{"If-None-Match", "W/" + etag}});
    ASSERT_TRUE(weak);
    EXPECT_EQ(weak->status, 304);
    const auto other =
        via_nginx->Get((frame + "&yaw=11").c_str(), {{"If-None-Match", "\"another\""}});
    ASSERT_TRUE(other && other->status == 200);
    EXPECT_TRUE(other->body == first->body);
    expect_reached(0, 0, "the same frame again, plainly and with If-None-Match");

    // A frame nginx has not cached, asked with the ETag a replica gave for it: nginx fetches
    // the whole frame (to cache it) and answers 304; then it serves the frame itself.
    const auto direct = replicas_[0]->client()->Get((frame + "&yaw=22").c_str());
    ASSERT_TRUE(direct && direct->status == 200);
    expect_reached(1, 1, "a frame asked of a replica directly");
    const auto revalidated = via_nginx->Get((frame + "&yaw=22").c_str(),
                                            {{"If-None-Match", direct->get_header_value("ETag")}});
    ASSERT_TRUE(revalidated);
    EXPECT_EQ(revalidated->status, 304);
    // Rendered again unless nginx chose the replica that has it in memory.
    expect_reached(1, std::nullopt, "a new frame with If-None-Match");
    const auto cached = via_nginx->Get((frame + "&yaw=22").c_str());
    ASSERT_TRUE(cached && cached->status == 200);
    EXPECT_EQ(cached->get_header_value("X-Proxy-Cache"), "HIT");
    EXPECT_TRUE(cached->body == direct->body);
    expect_reached(0, 0, "that frame again");

    // A request carrying the API key neither reads nor fills the cache.
    const auto keyed =
        via_nginx->Get((frame + "&yaw=33").c_str(), {{"Authorization", "Bearer some-key"}});
    ASSERT_TRUE(keyed && keyed->status == 200);
    EXPECT_EQ(keyed->get_header_value("X-Proxy-Cache"), "BYPASS");
    const auto after_keyed = via_nginx->Get((frame + "&yaw=33").c_str());
    ASSERT_TRUE(after_keyed && after_keyed->status == 200);
    EXPECT_EQ(after_keyed->get_header_value("X-Proxy-Cache"), "MISS");
    const auto keyed_again =
        via_nginx->Get((frame + "&yaw=11").c_str(), {{"Authorization", "Bearer some-key"}});
    ASSERT_TRUE(keyed_again && keyed_again->status == 200);
    expect_reached(3, std::nullopt, "three frames with and without the key");

    // Errors are never cached: each asks a replica again.
    const std::string unknown = "/v1/render?environment=" + std::string(64, 'a') + "&mesh=default";
    for (int i = 0; i < 2; ++i) {
        expect_problem("GET", "/v1/render", via_nginx->Get(unknown.c_str()),
                       server::ProblemKind::UnknownId, "environment");
    }
    expect_reached(2, 0, "an unknown environment's frame twice");
}

TEST_F(Replicas, ACrowdThroughNginxSpreadsOverTheReplicasSlow) {
    // The same file with one replica, beside the fixture's nginx with all of them.
    Nginx to_one(root_.root() / "nginx-one", {replicas_[0]->port()});
    ASSERT_FALSE(HasFailure());
    constexpr int kClients = 6;
    constexpr auto kPhase = 4s;
    std::atomic<int> frame_number = 0;
    struct Phase {
        const Nginx* nginx;
        std::string name;
    };
    std::map<std::string, double> frames_per_second;
    for (const Phase& phase : {Phase{&to_one, "1 replica"},
                               Phase{nginx_.get(), std::to_string(kReplicas) + " replicas"}}) {
        std::vector<double> rendered_before;
        for (const auto& replica : replicas_) {
            rendered_before.push_back(admin_metric(*replica, "oer_render_seconds_count"));
        }
        std::map<int, int> statuses;
        std::mutex statuses_mutex;
        std::vector<std::thread> crowd;
        const auto start = Clock::now();
        for (int i = 0; i < kClients; ++i) {
            crowd.emplace_back([&, i] {
                auto client = load_client(phase.nginx->port(), i, 60);
                std::map<int, int> own;
                while (Clock::now() - start < kPhase) {
                    // A new angle each time: neither nginx nor a replica has it.
                    const int n = ++frame_number;
                    const auto result = client->Get(
                        ("/v1/render?environment=default&mesh=default&width=256&height=256&yaw=" +
                         std::to_string(-180.0 + 0.01 * n))
                            .c_str());
                    ++own[result ? result->status : 0];
                }
                const std::lock_guard lock(statuses_mutex);
                for (const auto& [status, count] : own) {
                    statuses[status] += count;
                }
            });
        }
        for (std::thread& thread : crowd) {
            thread.join();
        }
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        frames_per_second[phase.name] = statuses[200] / seconds;
        std::cerr << kClients << " clients through nginx to " << phase.name << ": "
                  << frames_per_second[phase.name] << " frames/s (256x256)";
        for (const auto& [status, count] : statuses) {
            std::cerr << ", " << count << " x " << status;
        }
        std::cerr << "; rendered by the replicas:";
        std::vector<double> rendered;
        for (std::size_t r = 0; r < replicas_.size(); ++r) {
            rendered.push_back(admin_metric(*replicas_[r], "oer_render_seconds_count") -
                               rendered_before[r]);
            std::cerr << " " << rendered.back();
        }
        std::cerr << " (2 CPU cores shared by all)\n";
        // Only frames and the refusals oer and nginx promise under load.
        for (const auto& [status, count] : statuses) {
            EXPECT_TRUE(status == 200 || status == 503) << count << " answers " << status;
        }
        EXPECT_GT(statuses[200], 0);
        if (phase.nginx == &to_one) {
            EXPECT_GT(rendered[0], 0);
            EXPECT_EQ(rendered[1] + rendered[2], 0) << "nginx with one replica used others";
        } else {
            for (std::size_t r = 0; r < rendered.size(); ++r) {
                EXPECT_GT(rendered[r], 0) << "nginx sent replica " << r << " nothing";
            }
        }
    }
}
