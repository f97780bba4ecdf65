// A full disk: oer-server's data folder on a small tmpfs that the test fills with a ballast
// file. Uploads that cannot be stored answer 507 Insufficient Storage (RFC 4918 section 11.5)
// naming the write that failed, leave nothing behind, and succeed once the ballast goes; the
// service stays up meanwhile (probes, rigs and frames of stored assets, frames whose scene
// transfer cannot be stored).
//
// The tmpfs is the server's own: mounted in a mount namespace of its own by `unshare --mount`
// (root with CAP_SYS_ADMIN), else by `unshare --user --map-root-user --mount` (unprivileged user
// namespaces); the test reaches it through /proc/<pid>/root. Where neither may mount (a
// container without CAP_SYS_ADMIN, whose seccomp profile refuses unshare), it uses the
// container's own small tmpfs /dev/shm, filled for the few seconds of the test. When none of
// these is possible the test fails, saying why each was not.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/statfs.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>

#include "http_support.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/rig_options.hpp"
#include "server_process.hpp"

using namespace oer;
using namespace oer::itest;
using namespace oer::ptest;
namespace fs = std::filesystem;

namespace {

constexpr const char* kTmpfsSize = "32m";
// The /dev/shm fallback fills what it has free: at most this much.
constexpr std::uint64_t kMaxSharedMemoryToFill = 512ull << 20;
constexpr std::uint64_t kTmpfsMagic = 0x01021994;  // TMPFS_MAGIC, linux/magic.h

// Runs a shell command line; its exit status and what it printed on stderr.
std::pair<int, std::string> run(const std::string& command, const fs::path& scratch) {
    const fs::path err = scratch / "probe.err";
    const int raw = std::system((command + " >/dev/null 2>" + err.string()).c_str());
    std::ifstream in(err);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

std::string quoted(const std::string& text) {
    return "'" + text + "'";  // our paths hold no quote
}

// A small file system for the server's data folder, and how to reach it from this process.
class SmallDisk {
  public:
    explicit SmallDisk(const TempRoot& root) : scratch_(root.root()) {
        mount_point_ = root.root() / "disk";
        fs::create_directories(mount_point_);
        // $0: the mount point; "$@": the server's command line.
        const std::string script = std::string("mount -t tmpfs -o size=") + kTmpfsSize +
                                   " oer-full-disk \"$0\" && exec \"$@\"";
        const std::vector<std::vector<std::string>> namespaces = {
            {"unshare", "--mount", "--propagation", "private"},
            {"unshare", "--user", "--map-root-user", "--mount", "--propagation", "private"}};
        for (const auto& prefix : namespaces) {
            std::string probe;
            for (const std::string& word : prefix) {
                probe += word + " ";
            }
            probe += "-- sh -c " + quoted(script) + " " + quoted(mount_point_.string()) + " true";
            const auto [status, error] = run(probe, scratch_);
            if (status == 0) {
                wrapper_ = prefix;
                wrapper_.insert(wrapper_.end(), {"--", "sh", "-c", script, mount_point_.string()});
                how_ = "a " + std::string(kTmpfsSize) + " tmpfs mounted by `" + probe + "`";
                return;
            }
            refusals_ += "\n  `" + probe + "` failed (" + std::to_string(status) + "): " + error;
        }
        struct statfs shm {};
        if (::statfs("/dev/shm", &shm) != 0) {
            refusals_ += "\n  /dev/shm: " + std::string(std::strerror(errno));
            return;
        }
        const std::uint64_t free = std::uint64_t(shm.f_bavail) * std::uint64_t(shm.f_bsize);
        if (std::uint64_t(shm.f_type) != kTmpfsMagic || free > kMaxSharedMemoryToFill) {
            refusals_ += "\n  /dev/shm is not a tmpfs of at most " +
                         std::to_string(kMaxSharedMemoryToFill >> 20) + " MiB free (" +
                         std::to_string(free >> 20) + " MiB free)";
            return;
        }
        std::random_device random;
        mount_point_ = fs::path("/dev/shm") / ("oer-full-disk-" + std::to_string(::getpid()) + "-" +
                                               std::to_string(random()));
        fs::create_directories(mount_point_);
        shared_ = true;
        how_ = "/dev/shm, " + std::to_string(free >> 20) + " MiB free";
    }

    ~SmallDisk() {
        if (shared_) {
            std::error_code ignored;
            fs::remove_all(mount_point_, ignored);
        }
    }

    bool usable() const { return !how_.empty(); }
    const std::string& how() const { return how_; }
    const std::string& refusals() const { return refusals_; }
    const std::vector<std::string>& wrapper() const { return wrapper_; }
    // The data folder as the server names it.
    fs::path data_dir() const { return mount_point_ / "data"; }
    // The file system's root as this process reaches it, while the server runs.
    fs::path seen_from_test(const ServerProcess& server) const {
        return shared_ ? mount_point_
                       : fs::path("/proc") / std::to_string(server.pid()) / "root" /
                             mount_point_.relative_path();
    }

  private:
    fs::path scratch_;
    fs::path mount_point_;
    std::vector<std::string> wrapper_;
    std::string how_;
    std::string refusals_;
    bool shared_ = false;
};

std::uint64_t free_bytes(const fs::path& path) {
    struct statvfs status {};
    EXPECT_EQ(::statvfs(path.c_str(), &status), 0) << path << ": " << std::strerror(errno);
    return std::uint64_t(status.f_bavail) * std::uint64_t(status.f_frsize);
}

// A file that takes all the free space of its file system but `room` bytes.
class Ballast {
  public:
    Ballast(fs::path path, std::uint64_t room) : path_(std::move(path)) {
        const std::uint64_t free = free_bytes(path_.parent_path());
        if (free <= room) {
            return;
        }
        const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
        EXPECT_GE(fd, 0) << path_ << ": " << std::strerror(errno);
        if (fd < 0) {
            return;
        }
        const int result = ::posix_fallocate(fd, 0, off_t(free - room));
        EXPECT_EQ(result, 0) << "fallocate " << (free - room)
                             << " bytes: " << std::strerror(result);
        ::close(fd);
    }
    ~Ballast() { fs::remove(path_); }
    Ballast(const Ballast&) = delete;
    Ballast& operator=(const Ballast&) = delete;

  private:
    fs::path path_;
};

std::string detail_of(const httplib::Result& result) {
    if (!result) {
        return "";
    }
    return Json::parse(result->body, nullptr, false).value("detail", std::string());
}

std::vector<std::string> names_in(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder)) {
        names.push_back(entry.path().filename().string());
    }
    return names;
}

