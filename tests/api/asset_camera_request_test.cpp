// A render request from one of the asset's own cameras (api/render_request.hpp, AssetCameraSpec):
// `camera=asset:N` or `asset:NAME` in the query, `"camera": {"asset": N or "NAME"}` in the body,
// one canonical document and ETag for both, its errors, and the camera it resolves to.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/render_request.hpp"
#include "oer/mesh/camera.hpp"
#include "rejected_parameter.hpp"

using namespace oer;
using oer::testing::rejected_member;
using oer::testing::rejected_parameter;
using Json = nlohmann::json;
using Query = std::multimap<std::string, std::string>;

namespace {

Json canonical_of_query(const Query& query) {
    return api::normalised_render_json(api::parse_render_query(query));
}

Json canonical_of_body(const std::string& body) {
    return api::normalised_render_json(api::parse_render_json(body));
}

// A mesh with a perspective camera "Front" and an orthographic "Top", both on +Z looking at the
// origin.
std::shared_ptr<const Mesh> mesh_with_cameras() {
    auto mesh = std::make_shared<Mesh>();
    AssetCamera front;
    front.name = "Front";
    front.camera = {{0.0f, 1.0f, 4.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 30.0f};
    AssetCamera top = front;
    top.name = "Top";
    top.projection = CameraProjection::Orthographic;
    mesh->cameras = {front, top};
    return mesh;
}

// The InvalidParameter that resolving spec's camera throws: its parameter and message.
api::InvalidParameter resolve_error(const api::RenderSpec& spec,
                                    const std::vector<std::shared_ptr<const Mesh>>& meshes) {
    try {
        api::resolved_camera(spec, meshes);
    } catch (const api::InvalidParameter& error) {
        return error;
    }
    ADD_FAILURE() << "the camera resolved";
    return api::InvalidParameter("", "");
}

}  // namespace

TEST(AssetCameraRequest, BothFormsGiveOneCanonicalDocumentAndEtag) {
    const Query query = {{"environment", "default"}, {"mesh", "default"}, {"camera", "asset:1"}};
    const std::string body =
        R"({"environment": "default", "objects": [{"mesh": "default"}], "camera": {"asset": 1}})";
    EXPECT_EQ(canonical_of_query(query).at("camera"), (Json{{"asset", 1}}))
        << "an asset camera has its own field of view: the document holds none";
    EXPECT_EQ(canonical_of_query(query), canonical_of_body(body));
    EXPECT_EQ(api::render_etag(api::parse_render_query(query)),
              api::render_etag(api::parse_render_json(body)));

    const Query named = {{"environment", "default"}, {"mesh", "default"}, {"camera", "asset:Top"}};
    EXPECT_EQ(canonical_of_query(named).at("camera"), (Json{{"asset", "Top"}}));
    EXPECT_EQ(canonical_of_query(named),
              canonical_of_body(R"({"environment": "default", "objects": [{"mesh": "default"}],
                                    "camera": {"asset": "Top"}})"));
    // The canonical document is itself a body of the same request.
    EXPECT_EQ(canonical_of_body(canonical_of_query(named).dump()), canonical_of_query(named));
}

TEST(AssetCameraRequest, EachCameraHasItsOwnEtag) {
    const auto etag = [](const std::string& camera) {
        return api::render_etag(api::parse_render_query(
            {{"environment", "default"}, {"mesh", "default"}, {"camera", camera}}));
    };
    EXPECT_NE(etag("asset:0"), etag("asset:1"));
    EXPECT_NE(etag("asset:0"), etag("asset:Front"));
    EXPECT_NE(etag("asset:0"), api::render_etag(api::parse_render_query(
                                   {{"environment", "default"}, {"mesh", "default"}})));
}

TEST(AssetCameraRequest, MalformedOrContradictoryCamerasAreRejectedNamingTheParameter) {
    const auto query = [](Query more) {
        more.insert({{"environment", "default"}, {"mesh", "default"}});
        return more;
    };
    EXPECT_EQ(rejected_parameter(query({{"camera", "asset:"}})), "camera");
    EXPECT_EQ(rejected_parameter(query({{"camera", "front"}})), "camera");
    EXPECT_EQ(rejected_parameter(query({{"camera", "asset:99999999999"}})), "camera");
    // The asset camera places itself and has its own field of view.
    for (const char* other : {"eye", "target", "up", "yaw", "pitch", "distance", "fov_y"}) {
        const std::string value = std::string(other) == "eye" || std::string(other) == "target" ||
                                          std::string(other) == "up"
                                      ? "0,1,0"
                                      : "10";
        EXPECT_EQ(rejected_parameter(query({{"camera", "asset:0"}, {other, value}})), other);
    }
    const auto body = [](const std::string& camera) {
        return R"({"environment": "default", "objects": [{"mesh": "default"}], "camera": )" +
               camera + "}";
    };
    EXPECT_EQ(rejected_member(body(R"({"asset": -1})")), "camera/asset");
    EXPECT_EQ(rejected_member(body(R"({"asset": ""})")), "camera/asset");
    EXPECT_EQ(rejected_member(body(R"({"asset": [0]})")), "camera/asset");
    EXPECT_EQ(rejected_member(body(R"({"asset": 0, "fov_y": 50})")), "camera/fov_y");
    EXPECT_EQ(rejected_member(body(R"({"asset": 0, "eye": [0, 0, 3], "target": [0, 0, 0]})")),
              "camera/eye");
    EXPECT_EQ(rejected_member(body(R"({"asset": 0, "orbit": {}})")), "camera/orbit");
    EXPECT_EQ(rejected_member(body(R"({"asset": 0})")), "");
}

// The camera of the first object's mesh, placed by that object's transform.
TEST(AssetCameraRequest, ResolvesToTheFirstObjectsCameraPlacedByItsTransform) {
    const auto mesh = mesh_with_cameras();
    const api::RenderSpec spec = api::parse_render_json(R"({"environment": "default",
        "objects": [{"mesh": "default", "transform": [0,0,-1,0, 0,1,0,0, 1,0,0,0, 2,0,0,1]},
                    {"mesh": "default"}],
        "camera": {"asset": "Front"}})");
    const Camera camera = api::resolved_camera(spec, {mesh, std::make_shared<const Mesh>()});
    // A quarter turn about +Y (+Z to +X) and a move of 2 along +X.
    EXPECT_NEAR(glm::length(camera.eye - glm::vec3(6, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(camera.target - glm::vec3(2, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(camera.up - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(camera.fov_y, 30.0f);

    // Untransformed, the camera is the mesh's own, exactly; by index as by name.
    const api::RenderSpec by_index = api::parse_render_query(
        {{"environment", "default"}, {"mesh", "default"}, {"camera", "asset:0"}});
    const Camera own = api::resolved_camera(by_index, {mesh});
    EXPECT_EQ(own.eye, mesh->cameras[0].camera.eye);
    EXPECT_EQ(own.target, mesh->cameras[0].camera.target);
    EXPECT_EQ(own.up, mesh->cameras[0].camera.up);
    EXPECT_EQ(own.fov_y, 30.0f);
    const FrameRequest request =
        api::to_frame_request(by_index, std::make_shared<const Rig>(), nullptr, {mesh});
    ASSERT_TRUE(request.camera.has_value());
    EXPECT_EQ(request.camera->eye, own.eye);
}

// A camera the mesh does not have, an orthographic one, or one without an object: 422 naming
// `camera`, saying what the mesh has.
TEST(AssetCameraRequest, AMissingOrOrthographicCameraIsRejectedListingTheMeshsCameras) {
    const auto mesh = mesh_with_cameras();
    const auto spec = [](const std::string& camera) {
        return api::parse_render_query(
            {{"environment", "default"}, {"mesh", "default"}, {"camera", camera}});
    };
    for (const char* missing : {"asset:2", "asset:Side"}) {
        const api::InvalidParameter error = resolve_error(spec(missing), {mesh});
        EXPECT_EQ(error.parameter(), "camera");
        EXPECT_NE(std::string(error.what())
                      .find("it has 2: 0 'Front' (perspective), 1 'Top' "
                            "(orthographic)"),
                  std::string::npos)
            << error.what();
    }
    EXPECT_NE(std::string(resolve_error(spec("asset:0"), {std::make_shared<const Mesh>()}).what())
                  .find("it has no cameras"),
              std::string::npos);
    const api::InvalidParameter orthographic = resolve_error(spec("asset:Top"), {mesh});
    EXPECT_EQ(orthographic.parameter(), "camera");
    EXPECT_NE(std::string(orthographic.what()).find("orthographic: oer renders perspective"),
              std::string::npos)
        << orthographic.what();
    const api::RenderSpec no_object =
        api::parse_render_query({{"environment", "default"}, {"camera", "asset:0"}});
    EXPECT_EQ(resolve_error(no_object, {}).parameter(), "camera");
}
