// kill -9 and a restart on the same data folder: nothing the server acknowledged is lost and
// nothing damaged is served. The server is killed while an upload's body arrives, while a map is
// preprocessed, while a frame makes a specular cube and bakes a scene's transfer, and while a
// mesh is written to the store, each a few times at different moments; the moments are found by
// watching the server (its oer_computations_in_progress gauge, inotify on its store), never by
// guessing a delay. After every restart each rig, mesh and frame that was answered 200 or 201
// before is served the same (the same JSON, the same frame bytes and ETag), no temporary file of an
// interrupted write is left, and what was never acknowledged is unknown (404) or, uploaded or drawn
// again, computed as an uninterrupted server computes it. (tests/integration/store_test.cpp and
// tests/server/asset_store_test.cpp cover restarts after a clean stop, damaged entries and leftover
// temporary files in-process.)
#include <gtest/gtest.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <map>
#include <optional>
#include <thread>

#include "http_support.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/mesh/material_spheres.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/server/asset_store.hpp"
#include "server_process.hpp"

using namespace oer;
using namespace oer::itest;
using namespace oer::ptest;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Where in a computation a kill lands: at its start, half way, near its end (fractions of how
// long an uninterrupted one took).
constexpr double kMoments[] = {0.0, 0.5, 0.9};

// The material spheres (oer/mesh/material_spheres.hpp) at their default 32 rings: 21 k
// vertices, whose scene transfer takes a second or two to bake at the test servers' smallest
// budget of 64 rays a point (2.1 s measured on 2 cores at a load of 10).
constexpr int kSceneRings = 32;
// An upload or a frame answered before the kill.
struct Acknowledged {
    std::map<std::string, Json> rigs;    // id -> the upload's answer, "cached" removed
    std::map<std::string, Json> meshes;  // id -> the upload's answer, "cached" removed
    struct Frame {
        Json request;
        std::string etag;
        std::string body;
    };
    std::vector<Frame> frames;

    void add_rig(Json answer) {
        answer.erase("cached");
        const std::string id = answer.at("id");
        rigs[id] = std::move(answer);
    }
    void add_mesh(Json answer) {
        answer.erase("cached");
        const std::string id = answer.at("id");
        meshes[id] = std::move(answer);
    }
};

// A small frame of one object; occlusion off keeps dense meshes from needing a transfer bake.
Json frame_request(const std::string& environment, const std::string& mesh, bool occlusion) {
    return {{"environment", environment},
            {"objects", {{{"mesh", mesh}}}},
            {"width", 64},
            {"height", 48},
            {"samples", 1},
            {"shadows", {{"resolution", 256}}},
            {"occlusion", occlusion},
            {"format", "png"}};
}

Answer render(const ServerProcess& server, const Json& request) {
    return answer_of(post_json(*server.client(), "/v1/render", request));
}

// Every acknowledged rig, mesh and frame is served as it was answered.
void expect_served(const ServerProcess& server, const Acknowledged& acknowledged) {
    auto client = server.client();
    for (const auto& [id, rig] : acknowledged.rigs) {
        const auto result = client->Get(("/v1/environments/" + id).c_str());
        ASSERT_TRUE(result && result->status == 200) << "rig " << id << " is lost";
        // Equal with its timings: read back, not recomputed.
        EXPECT_EQ(Json::parse(result->body), rig) << "rig " << id << " changed";
    }
    for (const auto& [id, mesh] : acknowledged.meshes) {
        const auto result = client->Get(("/v1/meshes/" + id).c_str());
        ASSERT_TRUE(result && result->status == 200) << "mesh " << id << " is lost";
        EXPECT_EQ(Json::parse(result->body), mesh) << "mesh " << id << " changed";
    }
    for (const Acknowledged::Frame& frame : acknowledged.frames) {
        const Answer again = render(server, frame.request);
        ASSERT_EQ(again.status, 200) << frame.request.dump();
        EXPECT_EQ(again.etag, frame.etag) << frame.request.dump();
        EXPECT_TRUE(again.body == frame.body) << "the frame differs: " << frame.request.dump();
    }
}

class KillRestart : public ::testing::Test {
  protected:
    void start(const fs::path& data) {
        server_.reset();
        server_ = std::make_unique<ServerProcess>(ServerLaunch(data, root_.root()));
    }

    // After a kill -9: a server on the same data folder that serves everything acknowledged,
    // whose store removed (and logged) any temporary file the killed write left. The store
    // spares temporary files younger than kAbandonedTemporaryAge (they may be another
    // process's writes in progress: asset_store.hpp, tests/process/replicas_test.cpp), so the
    // killed write's are dated back by that much, as for a restart that came later.
    void restart() {
        const std::vector<fs::path> leftovers_before = temporary_files(root_.data());
        const bool leftovers = !leftovers_before.empty();
        set_untouched_for(leftovers_before,
                          server::kAbandonedTemporaryAge + std::chrono::minutes(1));
        start(root_.data());
        if (::testing::Test::HasFatalFailure()) {
            return;
        }
        EXPECT_EQ(temporary_files(root_.data()), std::vector<fs::path>{});
        EXPECT_EQ(server_->log().find("left by an interrupted write") != std::string::npos,
                  leftovers)
            << "the store's start-up and the temporary files left disagree";
        expect_served(*server_, acknowledged_);
    }

    void acknowledge_frame(const Json& request) {
        const Answer frame = render(*server_, request);
        ASSERT_EQ(frame.status, 200) << request.dump();
        acknowledged_.frames.push_back({request, frame.etag, frame.body});
    }

    TempRoot root_;
    Acknowledged acknowledged_;
    std::unique_ptr<ServerProcess> server_;
};

}  // namespace

