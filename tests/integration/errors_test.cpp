// Every error status of the API produced by a real request, answered as RFC 9457 problem+json
// with the right status, a detail, and (422, 404) the member or parameter at fault.
#include <gtest/gtest.h>

#include <optional>
#include <set>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

const std::string kUnknownId = "0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef";

class Errors : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        root_ = new TempRoot();
        server::ServiceConfig config = test_config(root_->data());
        config.max_upload_bytes = 256 << 10;
        config.max_image_pixels = 128 * 64;
        config.max_frame_width = 256;
        config.max_frame_height = 256;
        server_ = new TestServer(config);
    }
    static void TearDownTestSuite() {
        delete server_;
        delete root_;
        server_ = nullptr;
        root_ = nullptr;
        rig_.reset();
    }
    void SetUp() override { client_ = server_->client(); }

    // A rig of three lights, uploaded once to the suite's server (each --gtest_repeat round
    // starts a new server, with an empty data folder).
    static const Json& rig() {
        if (!rig_) {
            auto client = server_->client();
            rig_ = upload_environment(*client, exr_bytes(three_disc_environment(128, 64).image),
                                      "image/x-exr", "light_count=3");
        }
        return *rig_;
    }

    static inline TempRoot* root_ = nullptr;
    static inline TestServer* server_ = nullptr;
    static inline std::optional<Json> rig_;
    std::unique_ptr<httplib::Client> client_;
};

}  // namespace

TEST_F(Errors, MalformedJsonIs400) {
    for (const std::string body : {"{\"environment\": ", "{\"environment\": \"default\",}", "nul",
                                   "{\"width\": 1e999999}"}) {
        const auto result = client_->Post("/v1/render", body, "application/json");
        expect_problem("POST", "/v1/render", result, ProblemKind::MalformedRequest);
    }
}

TEST_F(Errors, UnknownIdsAre404NamingWhereTheyCameFrom) {
    for (const std::string& path :
         {"/v1/environments/" + kUnknownId, "/v1/environments/" + kUnknownId + "/preview.jpg",
          "/v1/environments/" + kUnknownId + "/irradiance.exr", "/v1/meshes/" + kUnknownId}) {
        SCOPED_TRACE(path);
        const std::string route =
            path.find("/v1/meshes/") == 0                   ? "/v1/meshes/{id}"
            : path.find("preview.jpg") != std::string::npos ? "/v1/environments/{id}/preview.jpg"
            : path.find("irradiance") != std::string::npos  ? "/v1/environments/{id}/irradiance.exr"
                                                            : "/v1/environments/{id}";
        expect_problem("GET", route, client_->Get(path.c_str()), ProblemKind::UnknownId);
    }
    expect_problem("POST", "/v1/render",
                   post_json(*client_, "/v1/render", {{"environment", kUnknownId}}),
                   ProblemKind::UnknownId, "environment");
    expect_problem("POST", "/v1/render",
                   post_json(*client_, "/v1/render",
                             {{"environment", "default"},
                              {"objects", {{{"mesh", "default"}}, {{"mesh", kUnknownId}}}}}),
                   ProblemKind::UnknownId, "objects/1/mesh");
    expect_problem("GET", "/v1/render",
                   client_->Get(("/v1/render?environment=" + kUnknownId).c_str()),
                   ProblemKind::UnknownId, "environment");
}