bool has_entry(const fs::path& folder, const std::string& id) {
    for (const std::string& name : names_in(folder)) {
        if (name.starts_with(id)) {
            return true;
        }
    }
    return false;
}

Json render_body(const std::string& environment, const std::string& mesh, int width,
                 double x = 0.0) {
    Json object = {{"mesh", mesh}};
    if (x != 0.0) {
        object["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, 0, 0, 1};
    }
    return {{"environment", environment},
            {"objects", {object}},
            {"width", width},
            {"height", 48},
            {"samples", 1},
            {"shadows", {{"resolution", 256}}},
            {"format", "png"}};
}

}  // namespace

TEST(FullDisk, UploadsAre507NothingIsLeftAndFreedSpaceBringsThemBack) {
    TempRoot root;
    const SmallDisk disk(root);
    ASSERT_TRUE(disk.usable()) << "no way to give the server a small file system here:"
                               << disk.refusals();
    std::cerr << "the data folder is on " << disk.how() << "\n";
    ServerLaunch launch(disk.data_dir(), root.root());
    launch.wrapper = disk.wrapper();
    ServerProcess server(launch);
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
    const fs::path top = disk.seen_from_test(server);
    const fs::path data = top / "data";
    ASSERT_TRUE(fs::is_directory(data / "environments")) << data;
    auto client = server.client();

    // Stored while there is room: a rig, a mesh, a frame of them (its transfer stored).
    const Json stored_rig = upload_environment(
        *client, exr_bytes(three_disc_environment(128, 64).image), "image/x-exr", "light_count=3");
    // OBJ: Lambertian, so that no frame here waits for a specular cube.
    const Json stored_mesh =
        upload_mesh(*client, box_obj({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5}), "model/obj");
    ASSERT_TRUE(stored_rig.is_object() && stored_mesh.is_object());
    const std::string rig_id = stored_rig.at("id"), mesh_id = stored_mesh.at("id");
    const auto first_frame = post_json(*client, "/v1/render", render_body(rig_id, mesh_id, 64));
    ASSERT_TRUE(first_frame);
    ASSERT_EQ(first_frame->status, 200) << first_frame->body;
    // The upload's bakes ahead stored too, before the disk fills.
    wait_for_preparation(*client, mesh_id);

    // What is uploaded while the disk is full.
    const std::string map = exr_bytes(three_disc_environment(160, 80).image);
    const std::string map_id = api::sha256_hex(map);
    const std::string new_rig_id =
        api::rig_id(map_id, api::parse_rig_options({{"light_count", "2"}}));
    const std::string obj = box_obj({-0.25, 0.0, -0.25}, {0.25, 2.0, 0.25});
    const std::string obj_id = api::sha256_hex(obj);
    const auto post_map = [&] {
        return client->Post("/v1/environments?light_count=2", map, "image/x-exr");
    };
    const auto post_obj = [&] { return client->Post("/v1/meshes", obj, "model/obj"); };
    const auto expect_nothing_left = [&](bool map_stored) {
        EXPECT_EQ(temporary_files(data), std::vector<fs::path>{});
        EXPECT_EQ(has_entry(data / "environments", map_id), map_stored);
        EXPECT_FALSE(has_entry(data / "rigs", new_rig_id));
        EXPECT_FALSE(has_entry(data / "rig-sources", new_rig_id));
        EXPECT_FALSE(has_entry(data / "meshes", obj_id));
        expect_problem("GET", "/v1/environments/{id}",
                       client->Get(("/v1/environments/" + new_rig_id).c_str()),
                       server::ProblemKind::UnknownId);
        expect_problem("GET", "/v1/meshes/{id}", client->Get(("/v1/meshes/" + obj_id).c_str()),
                       server::ProblemKind::UnknownId);
    };

    {
        SCOPED_TRACE("no room at all");
        const Ballast ballast(top / "ballast", 0);
        ASSERT_EQ(free_bytes(top), 0u);
        const auto refused_map = post_map();
        expect_problem("POST", "/v1/environments", refused_map,
                       server::ProblemKind::InsufficientStorage);
        const std::string map_detail = detail_of(refused_map);
        EXPECT_NE(map_detail.find("the map " + map_id + " could not be stored"), std::string::npos)
            << map_detail;
        EXPECT_NE(map_detail.find(std::strerror(ENOSPC)), std::string::npos) << map_detail;
        EXPECT_NE(map_detail.find("storage is full"), std::string::npos) << map_detail;
        EXPECT_EQ(map_detail.find(top.string()), std::string::npos) << "a path in " << map_detail;
        const auto refused_mesh = post_obj();
        expect_problem("POST", "/v1/meshes", refused_mesh,
                       server::ProblemKind::InsufficientStorage);
        EXPECT_NE(detail_of(refused_mesh).find("the mesh " + obj_id + " could not be stored"),
                  std::string::npos)
            << detail_of(refused_mesh);
        expect_nothing_left(false);

        // The service is up: probes, stored rigs and meshes, frames of them, and a frame of a
        // new scene, whose transfer cannot be stored.
        EXPECT_EQ(client->Get("/healthz")->status, 200);
        EXPECT_EQ(server.admin_client()->Get("/readyz")->status, 200);
        const Json rig = expect_conforms("GET", "/v1/environments/{id}",
                                         client->Get(("/v1/environments/" + rig_id).c_str()));
        ASSERT_TRUE(rig.is_object());
        EXPECT_EQ(rig.at("sh"), stored_rig.at("sh"));
        EXPECT_EQ(client->Get(("/v1/meshes/" + mesh_id).c_str())->status, 200);
        const auto again = post_json(*client, "/v1/render", render_body(rig_id, mesh_id, 64));
        ASSERT_TRUE(again);
        ASSERT_EQ(again->status, 200) << again->body;
        EXPECT_TRUE(again->body == first_frame->body);
        const auto wider = post_json(*client, "/v1/render", render_body(rig_id, mesh_id, 80));
        ASSERT_TRUE(wider);
        EXPECT_EQ(wider->status, 200) << wider->body;
        const double transfers = admin_metric(server, "oer_transfers_computed_total");
        const auto moved = post_json(*client, "/v1/render", render_body(rig_id, mesh_id, 64, 0.3));
        ASSERT_TRUE(moved);
        EXPECT_EQ(moved->status, 200) << moved->body;
        EXPECT_EQ(admin_metric(server, "oer_transfers_computed_total"), transfers + 1.0);
        EXPECT_NE(server.log().find("is kept in memory only"), std::string::npos);
        EXPECT_EQ(temporary_files(data), std::vector<fs::path>{});
    }
    {
        SCOPED_TRACE("room for the map and the rig's record, not for the rig");
        const std::uint64_t page = 4096;
        const Ballast ballast(top / "ballast", (map.size() + page - 1) / page * page + page);
        const auto refused = post_map();
        expect_problem("POST", "/v1/environments", refused,
                       server::ProblemKind::InsufficientStorage);
        EXPECT_NE(detail_of(refused).find("the rig " + new_rig_id + " could not be stored"),
                  std::string::npos)
            << detail_of(refused);
        // The map stays (its upload again will not store it twice); the rig's record goes
        // with the rig, so the id is unknown rather than half there.
        expect_nothing_left(true);
    }

    // Space freed: the same uploads succeed, and what they made is served.
    const Json rig = upload_environment(*client, map, "image/x-exr", "light_count=2");
    ASSERT_TRUE(rig.is_object());
    EXPECT_EQ(rig.at("id"), new_rig_id);
    EXPECT_EQ(rig.at("cached"), false);
    const Json mesh = upload_mesh(*client, obj, "model/obj");
    ASSERT_TRUE(mesh.is_object());
    EXPECT_EQ(mesh.at("id"), obj_id);
    EXPECT_EQ(client->Get(("/v1/environments/" + new_rig_id).c_str())->status, 200);
    EXPECT_EQ(client->Get(("/v1/meshes/" + obj_id).c_str())->status, 200);
    const auto frame = post_json(*client, "/v1/render", render_body(new_rig_id, obj_id, 64));
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->status, 200) << frame->body;
    EXPECT_TRUE(has_entry(data / "rigs", new_rig_id));
    EXPECT_TRUE(has_entry(data / "meshes", obj_id));
    EXPECT_EQ(temporary_files(data), std::vector<fs::path>{});
    EXPECT_EQ(server.stop(), 0);
}