TEST_F(KillRestart, DuringAnUploadsBody) {
    start(root_.data());
    ASSERT_FALSE(HasFatalFailure());
    auto client = server_->client();
    acknowledged_.add_rig(upload_environment(
        *client, exr_bytes(three_disc_environment(128, 64).image), "image/x-exr", "light_count=3"));
    acknowledged_.add_mesh(
        upload_mesh(*client, box_obj({-0.5, 0, -0.5}, {0.5, 1, 0.5}), "model/obj"));
    ASSERT_FALSE(HasFatalFailure());
    acknowledge_frame(frame_request(acknowledged_.rigs.begin()->first,
                                    acknowledged_.meshes.begin()->first, true));

    const std::string map = exr_bytes(three_disc_environment(192, 96).image);
    const std::string map_id = api::sha256_hex(map);
    const std::string rig_id = api::rig_id(map_id, api::parse_rig_options({{"light_count", "2"}}));
    for (const std::size_t sent : {std::size_t(0), map.size() / 2, map.size() - 1}) {
        SCOPED_TRACE(std::to_string(sent) + " of the body's " + std::to_string(map.size()) +
                     " bytes sent");
        RawSocket socket(server_->port());
        ASSERT_TRUE(socket.ok());
        ASSERT_TRUE(
            socket.send_all("POST /v1/environments?light_count=2 HTTP/1.1\r\n"
                            "Host: 127.0.0.1\r\nContent-Type: image/x-exr\r\n"
                            "Content-Length: " +
                            std::to_string(map.size()) + "\r\n\r\n" + map.substr(0, sent)));
        // The server waits for the rest: it has not answered.
        EXPECT_EQ(socket.receive(std::chrono::milliseconds(200)), std::string());
        server_->kill();
        restart();
        ASSERT_FALSE(HasFatalFailure());
        expect_problem("GET", "/v1/environments/{id}",
                       server_->client()->Get(("/v1/environments/" + rig_id).c_str()),
                       server::ProblemKind::UnknownId);
        for (const auto& entry : fs::directory_iterator(root_.data() / "environments")) {
            EXPECT_FALSE(entry.path().filename().string().starts_with(map_id)) << entry.path();
        }
    }
    EXPECT_EQ(server_->stop(), 0);
}

