// The occlusion switches and a scene's transfer in the service (TransferRegistry): the render
// request's occlusion and bounce in both forms, bad values answered as problems; a frame with
// occlusion on bakes its scene's transfer once (concurrent frames included), stores it by the
// scene's id, reads it back after a restart without baking, and bakes again, never serves, an
// entry that is damaged or belongs to another scene. The default scene's transfer is baked at
// start-up. Scenes here are small (a box, the default product), so that the bakes stay quick.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <latch>
#include <set>
#include <thread>

#include "http_support.hpp"
#include "json_schema.hpp"
#include "oer/server/asset_store.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

// The entries of the store's transfer folder, by file name.
std::set<std::string> transfer_entries(const TempRoot& root) {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(root.data() / "transfer")) {
        names.insert(entry.path().filename().string());
    }
    return names;
}

Json box_scene(const std::string& mesh, int width = 48) {
    return {{"environment", "default"},
            {"objects", {{{"mesh", mesh}}}},
            {"width", width},
            {"height", 32},
            {"format", "png"},
            {"samples", 1},
            {"shadows", {{"resolution", 256}}}};
}

httplib::Result render(httplib::Client& client, const Json& body) {
    return post_json(client, "/v1/render", body);
}

// The frame's bytes, checked to be a frame.
std::string frame_of(const httplib::Result& result) {
    EXPECT_TRUE(result) << "no answer";
    if (!result) {
        return {};
    }
    EXPECT_EQ(result->status, 200) << result->body;
    return result->body;
}

std::string upload_box(httplib::Client& client) {
    const Json mesh = upload_mesh(client, box_obj({-0.4, 0.0, -0.3}, {0.4, 0.6, 0.3}), "model/obj");
    EXPECT_TRUE(mesh.is_object());
    return mesh.is_object() ? mesh.at("id").get<std::string>() : std::string();
}

bool logged(const TestServer& server, const std::string& text) {
    for (const std::string& line : server.log_lines()) {
        if (line.find(text) != std::string::npos) {
            return true;
        }
    }
    return false;
}

// The one entry in `after` that `before` lacks.
std::string new_entry(const std::set<std::string>& before, const std::set<std::string>& after) {
    std::vector<std::string> added;
    for (const std::string& name : after) {
        if (!before.contains(name)) {
            added.push_back(name);
        }
    }
    EXPECT_EQ(added.size(), 1u);
    return added.empty() ? std::string() : added.front();
}

}  // namespace

TEST(Transfer, TheSwitchesReadInBothFormsAndBadValuesAreProblems) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.warm_default_scene = true;  // the default scene's transfer is baked at start-up
    TestServer server(config);
    auto client = server.client();
    const double at_start = transfers_computed(*client);
    Json body = box_scene("default");
    const auto by_default = render(*client, body);
    body["occlusion"] = false;
    body["bounce"] = "none";
    const auto switched = render(*client, body);
    const auto queried = client->Get(
        "/v1/render?environment=default&mesh=default&width=48&height=32&format=png&samples=1&"
        "shadow_resolution=256&occlusion=off&bounce=none");
    ASSERT_TRUE(by_default && switched && queried);
    ASSERT_EQ(switched->status, 200) << switched->body;
    ASSERT_EQ(queried->status, 200) << queried->body;
    expect_conforms("POST", "/v1/render", switched);
    EXPECT_EQ(switched->get_header_value("ETag"), queried->get_header_value("ETag"));
    EXPECT_EQ(switched->body, queried->body);
    EXPECT_NE(switched->get_header_value("ETag"), by_default->get_header_value("ETag"));
    // The defaults spelled out are the same request.
    body["occlusion"] = true;
    body["bounce"] = "one";
    const auto spelled = render(*client, body);
    ASSERT_TRUE(spelled);
    EXPECT_EQ(spelled->get_header_value("ETag"), by_default->get_header_value("ETag"));

    for (const auto& [member, value] : {std::pair<std::string, Json>{"occlusion", "off"},
                                        std::pair<std::string, Json>{"occlusion", 1},
                                        std::pair<std::string, Json>{"bounce", "two"},
                                        std::pair<std::string, Json>{"bounce", true}}) {
        Json bad = box_scene("default");
        bad[member] = value;
        expect_problem("POST", "/v1/render", render(*client, bad), ProblemKind::InvalidParameter,
                       member);
    }
    for (const auto& [parameter, value] : {std::pair<std::string, std::string>{"occlusion", "true"},
                                           std::pair<std::string, std::string>{"bounce", "One"}}) {
        const std::string path =
            "/v1/render?environment=default&mesh=default&" + parameter + "=" + value;
        expect_problem("GET", "/v1/render", client->Get(path.c_str()),
                       ProblemKind::InvalidParameter, parameter);
    }
    EXPECT_EQ(transfers_computed(*client), at_start)
        << "the default scene's transfer is baked at start-up, and occlusion off needs none";
}

