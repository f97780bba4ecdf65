// The asset's own cameras end to end: a GLB whose nodes hold cameras is uploaded, the mesh JSON
// lists them, `camera=asset:N` draws from one, and its X-Oer-Camera, given back as an explicit
// look-at camera, draws the same pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

// A GLB's JSON chunk edited by `edit` (the BIN chunk kept as it is).
std::string with_edited_json(const std::string& glb, const std::function<void(Json&)>& edit) {
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    Json document = Json::parse(glb.substr(20, json_length));
    edit(document);
    std::string text = document.dump();
    while (text.size() % 4 != 0) {
        text += ' ';
    }
    const std::string bin_chunk = glb.substr(20 + json_length);
    std::string out = glb.substr(0, 12);
    const std::uint32_t total = std::uint32_t(12 + 8 + text.size() + bin_chunk.size());
    const std::uint32_t length = std::uint32_t(text.size());
    std::memcpy(out.data() + 8, &total, 4);
    out.append(reinterpret_cast<const char*>(&length), 4);
    out += "JSON" + text + bin_chunk;
    return out;
}

// Camera 1's node: numbers that need all of a float's digits, so that a camera header rounded
// any coarser would draw another frame.
const glm::dvec3 kSideEye{2.5371, 1.2219, 0.3137};
const double kSideTurn = glm::radians(85.0);  // about +Y: -Z turns towards -X
const double kSideYfov = 0.9123;              // radians

// The box of box_glb with three cameras beside it: 0 "Front" on +Z, 1 "Side" on +X turned
// kSideTurn about +Y (looking nearly down -X), 2 "Plan" orthographic above it.
std::string box_with_cameras() {
    return with_edited_json(box_glb({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5}), [](Json& gltf) {
        gltf["cameras"] = {
            {{"type", "perspective"},
             {"name", "Front"},
             {"perspective", {{"yfov", 0.7}, {"znear", 0.05}}}},
            {{"type", "perspective"},
             {"name", "Side"},
             {"perspective", {{"yfov", kSideYfov}, {"znear", 0.05}, {"zfar", 50.0}}}},
            {{"type", "orthographic"},
             {"name", "Plan"},
             {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}}};
        gltf["nodes"].push_back({{"camera", 0}, {"translation", {0.0, 0.6, 3.0}}});
        gltf["nodes"].push_back(
            {{"camera", 1},
             {"translation", {kSideEye.x, kSideEye.y, kSideEye.z}},
             {"rotation", {0.0, std::sin(kSideTurn / 2), 0.0, std::cos(kSideTurn / 2)}}});
        gltf["nodes"].push_back({{"camera", 2},
                                 {"translation", {0.0, 4.0, 0.0}},
                                 {"rotation", {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)}}});
        gltf["scenes"][0]["nodes"] = {0, 1, 2, 3};
    });
}

// The three numbers of `name=x,y,z` in an X-Oer-Camera header, as text and as a vector.
std::string header_value(const std::string& header, const std::string& name) {
    const std::size_t at = header.find(name + "=");
    if (at == std::string::npos) {
        ADD_FAILURE() << "no " << name << " in X-Oer-Camera '" << header << "'";
        return "";
    }
    const std::size_t start = at + name.size() + 1;
    return header.substr(start, header.find(';', start) - start);
}

glm::dvec3 header_vector(const std::string& header, const std::string& name) {
    glm::dvec3 v(0.0);
    EXPECT_EQ(std::sscanf(header_value(header, name).c_str(), "%lf,%lf,%lf", &v.x, &v.y, &v.z), 3)
        << header;
    return v;
}

void expect_near(const glm::dvec3& got, const glm::dvec3& expected, const std::string& what) {
    EXPECT_LT(glm::length(got - expected), 1e-5)
        << what << ": (" << got.x << ", " << got.y << ", " << got.z << ")";
}

}  // namespace