TEST_F(KillRestart, DuringPreprocessingSlow) {
    start(root_.data());
    ASSERT_FALSE(HasFatalFailure());
    const std::string map =
        exr_bytes(three_disc_environment(kLargeMapWidth, kLargeMapWidth / 2).image);
    const std::string map_id = api::sha256_hex(map);
    // How long the server took for the last rig it computed whole (oer_preprocess_seconds):
    // the kills aim at fractions of it.
    std::chrono::milliseconds duration{};
    const auto upload_whole = [&](const std::string& query) {
        const double before = admin_metric(*server_, "oer_preprocess_seconds_sum");
        Json rig = upload_environment(*server_->client(), map, "image/x-exr", query);
        if (rig.is_object() && rig.at("cached") == false) {
            duration = std::chrono::milliseconds(std::lround(
                (admin_metric(*server_, "oer_preprocess_seconds_sum") - before) * 1000.0));
            std::cerr << "preprocessing a " << kLargeMapWidth << "x" << kLargeMapWidth / 2
                      << " map took " << duration.count() << " ms\n";
        }
        return rig;
    };
    acknowledged_.add_rig(upload_whole("light_count=4"));
    ASSERT_FALSE(HasFatalFailure());
    acknowledge_frame(frame_request(acknowledged_.rigs.begin()->first, "default", true));

    // Each kill with other options (another rig of the same map), so that none is cached.
    const LoadedImage loaded =
        load_image_memory(std::as_bytes(std::span(map.data(), map.size())), "map.exr");
    int killed_while_computing = 0;
    for (int lights = 1; lights <= int(std::size(kMoments)); ++lights) {
        const double moment = kMoments[lights - 1];
        SCOPED_TRACE("killed at " + std::to_string(moment) + " of the preprocessing time");
        const std::string query = "light_count=" + std::to_string(lights);
        const RigOptions options =
            api::parse_rig_options({{"light_count", std::to_string(lights)}});
        const std::string rig_id = api::rig_id(map_id, options);

        Answer answer;
        std::thread upload([&, client = server_->client()] {
            answer =
                answer_of(client->Post(("/v1/environments?" + query).c_str(), map, "image/x-exr"));
        });
        const bool computing = computation_started(*server_, "rig");
        std::this_thread::sleep_for(duration * moment);
        const bool still_computing =
            admin_metric(*server_, "oer_computations_in_progress", {{"computation", "rig"}}) >= 1;
        server_->kill();
        upload.join();
        ASSERT_TRUE(computing) << "the rig's preprocessing never started";
        killed_while_computing += still_computing;
        if (answer.status == 200 || answer.status == 201) {
            acknowledged_.add_rig(Json::parse(answer.body));
        }
        restart();
        ASSERT_FALSE(HasFatalFailure());

        // Unknown, or (had it been stored whole) the rig of the map; uploaded again, the rig of
        // the map, as the library computes it.
        Json expected = api::rig_to_json(build_rig(loaded, options), rig_id);
        expected.erase("timings_ms");
        auto client = server_->client();
        const auto lookup = client->Get(("/v1/environments/" + rig_id).c_str());
        ASSERT_TRUE(lookup);
        std::cerr << "killed at " << moment << " of the preprocessing time: while computing "
                  << still_computing << ", answered " << answer.status
                  << ", its rig after the restart " << lookup->status << "\n";
        if (lookup->status != 404) {
            Json rig = expect_conforms("GET", "/v1/environments/{id}", lookup);
            ASSERT_TRUE(rig.is_object());
            rig.erase("timings_ms");
            expect_json_near(rig, expected, 1e-9, "rig read after the kill");
        }
        Json again = upload_whole(query);
        ASSERT_TRUE(again.is_object());
        EXPECT_EQ(again.at("id"), rig_id);
        acknowledged_.add_rig(again);
        again.erase("cached");
        again.erase("timings_ms");
        expect_json_near(again, expected, 1e-9, "rig uploaded again");
        acknowledge_frame(frame_request(rig_id, "default", true));
    }
    // The gauge said so just before the kill (the last moment may fall after the end).
    EXPECT_GE(killed_while_computing, 2);
    EXPECT_EQ(server_->stop(), 0);
}