// Each switch changes the frame: the GL renderer honours FrameRequest::occlusion, ::bounce and
// ::transfer.
TEST(Transfer, TheSwitchesChangeTheFrame) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    Json body = box_scene("default");
    const std::string occluded = frame_of(render(*client, body));
    body["occlusion"] = false;
    const std::string unoccluded = frame_of(render(*client, body));
    body["occlusion"] = true;
    body["bounce"] = "none";
    const std::string direct = frame_of(render(*client, body));
    EXPECT_TRUE(occluded != unoccluded) << "occlusion off draws the same frame";
    EXPECT_TRUE(occluded != direct) << "bounce none draws the same frame";
}

TEST(Transfer, AFrameWithOcclusionBakesItsSceneOnce) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.warm_default_scene = true;  // the default scene's transfer is baked at start-up
    TestServer server(config);
    auto client = server.client();
    // The default scene's transfer is there from start-up: the default request bakes nothing.
    const double at_start = transfers_computed(*client);
    EXPECT_EQ(at_start, 1.0);
    const std::set<std::string> start_entries = transfer_entries(root);
    EXPECT_EQ(start_entries.size(), 1u);
    EXPECT_TRUE(logged(server, "transfers: transfer "));
    frame_of(client->Get("/v1/render?environment=default&mesh=default&width=40&height=30"));
    EXPECT_EQ(transfers_computed(*client), at_start);

    // The upload bakes its standard scene's transfer (the box alone, on the ground) ahead, then
    // the same scene's without the floor; its first frame reads the first and bakes nothing.
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    EXPECT_EQ(wait_for_preparation(*client, mesh), "ready");
    const Metrics before = scrape(*client);
    EXPECT_EQ(before.sum("oer_transfers_computed_total") - at_start, 2.0);
    const std::set<std::string> prepared_entries = transfer_entries(root);
    EXPECT_EQ(prepared_entries.size(), 3u);
    for (const std::string& entry : prepared_entries) {
        if (start_entries.contains(entry)) {
            continue;
        }
        ASSERT_EQ(entry.size(), 64u + std::string(".sealed").size()) << entry;
        EXPECT_TRUE(logged(
            server, "transfers: transfer " + entry.substr(0, 64) + " of 1 object(s) computed in "));
    }
    frame_of(render(*client, box_scene(mesh)));
    const Metrics baked = scrape(*client);
    EXPECT_EQ(baked.sum("oer_transfers_computed_total") - at_start, 2.0);
    EXPECT_EQ(baked.sum("oer_transfer_seconds_count") - before.sum("oer_transfer_seconds_count"),
              0.0);

    // Another frame of the same scene (another size, so not a cached frame): from memory.
    frame_of(render(*client, box_scene(mesh, 64)));
    const Metrics again = scrape(*client);
    EXPECT_EQ(again.sum("oer_transfers_computed_total") - at_start, 2.0);
    EXPECT_GE(again.sum("oer_cache_hits_total", {{"cache", "transfer"}}) -
                  baked.sum("oer_cache_hits_total", {{"cache", "transfer"}}),
              1.0);
    // Occlusion off needs no transfer; another bounce, or another transform, is another scene.
    Json off = box_scene(mesh);
    off["occlusion"] = false;
    frame_of(render(*client, off));
    EXPECT_EQ(transfers_computed(*client) - at_start, 2.0);
    Json direct = box_scene(mesh);
    direct["bounce"] = "none";
    frame_of(render(*client, direct));
    EXPECT_EQ(transfers_computed(*client) - at_start, 3.0);
    Json moved = box_scene(mesh);
    moved["objects"][0]["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.25, 0, 0, 1};
    frame_of(render(*client, moved));
    EXPECT_EQ(transfers_computed(*client) - at_start, 4.0);
    EXPECT_EQ(transfer_entries(root).size(), 5u);
}