TEST_F(Errors, BadIdsAreRejectedWithoutTouchingTheFileSystem) {
    // Not ids at all: the route may not match (404) or the id is invalid (422); never a file.
    for (const std::string path :
         {"/v1/environments/..%2F..%2F..%2Fetc%2Fpasswd", "/v1/meshes/..%2F..%2F..%2Fetc%2Fpasswd",
          "/v1/environments/%2E%2E", "/v1/meshes/..%5C..%5Cwin.ini"}) {
        SCOPED_TRACE(path);
        const auto result = client_->Get(path.c_str());
        ASSERT_TRUE(result);
        EXPECT_TRUE(result->status == 404 || result->status == 422) << result->status;
        EXPECT_EQ(result->get_header_value("Content-Type"), "application/problem+json");
        EXPECT_EQ(result->body.find("root:"), std::string::npos) << "served /etc/passwd";
    }
    // Valid-looking but not lowercase hex: no such asset (404) or an invalid id (422, naming
    // it), both listed by the spec; never a file read.
    std::string upper = kUnknownId;
    for (char& c : upper) {
        c = char(std::toupper(static_cast<unsigned char>(c)));
    }
    for (const auto& [path, route] :
         {std::pair{"/v1/environments/" + upper, std::string("/v1/environments/{id}")},
          std::pair{"/v1/meshes/" + upper, std::string("/v1/meshes/{id}")}}) {
        const auto result = client_->Get(path.c_str());
        ASSERT_TRUE(result);
        const bool invalid = result->status == 422;
        expect_problem("GET", route, result,
                       invalid ? ProblemKind::InvalidParameter : ProblemKind::UnknownId,
                       invalid ? std::optional<std::string>("id") : std::nullopt);
    }
    expect_problem("POST", "/v1/render",
                   post_json(*client_, "/v1/render", {{"environment", "../../etc/passwd"}}),
                   ProblemKind::InvalidParameter, "environment");
    expect_problem("GET", "/v1/render",
                   client_->Get("/v1/render?environment=..%2F..%2Fetc%2Fpasswd"),
                   ProblemKind::InvalidParameter, "environment");
    // Nothing appeared beside the data folder, and inside it only the store's own folders.
    std::set<std::string> beside;
    for (const auto& entry : std::filesystem::directory_iterator(root_->root())) {
        beside.insert(entry.path().filename().string());
    }
    EXPECT_EQ(beside, std::set<std::string>{"data"});
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root_->data())) {
        EXPECT_EQ(entry.path().filename().string().find("passwd"), std::string::npos)
            << entry.path();
    }
}

