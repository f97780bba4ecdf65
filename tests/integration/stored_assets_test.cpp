// Listing and deleting uploaded environments and meshes on a real server: pages in id order
// with each entry's size, format, time and URL; parameters checked; deletion answered 204 and
// then 404 everywhere the id is named, cached frames and previews included, with nothing of the
// entry left in the data folder; the presets refused; the API key needed to delete; and a
// deletion during a render of the same assets.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <optional>
#include <set>
#include <thread>

#include "http_support.hpp"
#include "oer/api/content_id.hpp"
#include "openapi_spec.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

// Seconds since the epoch of an RFC 3339 time in UTC to the second ("2026-12-01T09:30:00Z"),
// or -1 when it is not one.
long long epoch_seconds(const std::string& text) {
    std::tm utc{};
    const char* end = strptime(text.c_str(), "%Y-%m-%dT%H:%M:%SZ", &utc);
    return end && *end == '\0' ? (long long)timegm(&utc) : -1;
}

long long now_seconds() {
    return std::chrono::duration_cast<std::chrono::seconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

// Every page of a listing from its first, each held to the spec: the entries in the order
// served, and the number of pages.
std::pair<Json, int> walk(httplib::Client& client, const std::string& collection, int limit) {
    Json entries = Json::array();
    std::string next = "/v1/" + collection + "?limit=" + std::to_string(limit);
    int pages = 0;
    while (!next.empty() && pages < 100) {
        const Json page = expect_conforms("GET", "/v1/" + collection, client.Get(next.c_str()));
        if (!page.is_object()) {
            break;
        }
        ++pages;
        EXPECT_LE(page.at(collection).size(), std::size_t(limit));
        for (const Json& entry : page.at(collection)) {
            entries.push_back(entry);
        }
        next = page.value("next", "");
    }
    return {entries, pages};
}

std::vector<std::string> ids_of(const Json& entries) {
    std::vector<std::string> ids;
    for (const Json& entry : entries) {
        ids.push_back(entry.at("id"));
    }
    return ids;
}

// The files under the data folder whose name holds text.
std::vector<std::string> files_naming(const std::filesystem::path& data, const std::string& text) {
    std::vector<std::string> found;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(data)) {
        if (entry.path().filename().string().find(text) != std::string::npos) {
            found.push_back(entry.path().string());
        }
    }
    return found;
}

Json frame_request(const std::string& environment, const std::string& mesh) {
    return {{"environment", environment},
            {"objects", {{{"mesh", mesh}}}},
            {"width", 48},
            {"height", 32},
            {"format", "png"},
            {"samples", 1},
            {"shadows", {{"resolution", 256}}}};
}

// The methods of an Allow header, as a set.
std::set<std::string> allowed(const std::string& header) {
    std::set<std::string> methods;
    std::size_t start = 0;
    while (start < header.size()) {
        const std::size_t end = std::min(header.find(',', start), header.size());
        methods.insert(oer::testing::trim(header.substr(start, end - start)));
        start = end + 1;
    }
    return methods;
}

// One server for the tests that need no data folder of their own: each uploads its own assets
// and looks at those only.
class StoredAssetsShared : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        root_ = new TempRoot();
        server::ServiceConfig config = test_config(root_->data());
        config.cors_origins = {"https://shop.example"};
        server_ = new TestServer(config);
    }
    static void TearDownTestSuite() {
        delete server_;
        delete root_;
        server_ = nullptr;
        root_ = nullptr;
    }
    void SetUp() override { client_ = server_->client(); }

    static std::filesystem::path data() { return root_->data(); }

    static inline TempRoot* root_ = nullptr;
    static inline TestServer* server_ = nullptr;
    std::unique_ptr<httplib::Client> client_;
};

}  // namespace