// What invalidates what (docs/design.md section 9): a colour only weighs the bounce's reflector
// slots, so it bakes nothing: every colour takes the transfer of the upload's bake from memory,
// and is still another frame. The floor's toggle is another scene, which the upload baked
// ahead after the first frames' (GET .../preparation's without_floor): it bakes nothing either.
TEST(Transfer, AColourChangeOrTheFloorsToggleBakesNothing) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    EXPECT_EQ(wait_for_preparation(*client, mesh), "ready");
    const Json preparation =
        Json::parse(client->Get(("/v1/meshes/" + mesh + "/preparation").c_str())->body);
    EXPECT_EQ(preparation.at("without_floor").at("state"), "ready");
    EXPECT_EQ(preparation.at("without_floor").at("progress"), 1.0);
    const double prepared = transfers_computed(*client);
    const std::string plain = frame_of(render(*client, box_scene(mesh)));
    const Metrics before = scrape(*client);

    Json red = box_scene(mesh);
    red["objects"][0]["base_color"] = {0.8, 0.05, 0.05};
    const std::string red_frame = frame_of(render(*client, red));
    EXPECT_NE(red_frame, plain);
    Json green = red;
    green["objects"][0]["base_color"] = {0.05, 0.8, 0.05};
    EXPECT_NE(frame_of(render(*client, green)), red_frame);
    const Metrics after = scrape(*client);
    EXPECT_EQ(after.sum("oer_transfers_computed_total"), prepared);
    EXPECT_EQ(after.sum("oer_transfer_seconds_count"), before.sum("oer_transfer_seconds_count"));
    EXPECT_EQ(after.sum("oer_cache_hits_total", {{"cache", "transfer"}}) -
                  before.sum("oer_cache_hits_total", {{"cache", "transfer"}}),
              2.0);

    Json no_floor = red;
    no_floor["ground"] = false;
    EXPECT_NE(frame_of(render(*client, no_floor)), red_frame);
    no_floor["objects"][0]["base_color"] = {0.05, 0.05, 0.8};
    frame_of(render(*client, no_floor));
    frame_of(render(*client, green));
    EXPECT_EQ(transfers_computed(*client), prepared);
    EXPECT_EQ(scrape(*client).sum("oer_transfer_seconds_count"),
              before.sum("oer_transfer_seconds_count"));
}