TEST_F(KillRestart, DuringAFramesSpecularCubeAndTransferBakeSlow) {
    // Glossy spheres under an uploaded map: a frame first makes its rig's specular cube, then its
    // scene's transfer. Each kill aims at one computation of a scene of its own (a kill landing
    // after the computation's end stores it, and a later kill of the same scene would find
    // nothing to interrupt): three rigs of the map (1, 2 and 3 lights) for the cubes, three
    // placements of the spheres under the first for the transfers. A server that is never
    // killed draws each, on a data folder of its own: the frames to compare with, and how long
    // each computation took there.
    const std::string map = exr_bytes(three_disc_environment(256, 128).image);
    const std::string spheres(as_text(material_spheres_glb({.rings = kSceneRings})));
    const std::string mesh_id = api::sha256_hex(spheres);
    struct Scene {
        std::string computation;  // the one the kill aims at
        Json request;
        Answer reference;
        std::chrono::milliseconds duration{};
    };
    std::vector<Scene> scenes;
    std::vector<std::string> queries;
    {
        TempRoot other;
        start(other.data());
        ASSERT_FALSE(HasFatalFailure());
        std::vector<std::string> rigs;
        for (int lights = 1; lights <= 3; ++lights) {
            queries.push_back("light_count=" + std::to_string(lights));
            const Json rig =
                upload_environment(*server_->client(), map, "image/x-exr", queries.back());
            ASSERT_TRUE(rig.is_object());
            rigs.push_back(rig.at("id"));
            scenes.push_back({"specular", frame_request(rigs.back(), mesh_id, true), {}, {}});
        }
        upload_mesh(*server_->client(), spheres, "model/gltf-binary");
        for (int placement = 1; placement <= 3; ++placement) {
            Json request = frame_request(rigs.front(), mesh_id, true);
            request["objects"][0]["transform"] = {
                1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.1 * placement, 0, 0, 1};
            scenes.push_back({"transfer", request, {}, {}});
        }
        for (Scene& scene : scenes) {
            const std::string sum = "oer_" + scene.computation + "_seconds_sum";
            const double before = admin_metric(*server_, sum);
            scene.reference = render(*server_, scene.request);
            ASSERT_EQ(scene.reference.status, 200) << scene.reference.body;
            scene.duration = std::chrono::milliseconds(
                std::lround((admin_metric(*server_, sum) - before) * 1000.0));
            std::cerr << "a " << scene.computation << " took " << scene.duration.count() << " ms\n";
        }
        EXPECT_EQ(server_->stop(), 0);
    }

    start(root_.data());
    ASSERT_FALSE(HasFatalFailure());
    for (const std::string& query : queries) {
        acknowledged_.add_rig(upload_environment(*server_->client(), map, "image/x-exr", query));
    }
    acknowledged_.add_mesh(upload_mesh(*server_->client(), spheres, "model/gltf-binary"));
    ASSERT_FALSE(HasFatalFailure());
    // Under the preset, whose specular cube is made at start-up, and without occlusion: none of
    // the computations the kills aim at.
    acknowledge_frame(frame_request("default", mesh_id, false));
    std::map<std::string, int> killed_while_computing;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        const Scene& scene = scenes[i];
        const double moment = kMoments[i % std::size(kMoments)];
        SCOPED_TRACE(scene.computation + " killed at " + std::to_string(moment) + " of its time");
        Answer answer;
        std::thread frame([&] { answer = render(*server_, scene.request); });
        const bool computing = computation_started(*server_, scene.computation);
        std::this_thread::sleep_for(scene.duration * moment);
        const bool still_computing = admin_metric(*server_, "oer_computations_in_progress",
                                                  {{"computation", scene.computation}}) >= 1;
        server_->kill();
        frame.join();
        killed_while_computing[scene.computation] += still_computing;
        std::cerr << scene.computation << " killed at " << moment
                  << " of its time: while computing " << still_computing << ", answered "
                  << answer.status << "\n";
        ASSERT_TRUE(computing) << "the " << scene.computation << " never started";
        if (answer.status == 200) {
            acknowledged_.frames.push_back({scene.request, answer.etag, answer.body});
            EXPECT_TRUE(answer.body == scene.reference.body);
        }
        restart();
        ASSERT_FALSE(HasFatalFailure());
    }
    for (const char* computation : {"specular", "transfer"}) {
        EXPECT_GE(killed_while_computing[computation], 2) << computation;
    }
    // Drawn again after the kills: the frames of the server that was never killed, also after
    // one more restart (their cubes and transfers read back from the store).
    for (const Scene& scene : scenes) {
        const Answer again = render(*server_, scene.request);
        ASSERT_EQ(again.status, 200);
        EXPECT_EQ(again.etag, scene.reference.etag);
        EXPECT_TRUE(again.body == scene.reference.body)
            << "the frame differs from an uninterrupted one's: " << scene.request.dump();
        acknowledged_.frames.push_back({scene.request, again.etag, again.body});
    }
    server_->kill();
    restart();
    EXPECT_EQ(server_->stop(), 0);
}