TEST(StoredAssets, ListingsGiveEveryUploadOnceInIdOrderAPageAtATime) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const long long start = now_seconds();
    // Two maps (one as Radiance HDR), one of them under two sets of options: three rigs.
    const std::string exr = exr_bytes(three_disc_environment(64, 32).image);
    const std::string hdr = hdr_bytes(three_disc_environment(32, 16).image);
    std::map<std::string, std::pair<std::string, std::string>> map_of;  // rig -> bytes, type
    for (const auto& [bytes, type, query] :
         {std::tuple{exr, "image/x-exr", "light_count=1"},
          std::tuple{exr, "image/x-exr", "light_count=2"},
          std::tuple{hdr, "image/vnd.radiance", "light_count=1"}}) {
        const Json rig = upload_environment(*client, bytes, type, query);
        ASSERT_TRUE(rig.is_object());
        map_of[rig.at("id")] = {bytes, type};
    }
    std::map<std::string, std::pair<std::string, std::string>> mesh_of;  // id -> bytes, format
    for (int i = 1; i <= 3; ++i) {
        const bool glb = i == 2;
        const std::string bytes =
            glb ? box_glb({0, 0, 0}, {1, 1, 1}) : box_obj({0, 0, 0}, {i, 1, 1});
        const Json mesh = upload_mesh(*client, bytes, glb ? "model/gltf-binary" : "model/obj");
        ASSERT_TRUE(mesh.is_object());
        mesh_of[mesh.at("id")] = {bytes, glb ? "glb" : "obj"};
    }
    const long long end = now_seconds();

    for (const int limit : {100, 2, 1}) {
        SCOPED_TRACE("limit " + std::to_string(limit));
        const auto [environments, environment_pages] = walk(*client, "environments", limit);
        std::vector<std::string> expected;
        for (const auto& [id, map] : map_of) {
            expected.push_back(id);
        }
        EXPECT_EQ(ids_of(environments), expected) << "each once, in ascending order of id";
        EXPECT_EQ(environment_pages, (3 + limit - 1) / limit);
        for (const Json& entry : environments) {
            const std::string id = entry.at("id");
            const auto& [bytes, type] = map_of.at(id);
            EXPECT_EQ(entry.at("url"), "/v1/environments/" + id);
            EXPECT_EQ(entry.at("source"), api::sha256_hex(bytes));
            EXPECT_EQ(entry.at("media_type"), type);
            EXPECT_EQ(entry.at("bytes"), bytes.size());
            const long long created = epoch_seconds(entry.at("created"));
            EXPECT_GE(created, start - 1) << entry.at("created");
            EXPECT_LE(created, end + 1) << entry.at("created");
            const auto rig = client->Get(entry.at("url").get<std::string>().c_str());
            ASSERT_TRUE(rig);
            EXPECT_EQ(rig->status, 200) << "the entry's url answers";
        }

        const auto [meshes, mesh_pages] = walk(*client, "meshes", limit);
        expected.clear();
        for (const auto& [id, mesh] : mesh_of) {
            expected.push_back(id);
        }
        EXPECT_EQ(ids_of(meshes), expected);
        EXPECT_EQ(mesh_pages, (3 + limit - 1) / limit);
        for (const Json& entry : meshes) {
            const std::string id = entry.at("id");
            const auto& [bytes, format] = mesh_of.at(id);
            EXPECT_EQ(entry.at("url"), "/v1/meshes/" + id);
            EXPECT_EQ(entry.at("format"), format);
            EXPECT_EQ(entry.at("media_type"), format == "glb" ? "model/gltf-binary" : "model/obj");
            EXPECT_EQ(entry.at("bytes"), bytes.size());
            const long long created = epoch_seconds(entry.at("created"));
            EXPECT_GE(created, start - 1);
            EXPECT_LE(created, end + 1);
        }
    }
    // Without a limit, a page of up to 100; the presets are never listed.
    const Json all = expect_conforms("GET", "/v1/environments", client->Get("/v1/environments"));
    ASSERT_TRUE(all.is_object());
    EXPECT_EQ(all.at("environments").size(), 3u);
    EXPECT_FALSE(all.contains("next"));
    // A cursor past every id: an empty last page.
    const Json past = expect_conforms(
        "GET", "/v1/meshes", client->Get(("/v1/meshes?after=" + std::string(64, 'f')).c_str()));
    ASSERT_TRUE(past.is_object());
    EXPECT_TRUE(past.at("meshes").empty());
    EXPECT_FALSE(past.contains("next"));
}