TEST(Transfer, ConcurrentFramesBakeTheSceneOnce) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    const double at_start = transfers_computed(*client);
    constexpr int kClients = 4;
    std::latch ready(kClients);
    std::vector<std::thread> threads;
    std::vector<int> statuses(kClients, 0);
    for (int i = 0; i < kClients; ++i) {
        threads.emplace_back([&, i] {
            auto own = server.client();
            ready.arrive_and_wait();
            const auto result = render(*own, box_scene(mesh, 40 + 8 * i));
            statuses[std::size_t(i)] = result ? result->status : -1;
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    for (const int status : statuses) {
        EXPECT_EQ(status, 200);
    }
    // The four frames' scene once, however they met the upload's bake of it; then the floorless
    // scene, baked ahead.
    EXPECT_EQ(wait_for_preparation(*client, mesh), "ready");
    EXPECT_EQ(transfers_computed(*client) - at_start, 2.0);
}

TEST(Transfer, AnUploadedMeshsTransferSurvivesARestartWithoutRecomputation) {
    TempRoot root;
    std::string mesh, first_frame;
    std::set<std::string> entries;
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        mesh = upload_box(*client);
        ASSERT_FALSE(mesh.empty());
        first_frame = frame_of(render(*client, box_scene(mesh)));
        wait_for_preparation(*client, mesh);
        entries = transfer_entries(root);
    }
    TestServer second(test_config(root.data()));
    auto client = second.client();
    // The default scene's too, at start-up.
    EXPECT_EQ(transfers_computed(*client), 0.0) << "baked again after a restart";
    const std::string frame = frame_of(render(*client, box_scene(mesh)));
    EXPECT_TRUE(frame == first_frame) << "the same request renders differently after a restart";
    EXPECT_EQ(transfers_computed(*client), 0.0) << "baked again after a restart";
    EXPECT_EQ(transfer_entries(root), entries);
}

namespace {

// box_scene with the box moved x along the x axis: another scene, another transfer of the same
// size.
Json moved_box_scene(const std::string& mesh, double x) {
    Json scene = box_scene(mesh);
    scene["objects"][0]["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, 0, 0, 1};
    return scene;
}

double stored_transfer_bytes(httplib::Client& client) {
    return scrape(client).sum("oer_transfer_store_bytes");
}

}  // namespace

TEST(Transfer, ADamagedEntryIsBakedAgainNeverServed) {
    TempRoot root;
    std::string mesh, first_frame, entry;
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        mesh = upload_box(*client);
        ASSERT_FALSE(mesh.empty());
        wait_for_preparation(*client, mesh);
        const std::set<std::string> before = transfer_entries(root);
        first_frame = frame_of(render(*client, moved_box_scene(mesh, 0.5)));
        entry = new_entry(before, transfer_entries(root));
        ASSERT_FALSE(entry.empty());
    }
    const std::filesystem::path path = root.data() / "transfer" / entry;
    const std::string whole = [&path] {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    ASSERT_GT(whole.size(), 200u);
    {
        // Flip bytes in the payload, past the seal's header line.
        std::string damaged = whole;
        for (std::size_t i = whole.size() / 2; i < whole.size() / 2 + 8; ++i) {
            damaged[i] = char(~damaged[i]);
        }
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out << damaged;
    }
    TestServer second(test_config(root.data()));
    auto client = second.client();
    const std::string frame = frame_of(render(*client, moved_box_scene(mesh, 0.5)));
    EXPECT_EQ(transfers_computed(*client), 1.0);
    EXPECT_TRUE(frame == first_frame) << "the frame differs from the one of the undamaged transfer";
    EXPECT_TRUE(logged(second, "transfers: transfer " + entry.substr(0, 64) +
                                   " of 1 object(s) "
                                   "computed in "));
    // The same vectors again (the bake is deterministic); only the bake's time differs.
    EXPECT_EQ(std::filesystem::file_size(path), whole.size()) << "not stored again whole";
}

// A sound entry of another scene under this scene's id (a bake that changed without its
// version) has receivers that are not this scene's vertices: dropped and baked again.
TEST(Transfer, AnEntryOfAnotherSceneIsBakedAgainNeverServed) {
    TempRoot root;
    std::string mesh, first_frame, box_entry, default_entry;
    {
        server::ServiceConfig warm = test_config(root.data());
        warm.warm_default_scene = true;  // the default scene's entry is the other scene's
        TestServer first(warm);
        auto client = first.client();
        const std::set<std::string> at_start = transfer_entries(root);
        ASSERT_EQ(at_start.size(), 1u);
        default_entry = *at_start.begin();
        mesh = upload_box(*client);
        ASSERT_FALSE(mesh.empty());
        wait_for_preparation(*client, mesh);
        const std::set<std::string> prepared = transfer_entries(root);
        first_frame = frame_of(render(*client, moved_box_scene(mesh, 0.5)));
        box_entry = new_entry(prepared, transfer_entries(root));
        ASSERT_FALSE(box_entry.empty());
    }
    std::filesystem::copy_file(root.data() / "transfer" / default_entry,
                               root.data() / "transfer" / box_entry,
                               std::filesystem::copy_options::overwrite_existing);
    TestServer second(test_config(root.data()));
    auto client = second.client();
    const std::string frame = frame_of(render(*client, moved_box_scene(mesh, 0.5)));
    EXPECT_EQ(transfers_computed(*client), 1.0);
    EXPECT_TRUE(frame == first_frame);
    EXPECT_TRUE(logged(second, "does not fit its scene"));
}

// The stored transfers stay within --transfer-store-bytes: past it the least recently used go
// (from the store and from memory), and are baked again when a frame needs one; those used
// since are kept. The order survives a restart (by when each was written).
TEST(TransferStore, OverItsQuotaTheLeastRecentlyUsedAreRemoved) {
    TempRoot root;
    // The built-in mesh, moved: no upload, whose bakes ahead would be stored too.
    const std::string mesh = "default";
    double default_bytes = 0.0, moved_bytes = 0.0;
    {
        server::ServiceConfig warm = test_config(root.data());
        warm.warm_default_scene = true;  // the default scene's transfer is stored at start-up
        TestServer first(warm);
        auto client = first.client();
        default_bytes = stored_transfer_bytes(*client);
        ASSERT_GT(default_bytes, 0.0) << "the default scene's transfer is stored at start-up";
        frame_of(render(*client, moved_box_scene(mesh, 0.5)));  // A
        moved_bytes = stored_transfer_bytes(*client) - default_bytes;
        ASSERT_GT(moved_bytes, 0.0);
    }
    // Room for the default scene's and two moved ones', not three.
    server::ServiceConfig config = test_config(root.data());
    config.transfer_store_bytes = std::uint64_t(default_bytes + 2.5 * moved_bytes);
    config.frame_cache_bytes = 0;  // every frame uses its transfer
    config.warm_default_scene = true;
    TestServer second(config);
    auto client = second.client();
    EXPECT_EQ(stored_transfer_bytes(*client), default_bytes + moved_bytes);
    // Uses, oldest first: the default scene's and A's as written in the first run; then the
    // default scene's (its start-up frame), B, A, the default scene's again; then C overflows
    // the store. The least recently used is B, although the default scene's was written first.
    frame_of(render(*client, box_scene("default")));
    EXPECT_EQ(transfers_computed(*client), 0.0) << "the default scene's transfer was not stored";
    frame_of(render(*client, moved_box_scene(mesh, 1.0)));  // B, baked
    frame_of(render(*client, moved_box_scene(mesh, 0.5)));  // A, read back
    frame_of(render(*client, box_scene("default")));
    EXPECT_EQ(transfers_computed(*client), 1.0);
    frame_of(render(*client, moved_box_scene(mesh, 2.0)));  // C, baked: over the quota
    EXPECT_EQ(transfers_computed(*client), 2.0);
    EXPECT_EQ(scrape(*client).sum("oer_transfers_evicted_total"), 1.0);
    EXPECT_LE(stored_transfer_bytes(*client), double(config.transfer_store_bytes));
    EXPECT_TRUE(logged(second, "over the " + std::to_string(config.transfer_store_bytes) +
                                   " of --transfer-store-bytes"));
    // C, A and the default scene's are kept: rendered without a bake.
    frame_of(render(*client, moved_box_scene(mesh, 2.0)));
    frame_of(render(*client, moved_box_scene(mesh, 0.5)));
    frame_of(render(*client, box_scene("default")));
    EXPECT_EQ(transfers_computed(*client), 2.0) << "a transfer used since was removed";
    // B, the least recently used, went (from the store and from memory): baked again.
    frame_of(render(*client, moved_box_scene(mesh, 1.0)));
    EXPECT_EQ(transfers_computed(*client), 3.0) << "the least recently used was not removed";
}

// Deleting a mesh deletes the stored transfers of the scenes that hold it, and only those.
TEST(TransferStore, DeletingAMeshDeletesItsScenesTransfers) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::set<std::string> at_start = transfer_entries(root);
    const double default_bytes = stored_transfer_bytes(*client);
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    // Its two scenes baked ahead (on the floor and without it), two more.
    EXPECT_EQ(wait_for_preparation(*client, mesh), "ready");
    frame_of(render(*client, moved_box_scene(mesh, 0.5)));
    frame_of(render(*client, moved_box_scene(mesh, 1.0)));
    EXPECT_EQ(transfer_entries(root).size(), at_start.size() + 4);
    const auto deleted = client->Delete(("/v1/meshes/" + mesh).c_str());
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->status, 204);
    EXPECT_EQ(transfer_entries(root), at_start) << "the mesh's scenes' transfers are still stored";
    EXPECT_TRUE(std::filesystem::is_empty(root.data() / "transfer-meshes") ||
                std::distance(std::filesystem::directory_iterator(root.data() / "transfer-meshes"),
                              std::filesystem::directory_iterator()) == long(at_start.size()));
    EXPECT_EQ(stored_transfer_bytes(*client), default_bytes);
    EXPECT_TRUE(logged(server, "removed 4 stored transfer(s) of scenes holding mesh " + mesh));
}

