// The asset's own cameras (renderer/mesh/src/gltf_cameras.hpp): placed by their nodes' world
// transforms, as the node walk gives them to meshes too; perspective and orthographic; hostile
// cameras left out with a warning while the geometry loads.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "gltf_test_assets.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

// Rotations as glTF quaternions (x, y, z, w).
const json kQuarterTurnAboutY = {0.0, std::sqrt(0.5), 0.0, std::sqrt(0.5)};
const json kQuarterTurnDownAboutX = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};

json perspective_camera(const std::string& name, double yfov) {
    return {
        {"type", "perspective"},
        {"name", name},
        {"perspective", {{"yfov", yfov}, {"znear", 0.01}, {"zfar", 100.0}, {"aspectRatio", 1.5}}}};
}

json orthographic_camera(const std::string& name) {
    return {{"type", "orthographic"},
            {"name", name},
            {"orthographic", {{"xmag", 2.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 50.0}}}};
}

// The triangle kTriangle (bounds centre (0.5, 0.5, 0)) at node 0, and the nodes and cameras
// given; the scene lists node 0 and `roots`.
GltfBuilder triangle_with(const std::vector<json>& cameras, const std::vector<json>& nodes) {
    GltfBuilder b;
    b.mesh(json::array({{{"attributes", {{"POSITION", b.positions(kTriangle)}}}}}), "M");
    b.node({{"mesh", 0}});
    b.doc["cameras"] = cameras;
    for (const json& node : nodes) {
        b.node(node);
    }
    return b;
}

void expect_vec3_near(const glm::vec3& got, const glm::vec3& expected, const std::string& what) {
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(got[k], expected[k], 1e-5f) << what << "[" << k << "]";
    }
}

bool warned(const Mesh& mesh, const std::string& part) {
    for (const std::string& warning : mesh.warnings) {
        if (warning.find(part) != std::string::npos) {
            return true;
        }
    }
    return false;
}

}  // namespace

// A perspective camera on a rotated, translated node, and an orthographic one on a child of a
// scaled, translated node: eye at the node's origin, looking down its -Z with its +Y up, the
// target at the depth of the mesh's bounds' centre; yfov in degrees.
TEST(GltfCameras, ArePlacedByTheirNodesWorldTransforms) {
    GltfBuilder b = triangle_with(
        {perspective_camera("Front", 0.8), orthographic_camera("Top")},
        {{{"camera", 0}, {"translation", {1.0, 2.0, 3.0}}, {"rotation", kQuarterTurnAboutY}},
         {{"translation", {0.0, 0.0, 5.0}}, {"scale", {2.0, 2.0, 2.0}}, {"children", {3}}},
         {{"camera", 1}, {"translation", {0.0, 1.0, 0.0}}, {"rotation", kQuarterTurnDownAboutX}}});
    const Mesh mesh = load_gltf_text(b.gltf({0, 1, 2}));
    ASSERT_EQ(mesh.cameras.size(), 2u);
    EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();

    const AssetCamera& front = mesh.cameras[0];
    EXPECT_EQ(front.name, "Front");
    EXPECT_EQ(front.projection, CameraProjection::Perspective);
    // A quarter turn about +Y turns -Z to -X; the centre (0.5, 0.5, 0) is 0.5 ahead along -X.
    expect_vec3_near(front.camera.eye, {1, 2, 3}, "front eye");
    expect_vec3_near(front.camera.target, {0.5f, 2, 3}, "front target");
    expect_vec3_near(front.camera.up, {0, 1, 0}, "front up");
    EXPECT_NEAR(front.camera.fov_y, 0.8 * 180.0 / std::numbers::pi, 1e-4);
    EXPECT_FLOAT_EQ(front.aspect_ratio, 1.5f);
    EXPECT_FLOAT_EQ(front.znear, 0.01f);
    EXPECT_FLOAT_EQ(front.zfar, 100.0f);
    EXPECT_NO_THROW(validate_camera(front.camera));

    const AssetCamera& top = mesh.cameras[1];
    EXPECT_EQ(top.name, "Top");
    EXPECT_EQ(top.projection, CameraProjection::Orthographic);
    // The child's (0, 1, 0) scaled by 2 and moved by (0, 0, 5); a quarter turn down about +X
    // looks down -Y with -Z up; the centre is 1.5 below.
    expect_vec3_near(top.camera.eye, {0, 2, 5}, "top eye");
    expect_vec3_near(top.camera.target, {0, 0.5f, 5}, "top target");
    expect_vec3_near(top.camera.up, {0, 0, -1}, "top up");
    EXPECT_FLOAT_EQ(top.znear, 0.1f);
}