TEST_F(StoredAssetsShared, InvalidListingParametersAre422NamingThem) {
    httplib::Client* client = client_.get();
    const std::string upper(64, 'A');
    for (const std::string collection : {"environments", "meshes"}) {
        const std::string route = "/v1/" + collection;
        for (const auto& [query, parameter] :
             {std::pair<std::string, std::string>{"limit=0", "limit"},
              {"limit=1001", "limit"},
              {"limit=ten", "limit"},
              {"limit=-1", "limit"},
              {"limit=1&limit=2", "limit"},
              {"after=default", "after"},
              {"after=" + upper, "after"},
              {"after=../../etc", "after"},
              {"cursor=x", "cursor"}}) {
            SCOPED_TRACE(route + "?" + query);
            const auto result = client->Get((route + "?" + query).c_str());
            expect_problem("GET", route, result, ProblemKind::InvalidParameter, parameter);
        }
        const auto result = client->Get((route + "?limit=1001").c_str());
        ASSERT_TRUE(result);
        EXPECT_EQ(Json::parse(result->body).at("detail"), "limit: must be in 1..1000, got 1001");
    }
}

TEST_F(StoredAssetsShared, ADeletedEnvironmentIs404EverywhereAndLeavesNothingStored) {
    httplib::Client* client = client_.get();
    const std::string map = exr_bytes(three_disc_environment(48, 24).image);
    const Json rig = upload_environment(*client, map, "image/x-exr", "light_count=2");
    ASSERT_TRUE(rig.is_object());
    const std::string id = rig.at("id");
    const std::string map_id = api::sha256_hex(map);
    // Its frame (the default product is glossy: the rig's specular cube is made and stored),
    // twice so that the second comes from the frame cache, and its preview, cached too.
    const Json request = frame_request(id, "default");
    for (const char* cache : {"miss", "hit"}) {
        const auto frame = post_json(*client, "/v1/render", request);
        ASSERT_TRUE(frame);
        ASSERT_EQ(frame->status, 200) << frame->body;
        EXPECT_EQ(frame->get_header_value("X-Oer-Cache"), cache);
    }
    const std::string preview = "/v1/environments/" + id + "/preview.jpg";
    ASSERT_EQ(client->Get(preview.c_str())->status, 200);
    EXPECT_FALSE(files_naming(data(), id).empty());
    EXPECT_FALSE(files_naming(data(), map_id).empty());

    const auto deleted = client->Delete(("/v1/environments/" + id).c_str());
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->status, 204) << deleted->body;
    EXPECT_TRUE(deleted->body.empty());
    expect_conforms("DELETE", "/v1/environments/{id}", deleted);

    expect_problem("GET", "/v1/environments/{id}", client->Get(("/v1/environments/" + id).c_str()),
                   ProblemKind::UnknownId);
    expect_problem("GET", "/v1/environments/{id}/preview.jpg", client->Get(preview.c_str()),
                   ProblemKind::UnknownId);
    expect_problem("GET", "/v1/environments/{id}/irradiance.exr",
                   client->Get(("/v1/environments/" + id + "/irradiance.exr").c_str()),
                   ProblemKind::UnknownId);
    expect_problem("POST", "/v1/render", post_json(*client, "/v1/render", request),
                   ProblemKind::UnknownId, "environment");
    expect_problem("GET", "/v1/render",
                   client->Get(("/v1/render?environment=" + id + "&width=48&height=32").c_str()),
                   ProblemKind::UnknownId, "environment");
    expect_problem("DELETE", "/v1/environments/{id}",
                   client->Delete(("/v1/environments/" + id).c_str()), ProblemKind::UnknownId);
    const Json listing =
        expect_conforms("GET", "/v1/environments", client->Get("/v1/environments?limit=1000"));
    ASSERT_TRUE(listing.is_object());
    const std::vector<std::string> listed = ids_of(listing.at("environments"));
    EXPECT_EQ(std::count(listed.begin(), listed.end(), id), 0) << "still listed";
    EXPECT_EQ(files_naming(data(), id), std::vector<std::string>{})
        << "its rig, record or cube is still stored";
    EXPECT_EQ(files_naming(data(), map_id), std::vector<std::string>{})
        << "its map is still stored";

    // The same map and options make the same environment again, and its frame.
    const auto again = client->Post("/v1/environments?light_count=2", map, "image/x-exr");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 201) << again->body;
    const auto frame = post_json(*client, "/v1/render", request);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->status, 200) << frame->body;
}