// A stored transfer without the record of its meshes (stored by an older version) could never
// go with its meshes: it is removed at start-up.
TEST(TransferStore, ATransferWithoutItsRecordIsRemovedAtStartUp) {
    TempRoot root;
    const std::string orphan(64, 'a');
    {
        server::AssetStore store(root.data());
        store.put_derived(server::DerivedKind::Transfer, orphan, "a transfer of an older version");
    }
    TestServer server(test_config(root.data()));
    EXPECT_FALSE(std::filesystem::exists(root.data() / "transfer" / (orphan + ".sealed")));
    EXPECT_TRUE(logged(server, "stored transfer " + orphan + " has no record of its meshes"));
}

// An upload bakes ahead the transfer its first frames need (the mesh alone, untransformed, on
// the ground): the first frame finds it ready; GET .../preparation says so.
TEST(TransferPreparation, AnUploadBakesItsFirstFramesTransferAhead) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const double at_start = transfers_computed(*client);  // the default scene's
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    const std::string path = "/v1/meshes/" + mesh + "/preparation";
    EXPECT_EQ(wait_for_preparation(*client, mesh), "ready");
    const Json preparation =
        expect_conforms("GET", "/v1/meshes/{id}/preparation", client->Get(path.c_str()));
    EXPECT_EQ(preparation.value("progress", 0.0), 1.0);
    EXPECT_EQ(preparation.at("without_floor").value("state", ""), "ready");
    EXPECT_EQ(transfers_computed(*client), at_start + 2.0);
    frame_of(render(*client, box_scene(mesh)));
    Json without_floor = box_scene(mesh);
    without_floor["ground"] = false;
    frame_of(render(*client, without_floor));
    EXPECT_EQ(transfers_computed(*client), at_start + 2.0)
        << "a first frame, on the floor or not, baked its transfer again";
    expect_problem("GET", "/v1/meshes/{id}/preparation",
                   client->Get(("/v1/meshes/" + std::string(64, 'f') + "/preparation").c_str()),
                   ProblemKind::UnknownId);
}