// A node holding the mesh and a camera places both by one transform: the camera's eye is where
// the mesh's origin went.
TEST(GltfCameras, ACameraOnAMeshNodeSharesItsTransform) {
    GltfBuilder b;
    b.mesh(json::array({{{"attributes", {{"POSITION", b.positions(kTriangle)}}}}}), "M");
    b.doc["cameras"] = json::array({perspective_camera("", 0.5)});
    b.node({{"translation", {0.0, 1.0, 0.0}}, {"children", {1}}});
    b.node({{"mesh", 0},
            {"camera", 0},
            {"name", "Holder"},
            {"translation", {-2.0, 0.5, 4.0}},
            {"rotation", kQuarterTurnAboutY}});
    const Mesh mesh = load_gltf_text(b.gltf({0}), kUnrefined);
    ASSERT_EQ(mesh.cameras.size(), 1u);
    EXPECT_EQ(mesh.cameras[0].name, "Holder") << "an unnamed camera takes its node's name";
    ASSERT_EQ(mesh.primitives.size(), 1u);
    expect_vec3_near(mesh.cameras[0].camera.eye, mesh.primitives[0].positions[0], "eye");
    // The mesh's +X vertex went to -Z; the camera looks down the turned -Z, along -X.
    expect_vec3_near(mesh.primitives[0].positions[1], {-2, 1.5f, 3}, "vertex (1, 0, 0)");
    const glm::vec3 view =
        glm::normalize(mesh.cameras[0].camera.target - mesh.cameras[0].camera.eye);
    expect_vec3_near(view, {-1, 0, 0}, "view");
}

TEST(GltfCameras, AnAssetWithoutCamerasHasNone) {
    EXPECT_TRUE(load_gltf_text(single_primitive(kTriangle, json::object())).cameras.empty());
    EXPECT_TRUE(load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").cameras.empty());
}

// Hostile cameras are left out, each with a warning naming it, and the geometry loads: a yfov
// of 0 or of pi; a node scaled to nothing; a camera index that does not exist; a position that
// no float holds. An unnamed camera on an unnamed node is "camera N".
TEST(GltfCameras, HostileCamerasAreLeftOutWithAWarning) {
    GltfBuilder b = triangle_with(
        {perspective_camera("Zero", 0.0), perspective_camera("Wide", std::numbers::pi),
         perspective_camera("Flat", 0.5), perspective_camera("", 0.5)},
        {{{"camera", 0}},
         {{"camera", 1}},
         {{"camera", 2}, {"scale", {0.0, 0.0, 0.0}}},
         {{"camera", 7}},
         {{"camera", 3}, {"translation", {0.0, 0.0, 2.0}}}});
    // A position within double's range (the JSON parser refuses numbers beyond it) and beyond
    // float's.
    b.doc["cameras"].push_back(perspective_camera("Far", 0.5));
    b.node({{"camera", 4}, {"translation", {1e300, 0.0, 0.0}}});
    const Mesh mesh = load_gltf_text(b.gltf({0, 1, 2, 3, 4, 5, 6}), kUnrefined);
    ASSERT_EQ(mesh.cameras.size(), 1u);
    EXPECT_EQ(mesh.cameras[0].name, "camera 0");
    expect_vec3_near(mesh.cameras[0].camera.eye, {0, 0, 2}, "the one camera left");
    EXPECT_EQ(mesh.triangle_count, 1u);
    EXPECT_TRUE(warned(mesh, "camera 0 'Zero' of node 1 was left out: its yfov is not in (0, pi)"));
    EXPECT_TRUE(warned(mesh, "camera 1 'Wide' of node 2 was left out: its yfov"));
    EXPECT_TRUE(warned(mesh, "camera 2 'Flat' of node 3 was left out: its node's transform"));
    EXPECT_TRUE(warned(mesh, "camera 7 of node 4 was left out: it does not exist"));
    EXPECT_TRUE(warned(mesh, "camera 4 'Far' of node 6 was left out: its position is beyond"));
    EXPECT_EQ(mesh.warnings.size(), 5u);
}

// Cameras beyond MeshLimits::max_cameras are left out with one warning counting them.
TEST(GltfCameras, CamerasBeyondTheLimitAreLeftOut) {
    GltfBuilder b = triangle_with({perspective_camera("A", 0.5)},
                                  {{{"camera", 0}}, {{"camera", 0}}, {{"camera", 0}}});
    MeshLimits limits;
    limits.max_cameras = 2;
    const Mesh mesh = load_gltf_text(b.gltf({0, 1, 2, 3}), limits);
    EXPECT_EQ(mesh.cameras.size(), 2u);
    EXPECT_TRUE(warned(mesh, "1 camera(s) beyond the limit of 2 were left out"));
    EXPECT_EQ(load_gltf_text(b.gltf({0, 1, 2, 3})).cameras.size(), 3u)
        << "a camera used by three nodes is three views";
}