// kill -9 mid-job (docs/jobs.md): the server started again on the folder finishes the job,
// storing exactly the frames the killed one had not (its stored-frames counter) and rewriting
// none of those it had (each file keeps its inode and time); a temporary file the killed frame
// write left is removed at the start (dated back as restart() does).
TEST_F(KillRestart, DuringABatchJob) {
    start(root_.data());
    ASSERT_FALSE(HasFatalFailure());
    constexpr int kViews = 60;
    const Json render = {{"environment", "default"},
                         {"objects", Json::array({{{"mesh", "default"}}})},
                         {"width", 64},
                         {"height", 48},
                         {"samples", 1},
                         {"format", "png"}};
    auto client = server_->client();
    const Json created = expect_conforms(
        "POST", "/v1/jobs",
        post_json(*client, "/v1/jobs", {{"turntable", {{"render", render}, {"views", kViews}}}}));
    ASSERT_TRUE(created.is_object());
    const std::string id = created.at("id");
    const auto status = [&] {
        return expect_conforms("GET", "/v1/jobs/{id}",
                               server_->client()->Get(("/v1/jobs/" + id).c_str()));
    };
    ASSERT_TRUE(eventually([&] { return status().at("done") >= 8; }, std::chrono::minutes(1)));
    server_->kill();

    const fs::path frames = root_.data() / "jobs" / id / "frames";
    std::map<std::string, std::pair<ino_t, std::int64_t>> stored;  // name -> inode, mtime (ns)
    const auto identity = [](const fs::path& path) {
        struct stat info {};
        EXPECT_EQ(::stat(path.c_str(), &info), 0) << path;
        return std::pair<ino_t, std::int64_t>(
            info.st_ino, std::int64_t(info.st_mtim.tv_sec) * 1'000'000'000 + info.st_mtim.tv_nsec);
    };
    for (const auto& entry : fs::directory_iterator(frames)) {
        if (!entry.path().filename().string().starts_with(".")) {
            stored[entry.path().filename().string()] = identity(entry.path());
        }
    }
    ASSERT_LT(stored.size(), std::size_t(kViews)) << "the job ended before the kill";
    set_untouched_for(temporary_files(root_.data()),
                      server::kAbandonedTemporaryAge + std::chrono::minutes(1));

    start(root_.data());
    ASSERT_FALSE(HasFatalFailure());
    ASSERT_TRUE(
        eventually([&] { return status().at("state") == "done"; }, std::chrono::minutes(2)));
    const double missing = double(kViews - int(stored.size()));
    eventually([&] { return admin_metric(*server_, "oer_job_frames_stored_total") >= missing; },
               std::chrono::seconds(5));
    EXPECT_EQ(admin_metric(*server_, "oer_job_frames_stored_total"), missing);
    for (const auto& [name, before] : stored) {
        EXPECT_EQ(identity(frames / name), before) << name << " was written again";
    }
    EXPECT_EQ(temporary_files(root_.data()), std::vector<fs::path>{});
}

TEST_F(KillRestart, DuringAMeshStoreWriteSlow) {
    start(root_.data());
    ASSERT_FALSE(HasFatalFailure());
    acknowledged_.add_mesh(upload_mesh(*server_->client(), box_glb({-0.5, 0, -0.5}, {0.5, 1, 0.5}),
                                       "model/gltf-binary"));
    ASSERT_FALSE(HasFatalFailure());
    acknowledge_frame(frame_request("default", acknowledged_.meshes.begin()->first, true));

    // The moments of a write (asset_store.cpp, write_atomically): its temporary file made, that
    // file written and closed, renamed to the entry (before the folder is flushed and the upload
    // answered).
    struct Moment {
        const char* name;
        std::uint32_t event;
        bool temporary;  // the event names the temporary file, else the entry
    };
    const Moment moments[] = {{"temporary file created", IN_CREATE, true},
                              {"temporary file closed", IN_CLOSE_WRITE, true},
                              {"entry renamed into place", IN_MOVED_TO, false}};
    unsigned seed = 0;
    for (const Moment& moment : moments) {
        SCOPED_TRACE(std::string("killed at: ") + moment.name);
        // Other bytes each time (another texture), so that none is stored already.
        const std::string mesh = noise_box_glb(++seed, kTextureSide);
        const std::string id = api::sha256_hex(mesh);
        FolderWatch watch(root_.data() / "meshes", moment.event);
        Answer answer;
        std::thread upload([&, client = server_->client()] {
            answer = answer_of(client->Post("/v1/meshes", mesh, "model/gltf-binary"));
        });
        const auto event =
            watch.wait(moment.temporary ? ".tmp-" + id : id, std::chrono::seconds(60));
        server_->kill();
        upload.join();
        ASSERT_TRUE(event) << "no such event within 60 s";
        const bool entry_there = fs::exists(root_.data() / "meshes" / (id + ".glb"));
        // Answered only after the rename (which the last moment waits for), if the answer
        // outran the kill.
        if (answer.status == 200 || answer.status == 201) {
            EXPECT_TRUE(entry_there) << "answered before its entry was in place";
            acknowledged_.add_mesh(Json::parse(answer.body));
        }
        const bool left = !temporary_files(root_.data()).empty();
        std::cerr << "killed on \"" << moment.name << "\" (" << mesh.size()
                  << " bytes): temporary file left " << left << ", entry in place " << entry_there
                  << ", answered " << answer.status << "\n";
        if (moment.event == IN_CREATE) {
            EXPECT_TRUE(left) << "the kill came after the write it was meant to interrupt";
        }
        restart();
        ASSERT_FALSE(HasFatalFailure());

        // Unknown, or there whole; uploaded again, the library's mesh of the bytes.
        const Json expected =
            api::mesh_to_json(load_mesh_memory(std::as_bytes(std::span(mesh.data(), mesh.size())),
                                               "mesh.glb", MeshFormat::Glb),
                              id, MeshFormat::Glb);
        auto client = server_->client();
        const auto lookup = client->Get(("/v1/meshes/" + id).c_str());
        ASSERT_TRUE(lookup);
        EXPECT_EQ(lookup->status, entry_there ? 200 : 404) << lookup->body;
        if (lookup->status == 200) {
            EXPECT_EQ(Json::parse(lookup->body), expected);
        }
        Json again = upload_mesh(*client, mesh, "model/gltf-binary");
        ASSERT_TRUE(again.is_object());
        EXPECT_EQ(again.at("cached"), entry_there);
        acknowledged_.add_mesh(again);
        again.erase("cached");
        EXPECT_EQ(again, expected);
        acknowledge_frame(frame_request("default", id, false));
    }
    EXPECT_EQ(server_->stop(), 0);
}