namespace {

bool under_way(const Json& scene) {
    const std::string state = scene.value("state", "");
    return state == "queued" || state == "baking";
}

// A preparation's event stream, held to what GET .../preparation/events promises: each event a
// MeshPreparation, each scene's progress never going back, consecutive events differing in a
// state, a whole percent or a whole second of an estimate (not an event per look), every event
// but the last with a bake under way, and the end of the stream after the last.
void expect_preparation_stream(const EventStream& stream) {
    EXPECT_EQ(stream.status, 200);
    EXPECT_EQ(stream.content_type, "text/event-stream");
    EXPECT_TRUE(stream.ended) << "the stream did not end";
    ASSERT_FALSE(stream.events.empty());
    const auto change = [](const Json& scene) {
        const Json& left = scene.at("seconds_left");
        return scene.at("state").dump() + " " +
               std::to_string(int(std::floor(100.0 * scene.at("progress").get<double>()))) + " " +
               (left.is_null() ? "-" : std::to_string(std::lround(left.get<double>())));
    };
    for (std::size_t i = 0; i < stream.events.size(); ++i) {
        const Json& event = stream.events[i];
        EXPECT_EQ(
            oer::testing::openapi_schema_errors(event, "#/components/schemas/MeshPreparation"),
            std::vector<std::string>{})
            << event.dump();
        const bool last = i + 1 == stream.events.size();
        EXPECT_EQ(under_way(event) || under_way(event.at("without_floor")), !last) << event.dump();
        if (i == 0) {
            continue;
        }
        const Json& before = stream.events[i - 1];
        for (const char* scene : {"", "without_floor"}) {
            const Json& now = *scene ? event.at(scene) : event;
            const Json& then = *scene ? before.at(scene) : before;
            EXPECT_GE(now.at("progress").get<double>(), then.at("progress").get<double>())
                << "progress went back: " << then.dump() << " then " << now.dump();
        }
        EXPECT_TRUE(change(event) != change(before) ||
                    change(event.at("without_floor")) != change(before.at("without_floor")))
            << "an event without a change: " << before.dump() << " then " << event.dump();
    }
}

}  // namespace