TEST(AssetCamera, AFrameFromAnAssetCameraEqualsTheSameCameraGivenExplicitly) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json uploaded = upload_mesh(*client, box_with_cameras(), "model/gltf-binary");
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
    const std::string id = uploaded.at("id");
    ASSERT_EQ(uploaded.at("cameras").size(), 3u) << uploaded.dump(2);

    // GET /v1/meshes/{id} lists them too, as api/openapi.yaml describes.
    const Json listed =
        expect_conforms("GET", "/v1/meshes/{id}", client->Get(("/v1/meshes/" + id).c_str()));
    ASSERT_EQ(listed.at("cameras").size(), 3u);
    const Json& side = listed.at("cameras").at(1);
    EXPECT_EQ(side.at("index"), 1);
    EXPECT_EQ(side.at("name"), "Side");
    EXPECT_EQ(side.at("type"), "perspective");
    EXPECT_EQ(listed.at("cameras").at(2).at("type"), "orthographic");

    const std::string common =
        "/v1/render?environment=default&mesh=" + id + "&width=96&height=64&samples=1&format=png";
    const auto from_asset = client->Get((common + "&camera=asset:1").c_str());
    expect_conforms("GET", "/v1/render", from_asset);
    ASSERT_TRUE(from_asset);
    ASSERT_EQ(from_asset->status, 200) << from_asset->body;
    const std::string header = from_asset->get_header_value("X-Oer-Camera");
    // The node's transform: the eye at its translation, looking down its turned -Z with +Y up;
    // the target on that view at the depth of the box's centre (0, 0.5, 0).
    const glm::dvec3 forward{-std::sin(kSideTurn), 0.0, -std::cos(kSideTurn)};
    const double depth = glm::dot(glm::dvec3(0.0, 0.5, 0.0) - kSideEye, forward);
    expect_near(header_vector(header, "eye"), kSideEye, "eye");
    expect_near(header_vector(header, "target"), kSideEye + depth * forward, "target");
    expect_near(header_vector(header, "up"), {0.0, 1.0, 0.0}, "up");
    EXPECT_NEAR(std::stod(header_value(header, "fov_y")), glm::degrees(kSideYfov), 1e-4) << header;

    // The same camera given explicitly, as the header names it: the same pixels, exactly (the
    // header's nine digits read back as the floats the asset camera drew with).
    const auto explicit_camera = client->Get((common + "&eye=" + header_value(header, "eye") +
                                              "&target=" + header_value(header, "target") +
                                              "&up=" + header_value(header, "up") +
                                              "&fov_y=" + header_value(header, "fov_y"))
                                                 .c_str());
    ASSERT_TRUE(explicit_camera);
    ASSERT_EQ(explicit_camera->status, 200) << explicit_camera->body;
    EXPECT_NE(explicit_camera->get_header_value("ETag"), from_asset->get_header_value("ETag"))
        << "another request, drawn again";
    const Rgba8Image asset_frame = decode_image(from_asset);
    const FrameDifference explicit_difference =
        frame_difference(asset_frame, decode_image(explicit_camera));
    EXPECT_EQ(explicit_difference.differing, 0u) << "largest " << explicit_difference.largest;

    // By name, the same camera; camera 0 is another view.
    const auto by_name = client->Get((common + "&camera=asset:Side").c_str());
    ASSERT_TRUE(by_name);
    ASSERT_EQ(by_name->status, 200) << by_name->body;
    EXPECT_EQ(frame_difference(asset_frame, decode_image(by_name)).differing, 0u);
    const auto front = client->Get((common + "&camera=asset:0").c_str());
    ASSERT_TRUE(front);
    ASSERT_EQ(front->status, 200) << front->body;
    EXPECT_GT(frame_difference(asset_frame, decode_image(front)).differing,
              asset_frame.pixels.size() / 10)
        << "camera 0 draws the same frame as camera 1";
}

TEST(AssetCamera, ACameraTheMeshCannotDrawIsAnInvalidParameter) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json uploaded = upload_mesh(*client, box_with_cameras(), "model/gltf-binary");
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
    const std::string common = "/v1/render?environment=default&width=32&height=32&mesh=" +
                               uploaded.at("id").get<std::string>();
    for (const char* camera : {"asset:2", "asset:Plan", "asset:3", "asset:Nowhere"}) {
        expect_problem("GET", "/v1/render", client->Get((common + "&camera=" + camera).c_str()),
                       ProblemKind::InvalidParameter, "camera");
    }
    expect_problem("GET", "/v1/render",
                   client->Get((common + "&camera=asset:0&eye=0,0,3&target=0,0,0").c_str()),
                   ProblemKind::InvalidParameter, "eye");
    expect_problem("GET", "/v1/render",
                   client->Get("/v1/render?environment=default&mesh=default&camera=asset:0"),
                   ProblemKind::InvalidParameter, "camera");
}

// The mesh JSON is made from the decoded mesh whenever it is read back from the store, so a
// restarted service lists the same cameras and draws from them.
TEST(AssetCamera, TheCamerasAreListedAndDrawnAfterARestart) {
    TempRoot root;
    Json before;
    std::string id;
    {
        TestServer server(test_config(root.data()));
        auto client = server.client();
        const Json uploaded = upload_mesh(*client, box_with_cameras(), "model/gltf-binary");
        ASSERT_FALSE(::testing::Test::HasFatalFailure());
        id = uploaded.at("id");
        before =
            expect_conforms("GET", "/v1/meshes/{id}", client->Get(("/v1/meshes/" + id).c_str()));
    }
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json after =
        expect_conforms("GET", "/v1/meshes/{id}", client->Get(("/v1/meshes/" + id).c_str()));
    ASSERT_EQ(after.at("cameras").size(), 3u);
    EXPECT_EQ(after.at("cameras"), before.at("cameras"));
    const auto frame = client->Get(
        ("/v1/render?environment=default&width=32&height=32&occlusion=off&camera=asset:Side&mesh=" +
         id)
            .c_str());
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->status, 200) << frame->body;
}