TEST_F(StoredAssetsShared, ADeletedMeshIs404EverywhereAndItsFileIsGone) {
    httplib::Client* client = client_.get();
    const Json mesh = upload_mesh(*client, box_obj({0, 0, 0}, {1, 2, 1}), "model/obj");
    ASSERT_TRUE(mesh.is_object());
    const std::string id = mesh.at("id");
    const Json request = frame_request("default", id);
    const std::string query = "/v1/render?environment=default&mesh=" + id + "&width=48&height=32";
    for (int i = 0; i < 2; ++i) {
        const auto frame = post_json(*client, "/v1/render", request);
        ASSERT_TRUE(frame);
        ASSERT_EQ(frame->status, 200) << frame->body;
        ASSERT_EQ(client->Get(query.c_str())->status, 200);
    }
    ASSERT_EQ(files_naming(data() / "meshes", id).size(), 1u);

    const auto deleted = client->Delete(("/v1/meshes/" + id).c_str());
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->status, 204) << deleted->body;
    expect_conforms("DELETE", "/v1/meshes/{id}", deleted);

    expect_problem("GET", "/v1/meshes/{id}", client->Get(("/v1/meshes/" + id).c_str()),
                   ProblemKind::UnknownId);
    expect_problem("POST", "/v1/render", post_json(*client, "/v1/render", request),
                   ProblemKind::UnknownId, "objects/0/mesh");
    expect_problem("GET", "/v1/render", client->Get(query.c_str()), ProblemKind::UnknownId, "mesh");
    expect_problem("DELETE", "/v1/meshes/{id}", client->Delete(("/v1/meshes/" + id).c_str()),
                   ProblemKind::UnknownId);
    const Json listing = expect_conforms("GET", "/v1/meshes", client->Get("/v1/meshes?limit=1000"));
    ASSERT_TRUE(listing.is_object());
    const std::vector<std::string> listed = ids_of(listing.at("meshes"));
    EXPECT_EQ(std::count(listed.begin(), listed.end(), id), 0) << "still listed";
    EXPECT_TRUE(files_naming(data(), id).empty());
}

TEST_F(StoredAssetsShared, ThePresetsCannotBeDeleted) {
    httplib::Client* client = client_.get();
    for (const std::string collection : {"environments", "meshes"}) {
        SCOPED_TRACE(collection);
        const std::string path = "/v1/" + collection + "/default";
        const auto refused = client->Delete(path.c_str());
        expect_problem("DELETE", "/v1/" + collection + "/{id}", refused,
                       ProblemKind::PresetNotDeletable);
        ASSERT_TRUE(refused);
        EXPECT_NE(Json::parse(refused->body).at("detail").get<std::string>().find("built-in"),
                  std::string::npos);
        EXPECT_EQ(client->Get(path.c_str())->status, 200);
    }
    const auto frame = post_json(*client, "/v1/render", frame_request("default", "default"));
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->status, 200);
}

// The routes' methods: 405 naming them for another method, and CORS preflights listing them.
TEST_F(StoredAssetsShared, TheMethodsOfEachPathAreTheRoutes) {
    httplib::Client* client = client_.get();
    const std::string id(64, 'a');
    for (const auto& [path, methods] :
         {std::pair<std::string, std::set<std::string>>{"/v1/environments", {"GET", "POST"}},
          {"/v1/environments/" + id, {"GET", "DELETE"}},
          {"/v1/meshes", {"GET", "POST"}},
          {"/v1/meshes/" + id, {"GET", "DELETE"}}}) {
        SCOPED_TRACE(path);
        const auto put = client->Put(path.c_str(), "{}", "application/json");
        ASSERT_TRUE(put);
        EXPECT_EQ(put->status, 405);
        EXPECT_EQ(allowed(put->get_header_value("Allow")), methods);
        EXPECT_EQ(Json::parse(put->body).at("type"),
                  server::problem_type(ProblemKind::MethodNotAllowed).type);
        const auto preflight = client->Options(
            path.c_str(),
            {{"Origin", "https://shop.example"}, {"Access-Control-Request-Method", "DELETE"}});
        ASSERT_TRUE(preflight);
        EXPECT_EQ(preflight->status, 204);
        std::set<std::string> expected = methods;
        expected.insert("OPTIONS");
        EXPECT_EQ(allowed(preflight->get_header_value("Access-Control-Allow-Methods")), expected);
    }
}