// The preparation as server-sent events: followed from the upload to the end of both bakes;
// followed again once prepared, one event (the same as GET .../preparation) and the end; 404
// for a mesh that is not there.
TEST(TransferPreparation, ItsEventStreamFollowsTheBakesToTheirEnd) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    const std::string path = "/v1/meshes/" + mesh + "/preparation";
    const EventStream stream = follow_events(*client, path + "/events");
    expect_preparation_stream(stream);
    ASSERT_FALSE(stream.events.empty());
    EXPECT_EQ(stream.events.back().at("state"), "ready");
    EXPECT_EQ(stream.events.back().at("without_floor").at("state"), "ready");
    std::printf("[ preparation ] %zu events\n", stream.events.size());

    const EventStream prepared = follow_events(*client, path + "/events");
    expect_preparation_stream(prepared);
    ASSERT_EQ(prepared.events.size(), 1u);
    EXPECT_EQ(prepared.events[0],
              expect_conforms("GET", "/v1/meshes/{id}/preparation", client->Get(path.c_str())));

    expect_problem(
        "GET", "/v1/meshes/{id}/preparation/events",
        client->Get(("/v1/meshes/" + std::string(64, 'f') + "/preparation/events").c_str()),
        ProblemKind::UnknownId);
}

// While the bake runs, the preparation reports its progress and the time left, polled and, at
// the same time, as its event stream: events partway too, each with its estimate (and, as
// every stream, each differing from the one before: expect_preparation_stream).
TEST(TransferPreparation, ABakeReportsItsProgressSlow) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.transfer_ray_budget = 1'000'000'000;  // 1024 rays a point: a bake of about a second
    TestServer server(config);
    auto client = server.client();
    const Json uploaded = upload_mesh(*client, grid_obj(150), "model/obj");
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
    const std::string path = "/v1/meshes/" + uploaded.at("id").get<std::string>() + "/preparation";
    EventStream stream;
    std::thread follower([&] { stream = follow_events(*server.client(), path + "/events"); });
    std::vector<Json> seen;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline &&
           (seen.empty() || seen.back().value("state", "") != "ready")) {
        seen.push_back(
            expect_conforms("GET", "/v1/meshes/{id}/preparation", client->Get(path.c_str())));
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    follower.join();
    ASSERT_EQ(seen.back().value("state", ""), "ready");
    bool partway = false;
    double last = 0.0;
    for (const Json& step : seen) {
        const double progress = step.value("progress", 0.0);
        EXPECT_GE(progress, last) << "progress went back";
        last = progress;
        if (step.value("state", "") == "baking" && progress > 0.0 && progress < 1.0) {
            partway = true;
            EXPECT_TRUE(step["seconds_left"].is_number()) << step.dump();
        }
    }
    EXPECT_TRUE(partway) << "no progress was seen between 0 and 1 in " << seen.size() << " answers";

    expect_preparation_stream(stream);
    ASSERT_FALSE(stream.events.empty());
    EXPECT_EQ(stream.events.back().at("state"), "ready");
    std::size_t streamed_partway = 0;
    for (const Json& event : stream.events) {
        for (const Json* scene : {&event, &event.at("without_floor")}) {
            const double progress = scene->at("progress").get<double>();
            if (scene->at("state") == "baking" && progress > 0.0 && progress < 1.0) {
                ++streamed_partway;
                EXPECT_TRUE(scene->at("seconds_left").is_number()) << event.dump();
            }
        }
    }
    EXPECT_GE(streamed_partway, 2u) << "too few events partway through the bakes";
    std::printf("[ preparation ] %zu answers polled, %zu events streamed, %zu of them partway\n",
                seen.size(), stream.events.size(), streamed_partway);
}

namespace {

// A service whose bakes take long enough to see frames drawn meanwhile: 1024 rays a point, so
// that the box of upload_box on the ground (4,120 points) bakes for about half a second to a
// second, with an occlusion that shows (its contact shadow).
server::ServiceConfig slow_bake_config(const TempRoot& root) {
    server::ServiceConfig config = test_config(root.data());
    config.transfer_ray_budget = 1'000'000'000;
    return config;
}

// A small frame of the box, with occlusion (the default).
std::string box_frame(const std::string& mesh) {
    return "/v1/render?environment=default&mesh=" + mesh +
           "&width=64&height=64&samples=1&format=png&yaw=40";
}

}  // namespace