TEST_F(Errors, UnsupportedMethodsAre405) {
    const auto remove = client_->Delete("/v1/environments");
    ASSERT_TRUE(remove);
    EXPECT_EQ(remove->status, 405);
    EXPECT_EQ(remove->get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(remove->get_header_value("Allow"), "POST, GET");
    EXPECT_EQ(Json::parse(remove->body).at("type"),
              server::problem_type(ProblemKind::MethodNotAllowed).type);
    const auto put = client_->Put("/v1/render", "{}", "application/json");
    ASSERT_TRUE(put);
    EXPECT_EQ(put->status, 405);
    EXPECT_EQ(put->get_header_value("Content-Type"), "application/problem+json");
    const auto post = client_->Post("/healthz", "", "text/plain");
    ASSERT_TRUE(post);
    EXPECT_EQ(post->status, 405);
    EXPECT_EQ(post->get_header_value("Allow"), "GET");
    // No route at all: 404 of the kind that names no id.
    const auto nowhere = client_->Get("/v1/nowhere");
    ASSERT_TRUE(nowhere);
    EXPECT_EQ(nowhere->status, 404);
    EXPECT_EQ(Json::parse(nowhere->body).at("type"),
              server::problem_type(ProblemKind::NotFound).type);
}

TEST_F(Errors, OverTheLimitsIs413) {
    // A body over max_upload_bytes (256 KiB).
    const std::string big(300 << 10, 'x');
    expect_problem("POST", "/v1/environments",
                   client_->Post("/v1/environments", big, "image/x-exr"),
                   ProblemKind::LimitExceeded);
    expect_problem("POST", "/v1/meshes", client_->Post("/v1/meshes", big, "model/obj"),
                   ProblemKind::LimitExceeded);
    // An image over max_image_pixels (128 x 64), however small its file.
    const std::string large_map = exr_bytes(three_disc_environment(256, 128).image);
    ASSERT_LT(large_map.size(), std::size_t(256 << 10));
    expect_problem("POST", "/v1/environments",
                   client_->Post("/v1/environments", large_map, "image/x-exr"),
                   ProblemKind::LimitExceeded);
    // A frame wider than max_frame_width (256).
    expect_problem("POST", "/v1/render",
                   post_json(*client_, "/v1/render", {{"environment", "default"}, {"width", 300}}),
                   ProblemKind::LimitExceeded);
    expect_problem("GET", "/v1/render", client_->Get("/v1/render?environment=default&height=257"),
                   ProblemKind::LimitExceeded);
    // A render body over the API's max_body_bytes (256 KiB), valid JSON throughout.
    const Json padded = {{"environment", "default"}, {"background", std::string(300 << 10, ' ')}};
    expect_problem("POST", "/v1/render", post_json(*client_, "/v1/render", padded),
                   ProblemKind::LimitExceeded);
}

TEST_F(Errors, WrongMediaTypesAre415) {
    const std::string map = exr_bytes(three_disc_environment(64, 32).image);
    expect_problem("POST", "/v1/environments", client_->Post("/v1/environments", map, "text/plain"),
                   ProblemKind::UnsupportedMediaType);
    expect_problem("POST", "/v1/render",
                   client_->Post("/v1/render", "{\"environment\": \"default\"}", "text/plain"),
                   ProblemKind::UnsupportedMediaType);
    expect_problem("POST", "/v1/meshes",
                   client_->Post("/v1/meshes", box_obj({0, 0, 0}, {1, 1, 1}), "image/png"),
                   ProblemKind::UnsupportedMediaType);
}

// The decoder is the declared type's: bytes of another image format are refused as what they
// are (both names in the detail), not decoded by whichever reader accepts them, and nothing of
// them is stored.
TEST_F(Errors, ABodyOfAnotherImageFormatThanDeclaredIs415NamingBoth) {
    const oer::HdrImage map = three_disc_environment(64, 32).image;
    const oer::Rgba8Image photo{8, 4, std::vector<std::uint8_t>(8 * 4 * 4, 128)};
    const std::vector<std::uint8_t> jpeg = oer::encode_jpeg(photo, 90);
    const struct {
        std::string body, declared, actual;
    } cases[] = {
        {std::string(jpeg.begin(), jpeg.end()), "image/x-exr", "image/jpeg"},
        {exr_bytes(map), "image/vnd.radiance", "image/x-exr"},
        {hdr_bytes(map), "image/x-exr", "image/vnd.radiance"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.actual + " as " + c.declared);
        const auto result = client_->Post("/v1/environments", c.body, c.declared);
        expect_problem("POST", "/v1/environments", result, ProblemKind::UnsupportedMediaType);
        ASSERT_TRUE(result);
        const std::string detail = Json::parse(result->body).at("detail").get<std::string>();
        EXPECT_EQ(detail,
                  "the body is " + c.actual + ", not " + c.declared + " as its Content-Type says");
    }
    // The same bytes under their own type are accepted (201, or 200 if stored before).
    const auto accepted = client_->Post("/v1/environments", exr_bytes(map), "image/x-exr");
    ASSERT_TRUE(accepted);
    EXPECT_TRUE(accepted->status == 201 || accepted->status == 200) << accepted->status;
}

// An upload's errors name the user's file as the page sent it (?filename=), never an internal
// name; without one, "the uploaded .glb file". A name that is not one line of UTF-8 is 422.
TEST_F(Errors, UploadErrorsNameTheUsersFile) {
    const std::string broken = "glTF\x02\x00\x00\x00broken";
    const auto named = client_->Post("/v1/meshes?filename=Sofa%20%E2%80%93%20velvet.glb", broken,
                                     "model/gltf-binary");
    expect_problem("POST", "/v1/meshes", named, server::ProblemKind::InvalidContent);
    ASSERT_TRUE(named);
    const std::string detail = Json::parse(named->body).value("detail", "");
    EXPECT_EQ(detail.rfind("Sofa \u2013 velvet.glb: ", 0), 0u) << detail;
    EXPECT_EQ(detail.find("upload."), std::string::npos) << detail;
    const auto unnamed = client_->Post("/v1/meshes", broken, "model/gltf-binary");
    ASSERT_TRUE(unnamed);
    EXPECT_EQ(Json::parse(unnamed->body).value("detail", "").rfind("the uploaded .glb file: ", 0),
              0u)
        << unnamed->body;
    const auto map = client_->Post("/v1/environments?filename=studio.exr&light_count=2",
                                   std::string("v/1\x01 not an exr"), "image/x-exr");
    ASSERT_TRUE(map);
    EXPECT_NE(Json::parse(map->body).value("detail", "").find("studio.exr"), std::string::npos)
        << map->body;
    EXPECT_EQ(Json::parse(map->body).value("detail", "").find("upload."), std::string::npos)
        << map->body;
    const auto basisu = client_->Post(
        "/v1/meshes?filename=chair.gltf",
        R"({"asset": {"version": "2.0"}, "extensionsRequired": ["KHR_texture_basisu"]})",
        "model/gltf+json");
    ASSERT_TRUE(basisu);
    const std::string advice = Json::parse(basisu->body).value("detail", "");
    EXPECT_NE(advice.find("chair.gltf: the asset requires the extension KHR_texture_basisu"),
              std::string::npos)
        << advice;
    EXPECT_NE(advice.find("export them as WebP"), std::string::npos) << advice;
    for (const char* bad :
         {"/v1/meshes?filename=", "/v1/meshes?filename=a%0Ab.glb", "/v1/meshes?filename=%FF.glb"}) {
        const auto refused = client_->Post(bad, broken, "model/gltf-binary");
        expect_problem("POST", "/v1/meshes", refused, server::ProblemKind::InvalidParameter);
        ASSERT_TRUE(refused);
        EXPECT_EQ(Json::parse(refused->body).value("parameter", ""), "filename") << bad;
    }
}

TEST_F(Errors, InvalidMembersAre422NamingThem) {
    const std::vector<std::pair<Json, std::string>> cases = {
        {{{"environment", "default"}, {"width", 0}}, "width"},
        {{{"environment", "default"}, {"widht", 5}}, "widht"},
        {{{"environment", "default"}, {"camera", {{"orbit", {{"pitch", 100}}}}}},
         "camera/orbit/pitch"},
        {{{"environment", "default"}, {"format", "gif"}}, "format"},
        {{{"environment", "default"},
          {"objects", {{{"mesh", "default"}, {"transform", Json::array({1, 2, 3})}}}}},
         "objects/0/transform"},
        {Json::array({1, 2}), "body"},
    };
    for (const auto& [body, parameter] : cases) {
        SCOPED_TRACE(body.dump());
        expect_problem("POST", "/v1/render", post_json(*client_, "/v1/render", body),
                       ProblemKind::InvalidParameter, parameter);
    }
    expect_problem("GET", "/v1/render", client_->Get("/v1/render?environment=default&color=red"),
                   ProblemKind::InvalidParameter, "color");
    expect_problem("GET", "/v1/render", client_->Get("/v1/render?environment=default&samples=3"),
                   ProblemKind::InvalidParameter, "samples");
    // Light switches must match the rig's lights.
    ASSERT_TRUE(rig().is_object());
    ASSERT_EQ(rig().at("lights").size(), 3u);
    expect_problem(
        "POST", "/v1/render",
        post_json(*client_, "/v1/render", {{"environment", rig().at("id")}, {"lights", {true}}}),
        ProblemKind::InvalidParameter, "lights");
    expect_problem("GET", "/v1/render",
                   client_->Get(("/v1/render?environment=" + rig().at("id").get<std::string>() +
                                 "&lights=1,0,1,1")
                                    .c_str()),
                   ProblemKind::InvalidParameter, "lights");
    expect_problem("GET", "/v1/environments/{id}/irradiance.exr",
                   client_->Get(("/v1/environments/" + rig().at("id").get<std::string>() +
                                 "/irradiance.exr?lights=1")
                                    .c_str()),
                   ProblemKind::InvalidParameter, "lights");
    // Upload options.
    const std::string map = exr_bytes(three_disc_environment(64, 32).image);
    expect_problem("POST", "/v1/environments",
                   client_->Post("/v1/environments?light_count=99", map, "image/x-exr"),
                   ProblemKind::InvalidParameter, "light_count");
    expect_problem("POST", "/v1/environments",
                   client_->Post("/v1/environments?bogus=1", map, "image/x-exr"),
                   ProblemKind::InvalidParameter, "bogus");
    // Uploads that do not decode.
    expect_problem("POST", "/v1/environments",
                   client_->Post("/v1/environments",
                                 "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 "
                                 "+X 128\n\x02\x02garbage",
                                 "image/vnd.radiance"),
                   ProblemKind::InvalidContent);
    std::string truncated = map.substr(0, map.size() / 2);
    expect_problem("POST", "/v1/environments",
                   client_->Post("/v1/environments", truncated, "image/x-exr"),
                   ProblemKind::InvalidContent);
    expect_problem(
        "POST", "/v1/meshes",
        client_->Post("/v1/meshes", std::string("glTF\x02\0\0\0garbage", 15), "model/gltf-binary"),
        ProblemKind::InvalidContent);
    expect_problem("POST", "/v1/meshes", client_->Post("/v1/meshes", "f 1 2 3\n", "model/obj"),
                   ProblemKind::InvalidContent);
}

TEST(ErrorsApiKey, UploadsNeedTheKeyAndProbesDoNot) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.api_key = "s3cret-key";
    TestServer server(config);
    auto client = server.client();
    const std::string map = exr_bytes(three_disc_environment(64, 32).image);
    const std::string obj = box_obj({0, 0, 0}, {1, 1, 1});
    // The store as start-up left it (the default scene's transfer).
    const auto stored_files = [&root] {
        std::set<std::filesystem::path> files;
        for (const auto& entry : std::filesystem::recursive_directory_iterator(root.data())) {
            if (entry.is_regular_file()) {
                files.insert(entry.path());
            }
        }
        return files;
    };
    const std::set<std::filesystem::path> at_start = stored_files();
    for (const httplib::Headers& headers :
         {httplib::Headers{}, httplib::Headers{{"Authorization", "Bearer wrong"}},
          httplib::Headers{{"Authorization", "s3cret-key"}},
          httplib::Headers{{"Authorization", "Basic s3cret-key"}},
          httplib::Headers{{"Authorization", "Bearer s3cret-keyX"}},
          httplib::Headers{{"Authorization", "Bearers3cret-key"}}}) {
        SCOPED_TRACE(headers.empty() ? "no key" : headers.begin()->second);
        const auto upload = client->Post("/v1/environments", headers, map, "image/x-exr");
        expect_problem("POST", "/v1/environments", upload, ProblemKind::Unauthorized);
        ASSERT_TRUE(upload);
        EXPECT_NE(upload->get_header_value("WWW-Authenticate").find("Bearer"), std::string::npos);
        expect_problem("POST", "/v1/meshes", client->Post("/v1/meshes", headers, obj, "model/obj"),
                       ProblemKind::Unauthorized);
    }
    // Nothing was stored by the refused uploads.
    EXPECT_EQ(stored_files(), at_start);
    const httplib::Headers key{{"Authorization", "Bearer s3cret-key"}};
    const auto upload = client->Post("/v1/environments", key, map, "image/x-exr");
    ASSERT_TRUE(upload);
    EXPECT_EQ(upload->status, 201) << upload->body;
    // The scheme is case-insensitive (RFC 9110 section 11.1), and spaces may precede the key.
    const httplib::Headers lower_case{{"Authorization", "bearer   s3cret-key"}};
    const auto mesh = client->Post("/v1/meshes", lower_case, obj, "model/obj");
    ASSERT_TRUE(mesh);
    EXPECT_EQ(mesh->status, 201) << mesh->body;
    for (const char* probe : {"/healthz", "/readyz", "/metrics"}) {
        const auto result = client->Get(probe);
        ASSERT_TRUE(result);
        EXPECT_EQ(result->status, 200) << probe;
    }
}

// api/openapi.yaml: with an API key, the uploads and deletions need it (StoredAssetsApiKey
// for the deletions) and every other route does not.
TEST(ErrorsApiKey, OnlyUploadsAndDeletionsNeedTheKey) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.api_key = "s3cret-key";
    TestServer server(config);
    auto client = server.client();
    for (const char* path :
         {"/v1/info", "/v1/presets", "/v1/environments/default", "/v1/meshes/default",
          "/v1/environments", "/v1/meshes", "/v1/render?environment=default&width=8&height=8"}) {
        const auto result = client->Get(path);
        ASSERT_TRUE(result) << path;
        EXPECT_EQ(result->status, 200) << path << ": " << result->body;
    }
    const auto render =
        post_json(*client, "/v1/render", {{"environment", "default"}, {"width", 8}, {"height", 8}});
    ASSERT_TRUE(render);
    EXPECT_EQ(render->status, 200) << render->body;
}