// A frame of an environment and a mesh both deleted while it renders: it finishes or is 404,
// the server stays up, and the next frame of them is 404. The mesh is a grid of 20,000
// triangles whose transfer the frame bakes first, so that the deletions land while it runs.
TEST(StoredAssets, DeletingWhileAFrameOfTheSameAssetsRendersCrashesNothing) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string map = exr_bytes(three_disc_environment(64, 32).image);
    const std::string grid = grid_obj(100);
    const Json rig = upload_environment(*client, map, "image/x-exr", "light_count=2");
    const Json mesh = upload_mesh(*client, grid, "model/obj");
    ASSERT_TRUE(rig.is_object() && mesh.is_object());
    Json request = frame_request(rig.at("id"), mesh.at("id"));
    request["width"] = 256;
    request["height"] = 256;
    for (int round = 0; round < 2; ++round) {
        SCOPED_TRACE(round);
        if (round == 1) {
            ASSERT_EQ(upload_environment(*client, map, "image/x-exr", "light_count=2").at("id"),
                      rig.at("id"));
            ASSERT_EQ(upload_mesh(*client, grid, "model/obj").at("id"), mesh.at("id"));
            request["background"] = "#102030";  // another frame, another bake's timing
        }
        std::optional<httplib::Result> answer;
        std::thread render([&] {
            auto own = server.client();
            answer.emplace(post_json(*own, "/v1/render", request));
        });
        std::this_thread::sleep_for(std::chrono::milliseconds(round == 0 ? 20 : 150));
        const auto environment_deleted =
            client->Delete(("/v1/environments/" + rig.at("id").get<std::string>()).c_str());
        const auto mesh_deleted =
            client->Delete(("/v1/meshes/" + mesh.at("id").get<std::string>()).c_str());
        render.join();
        const httplib::Result& frame = *answer;
        ASSERT_TRUE(environment_deleted && mesh_deleted);
        EXPECT_EQ(environment_deleted->status, 204);
        EXPECT_EQ(mesh_deleted->status, 204);
        ASSERT_TRUE(frame);
        if (frame->status == 200) {
            EXPECT_EQ(decode_image(frame).width, 256);
        } else {
            expect_problem("POST", "/v1/render", frame, ProblemKind::UnknownId);
        }
        expect_problem("POST", "/v1/render", post_json(*client, "/v1/render", request),
                       ProblemKind::UnknownId);
        const auto health = client->Get("/readyz");
        ASSERT_TRUE(health);
        EXPECT_EQ(health->status, 200);
    }
}

TEST(StoredAssetsApiKey, DeletingNeedsTheKeyListingDoesNot) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.api_key = "s3cret-key";
    TestServer server(config);
    auto client = server.client();
    const httplib::Headers key{{"Authorization", "Bearer s3cret-key"}};
    const auto uploaded =
        client->Post("/v1/meshes", key, box_obj({0, 0, 0}, {1, 1, 1}), "model/obj");
    ASSERT_TRUE(uploaded);
    ASSERT_EQ(uploaded->status, 201) << uploaded->body;
    const std::string path =
        "/v1/meshes/" + Json::parse(uploaded->body).at("id").get<std::string>();

    const Json listing = expect_conforms("GET", "/v1/meshes", client->Get("/v1/meshes"));
    ASSERT_TRUE(listing.is_object());
    EXPECT_EQ(listing.at("meshes").size(), 1u);
    for (const httplib::Headers& headers :
         {httplib::Headers{}, httplib::Headers{{"Authorization", "Bearer wrong"}}}) {
        const auto refused = client->Delete(path.c_str(), headers);
        expect_problem("DELETE", "/v1/meshes/{id}", refused, ProblemKind::Unauthorized);
        ASSERT_TRUE(refused);
        EXPECT_EQ(refused->get_header_value("WWW-Authenticate"), "Bearer");
        EXPECT_EQ(client->Get(path.c_str())->status, 200) << "deleted without the key";
    }
    // The key is asked before anything is said of the id: the preset and unknown ids too.
    expect_problem("DELETE", "/v1/environments/{id}", client->Delete("/v1/environments/default"),
                   ProblemKind::Unauthorized);
    expect_problem("DELETE", "/v1/environments/{id}",
                   client->Delete(("/v1/environments/" + std::string(64, 'b')).c_str()),
                   ProblemKind::Unauthorized);
    const auto deleted = client->Delete(path.c_str(), {{"Authorization", "bearer s3cret-key"}});
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->status, 204) << deleted->body;
    EXPECT_EQ(client->Get(path.c_str())->status, 404);
}