// A client that prefers not to wait (Prefer: wait=1, RFC 7240) gets, while its scene's
// transfer is baked, the frame drawn without it at once: marked preliminary, kept by nobody,
// without an ETag, the same pixels as the frame with occlusion off. Asked again once the bake
// is done, the same request gets the whole frame, the one a client without the preference gets.
TEST(TransferPreliminarySlow, AFrameThatPrefersNotToWaitIsDrawnWithoutItsTransferMeanwhile) {
    TempRoot root;
    server::ServiceConfig config = slow_bake_config(root);
    config.frame_cache_bytes = 0;
    TestServer server(config);
    auto client = server.client();
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    const std::string frame = box_frame(mesh);
    const httplib::Headers prefer{{"Prefer", "wait=1"}};
    const auto start = std::chrono::steady_clock::now();
    const auto preliminary = client->Get(frame.c_str(), prefer);
    const double preliminary_seconds = seconds_since(start);
    ASSERT_TRUE(preliminary);
    expect_conforms("GET", "/v1/render", preliminary);
    ASSERT_EQ(preliminary->status, 200) << preliminary->body;
    EXPECT_EQ(preliminary->get_header_value("X-Oer-Preliminary"), "transfer");
    EXPECT_EQ(preliminary->get_header_value("Preference-Applied"), "wait=1");
    EXPECT_EQ(preliminary->get_header_value("Cache-Control"), "no-store");
    EXPECT_FALSE(preliminary->has_header("ETag"));
    const auto unoccluded = client->Get((frame + "&occlusion=off").c_str());
    ASSERT_TRUE(unoccluded);
    EXPECT_TRUE(preliminary->body == unoccluded->body)
        << "the preliminary frame is not the frame with occlusion off";
    // The bake goes on without anyone waiting; then the whole frame.
    const std::string path = "/v1/meshes/" + mesh + "/preparation";
    ASSERT_TRUE(eventually(
        [&] {
            const auto answer = client->Get(path.c_str());
            return answer && Json::parse(answer->body).value("state", "") == "ready";
        },
        std::chrono::seconds(120)));
    const auto whole = client->Get(frame.c_str(), prefer);
    const auto plain = client->Get(frame.c_str());
    ASSERT_TRUE(whole && plain);
    EXPECT_FALSE(whole->has_header("X-Oer-Preliminary"));
    EXPECT_EQ(whole->get_header_value("ETag"), plain->get_header_value("ETag"));
    EXPECT_TRUE(whole->body == plain->body);
    EXPECT_FALSE(whole->body == preliminary->body) << "the occlusion changed nothing";
    std::printf("preliminary frame in %.0f ms while its transfer was baked\n",
                preliminary_seconds * 1e3);
}

// Asked again while its transfer bakes (the viewer asks every 0.5 s), the preliminary frame is
// served from memory, not drawn again: the bake keeps the cores.
TEST(TransferPreliminarySlow, APreliminaryFrameAskedAgainIsServedFromMemory) {
    TempRoot root;
    TestServer server(slow_bake_config(root));
    auto client = server.client();
    const std::string mesh = upload_box(*client);
    ASSERT_FALSE(mesh.empty());
    const std::string frame = box_frame(mesh);
    const httplib::Headers prefer{{"Prefer", "wait=0"}};
    const auto first = client->Get(frame.c_str(), prefer);
    const auto again = client->Get(frame.c_str(), prefer);
    ASSERT_TRUE(first && again);
    ASSERT_EQ(first->get_header_value("X-Oer-Preliminary"), "transfer") << "baked too soon";
    ASSERT_EQ(again->get_header_value("X-Oer-Preliminary"), "transfer") << "baked too soon";
    EXPECT_EQ(first->get_header_value("X-Oer-Cache"), "miss");
    EXPECT_EQ(again->get_header_value("X-Oer-Cache"), "hit");
    EXPECT_TRUE(again->body == first->body);
    EXPECT_EQ(wait_for_preparation(*client, mesh), "ready");
    const auto whole = client->Get(frame.c_str(), prefer);
    ASSERT_TRUE(whole);
    EXPECT_FALSE(whole->has_header("X-Oer-Preliminary"));
    EXPECT_EQ(whole->get_header_value("X-Oer-Cache"), "miss");
    EXPECT_FALSE(whole->body == first->body);
}
