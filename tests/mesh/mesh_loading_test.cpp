// Mesh loading: glTF 2.0 (synthetic assets built here, and the samples of assimp-testmodels,
// broken ones included) and OBJ (from memory, and the Stanford bunny of glmark2-data).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "gltf_test_assets.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

// ---------------------------------------------------------------------------------------------
// Format dispatch and limits

TEST(MeshLoading, FormatFromNameIsCaseInsensitiveAndRejectsOthers) {
    EXPECT_EQ(mesh_format_from_name("a/b/Box.GLB"), MeshFormat::Glb);
    EXPECT_EQ(mesh_format_from_name("box.gltf"), MeshFormat::Gltf);
    EXPECT_EQ(mesh_format_from_name("bunny.Obj"), MeshFormat::Obj);
    expect_error([] { mesh_format_from_name("model.fbx"); }, ErrorKind::Unsupported,
                 {"model.fbx", "'.fbx'"});
    expect_error([] { mesh_format_from_name("model"); }, ErrorKind::Unsupported, {"no extension"});
}

TEST(MeshLoading, BytesOverTheLimitAreRejectedBeforeParsing) {
    MeshLimits limits;
    limits.max_bytes = 10;
    expect_error([&] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", limits); },
                 ErrorKind::LimitExceeded, {"test.obj", "more than the limit of 10"});
}

TEST(MeshLoading, MissingFileIsAnIoError) {
    expect_error([] { load_mesh_file("/nonexistent/dir/x.obj"); }, ErrorKind::Io,
                 {"/nonexistent/dir/x.obj"});
}

// ---------------------------------------------------------------------------------------------
// Synthetic glTF

TEST(MeshLoadingGltf, TriangleStripBecomesAListKeepingTheWinding) {
    // A strip of three triangles, all counter-clockwise from +z when read the glTF way.
    const std::vector<glm::vec3> strip{{0, 1, 0}, {0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {2, 1, 0}};
    const Mesh mesh = load_gltf_text(single_primitive(strip, {{"mode", 5}}), kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.primitives.size(), 1u);
    const Primitive& p = mesh.primitives[0];
    EXPECT_EQ(p.indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
    for (std::size_t t = 0; t < 3; ++t) {
        EXPECT_GT(geometric_normal(p, t).z, 0.0f) << "triangle " << t;
    }
    for (const glm::vec3& n : p.normals) {  // computed: no NORMAL in the file
        EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    }
    EXPECT_EQ(mesh.triangle_count, 3u);
}

TEST(MeshLoadingGltf, IndexedTriangleFanBecomesAList) {
    GltfBuilder b;
    const std::vector<glm::vec3> fan{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}};
    const std::vector<std::uint16_t> order{0, 1, 2, 3, 4};
    json primitive = {{"mode", 6}, {"attributes", {{"POSITION", b.positions(fan)}}}};
    primitive["indices"] = b.indices(order, kUnsignedShort);
    b.mesh(json::array({primitive}));
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);
    const Primitive& p = mesh.primitives[0];
    // glTF: fan triangle i is (i + 1, i + 2, 0).
    EXPECT_EQ(p.indices, (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
    for (std::size_t t = 0; t < 3; ++t) {
        EXPECT_GT(geometric_normal(p, t).z, 0.0f) << "triangle " << t;
    }
}

TEST(MeshLoadingGltf, ByteShortAndIntIndicesGiveTheSameTriangles) {
    const std::vector<glm::vec3> quad{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<std::uint32_t> expected{0, 1, 2, 0, 2, 3};
    for (int type : {kUnsignedByte, kUnsignedShort, kUnsignedInt}) {
        GltfBuilder b;
        json primitive = {{"attributes", {{"POSITION", b.positions(quad)}}}};
        if (type == kUnsignedByte) {
            primitive["indices"] = b.indices(std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3}, type);
        } else if (type == kUnsignedShort) {
            primitive["indices"] = b.indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}, type);
        } else {
            primitive["indices"] = b.indices(expected, type);
        }
        b.mesh(json::array({primitive}));
        b.node({{"mesh", 0}});
        const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
        expect_valid(mesh);
        EXPECT_EQ(mesh.primitives[0].indices, expected) << "component type " << type;
    }
}

TEST(MeshLoadingGltf, SignedIndicesAreRejected) {
    GltfBuilder b;
    json primitive = {{"attributes", {{"POSITION", b.positions(kTriangle)}}}};
    primitive["indices"] = b.indices(std::vector<std::int16_t>{0, 1, 2}, 5122);
    b.mesh(json::array({primitive}), "Signed");
    b.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::Unsupported,
                 {"mesh 'Signed' primitive 0: indices", "SCALAR of SHORT"});
}

TEST(MeshLoadingGltf, NodeHierarchyIsBakedIntoPositionsAndNormals) {
    GltfBuilder b;
    const std::vector<glm::vec3> normals{{0, 0, 1}, {0.6f, 0, 0.8f}, {0, 1, 0}};
    json primitive = {
        {"attributes", {{"POSITION", b.positions(kTriangle)}, {"NORMAL", b.positions(normals)}}}};
    b.mesh(json::array({primitive}));
    const double s = std::sqrt(0.5);
    b.node({{"translation", {1, 2, 3}},
            {"rotation", {0, s, 0, s}},  // 90 degrees about +y, (x, y, z, w)
            {"scale", {2, 2, 2}},
            {"children", {1}}});
    // The child: a matrix (column-major), a non-uniform scale (1, 3, 0.5) then a shift.
    b.node({{"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0.5, 0, 0.25, -1, 0.5, 1}}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);

    const glm::dmat4 parent =
        glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)) *
        glm::mat4_cast(glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 1, 0))) *
        glm::scale(glm::dmat4(1.0), glm::dvec3(2));
    glm::dmat4 child(1.0);
    child[0][0] = 1;
    child[1][1] = 3;
    child[2][2] = 0.5;
    child[3] = glm::dvec4(0.25, -1, 0.5, 1);
    const glm::dmat4 world = parent * child;
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    const Primitive& p = mesh.primitives[0];
    ASSERT_EQ(p.positions.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        const glm::dvec3 expected = glm::dvec3(world * glm::dvec4(glm::dvec3(kTriangle[i]), 1.0));
        const glm::dvec3 expected_normal = glm::normalize(normal_matrix * glm::dvec3(normals[i]));
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(p.positions[i][k], expected[k], 1e-5) << "vertex " << i;
            EXPECT_NEAR(p.normals[i][k], expected_normal[k], 1e-5) << "vertex " << i;
        }
    }
    // The rotation maps +x to -z: the triangle's first edge (scaled by 2) runs along -z.
    EXPECT_NEAR(p.positions[1].z - p.positions[0].z, -2.0f, 1e-5f);
}

TEST(MeshLoadingGltf, NegativeScaleFlipsTheWindingBack) {
    GltfBuilder b;
    const std::vector<glm::vec3> normals(3, glm::vec3(0, 0, 1));
    json primitive = {
        {"attributes", {{"POSITION", b.positions(kTriangle)}, {"NORMAL", b.positions(normals)}}}};
    b.mesh(json::array({primitive}));
    b.node({{"mesh", 0}, {"scale", {-1, 1, 1}}});
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf({0, 1}), kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.primitives.size(), 2u);
    const Primitive& mirrored = mesh.primitives[0];
    EXPECT_EQ(mirrored.indices, (std::vector<std::uint32_t>{0, 2, 1}));
    EXPECT_EQ(mirrored.positions[1], glm::vec3(-1, 0, 0));
    EXPECT_GT(glm::dot(geometric_normal(mirrored, 0), mirrored.normals[0]), 0.0f);
    EXPECT_NEAR(mirrored.normals[0].z, 1.0f, 1e-6f);
    const Primitive& plain = mesh.primitives[1];
    EXPECT_EQ(plain.indices, (std::vector<std::uint32_t>{0, 1, 2}));
}

TEST(MeshLoadingGltf, LinesAndPointsAreRejectedNamingThePrimitive) {
    const std::vector<glm::vec3> two_lines{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    expect_error(
        [&] {
            load_gltf_text(single_primitive(two_lines, {{"mode", 1}}, "Wire"));
        },
        ErrorKind::Unsupported,
        {"test.gltf: mesh 'Wire' primitive 0: mode LINES is not supported (only "
         "triangles)"});
    expect_error(
        [&] {
            load_gltf_text(single_primitive(two_lines, {{"mode", 0}}, "Dots"));
        },
        ErrorKind::Unsupported, {"mesh 'Dots' primitive 0: mode POINTS"});
    expect_error(
        [&] {
            load_gltf_text(single_primitive(two_lines, {{"mode", 3}}));
        },
        ErrorKind::Unsupported, {"mode LINE_STRIP"});
    expect_error(
        [&] {
            load_gltf_text(single_primitive(two_lines, {{"mode", 9}}));
        },
        ErrorKind::InvalidInput, {"unknown mode 9"});
}

TEST(MeshLoadingGltf, AccessorRunningPastItsBufferViewIsRejected) {
    GltfBuilder b;
    const int view = b.view(kTriangle.data(), kTriangle.size() * sizeof(glm::vec3));
    const int too_many = b.accessor(view, kFloat, 4, "VEC3");  // 48 bytes from a 36-byte view
    b.mesh(json::array({{{"attributes", {{"POSITION", too_many}}}}}), "Long");
    b.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::InvalidInput,
                 {"mesh 'Long' primitive 0: POSITION: accessor 0",
                  "runs past the end of "
                  "bufferView 0 (36 bytes)"});
    // A stride that makes count * stride overrun the view.
    GltfBuilder c;
    const int strided = c.view(kTriangle.data(), kTriangle.size() * sizeof(glm::vec3), 16);
    c.mesh(json::array({{{"attributes", {{"POSITION", c.accessor(strided, kFloat, 3, "VEC3")}}}}}));
    c.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(c.gltf()); }, ErrorKind::InvalidInput,
                 {"stride 16", "runs past the end of bufferView 0"});
}

TEST(MeshLoadingGltf, BufferViewRunningPastItsBufferIsRejected) {
    GltfBuilder b;
    b.positions(kTriangle);
    b.doc["bufferViews"][0]["byteLength"] = 1000;
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::InvalidInput,
                 {"bufferView 0 (bytes 0 to 1000) runs past the end of buffer 0 (36 bytes)"});
}

TEST(MeshLoadingGltf, WrongAttributeTypesAreRejectedClearly) {
    GltfBuilder b;
    const int positions = b.positions(kTriangle);
    b.doc["accessors"][0]["type"] = "VEC2";
    b.mesh(json::array({{{"attributes", {{"POSITION", positions}}}}}));
    b.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::Unsupported,
                 {"POSITION: accessor 0 is VEC2 of FLOAT; expected VEC3 of FLOAT"});
}

TEST(MeshLoadingGltf, IndexOutOfRangeAndBadCountsAreRejected) {
    GltfBuilder b;
    json primitive = {{"attributes", {{"POSITION", b.positions(kTriangle)}}}};
    primitive["indices"] = b.indices(std::vector<std::uint32_t>{0, 1, 1000}, kUnsignedInt);
    b.mesh(json::array({primitive}), "Far");
    b.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::InvalidInput,
                 {"mesh 'Far' primitive 0: index 1000 out of range (3 vertices)"});

    const std::vector<glm::vec3> four{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    expect_error([&] { load_gltf_text(single_primitive(four, json::object())); },
                 ErrorKind::InvalidInput, {"vertex count 4 is not a multiple of 3"});
}

TEST(MeshLoadingGltf, NonFinitePositionIsRejected) {
    const std::vector<glm::vec3> bad{
        {0, 0, 0}, {1, 0, 0}, {0, std::numeric_limits<float>::quiet_NaN(), 0}};
    expect_error([&] { load_gltf_text(single_primitive(bad, json::object(), "Nan")); },
                 ErrorKind::InvalidInput,
                 {"mesh 'Nan' primitive 0: vertex 2 has a non-finite position"});
}

TEST(MeshLoadingGltf, NodeCycleAndExcessiveDepthAreRejected) {
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"children", {1}}});
    b.node({{"children", {2}}, {"mesh", 0}});
    b.node({{"children", {1}}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::InvalidInput,
                 {"node graph has a cycle at node 1"});

    // No scene at all, every node someone's child.
    json no_scene = json::parse(b.gltf());
    no_scene.erase("scenes");
    no_scene.erase("scene");
    no_scene["nodes"][0]["children"] = {2};
    expect_error([&] { load_gltf_text(no_scene.dump()); }, ErrorKind::InvalidInput,
                 {"node graph has a cycle"});

    GltfBuilder deep;
    deep.positions(kTriangle);
    deep.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    for (int n = 0; n < 100; ++n) {
        deep.node(n + 1 < 100 ? json{{"children", {n + 1}}} : json{{"mesh", 0}});
    }
    expect_error([&] { load_gltf_text(deep.gltf()); }, ErrorKind::LimitExceeded,
                 {"node graph deeper than 64 levels at node 65"});
    MeshLimits generous = kUnrefined;
    generous.max_node_depth = 100;
    EXPECT_EQ(load_gltf_text(deep.gltf(), generous).triangle_count, 1u);
}

TEST(MeshLoadingGltf, NodeWithTwoParentsIsRejected) {
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"children", {2}}});
    b.node({{"children", {2}}});
    b.node({{"mesh", 0}});
    expect_error(
        [&] {
            load_gltf_text(b.gltf({0, 1}));
        },
        ErrorKind::InvalidInput, {"node 2 is reached twice"});
}

TEST(MeshLoadingGltf, ScenesAreChosenAsTheSpecificationSays) {
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"mesh", 0}});
    b.node({{"mesh", 0}, {"translation", {5, 0, 0}}});
    b.node({{"mesh", 0}, {"translation", {0, 7, 0}}, {"children", {1}}});
    // The default scene, not scene 0.
    b.doc["scenes"] = {{{"nodes", {0}}}, {{"nodes", {2}}}};
    b.doc["scene"] = 1;
    Mesh mesh = load_gltf_text(b.gltf());
    ASSERT_EQ(mesh.primitives.size(), 2u);
    EXPECT_EQ(mesh.bounds.min, glm::vec3(0, 7, 0));
    EXPECT_EQ(mesh.bounds.max, glm::vec3(6, 8, 0));
    // No default scene: scene 0.
    b.doc.erase("scene");
    mesh = load_gltf_text(b.gltf());
    EXPECT_EQ(mesh.primitives.size(), 1u);
    // No scenes: every root node (0 and 2, 1 being 2's child).
    b.doc.erase("scenes");
    json d = json::parse(b.gltf());
    d.erase("scenes");
    d.erase("scene");
    mesh = load_gltf_text(d.dump());
    EXPECT_EQ(mesh.primitives.size(), 3u);
}

TEST(MeshLoadingGltf, MaterialsFollowTheGltfDefaults) {
    GltfBuilder b;
    const int positions = b.positions(kTriangle);
    b.doc["materials"] = {{{"name", "Paint"},
                           {"pbrMetallicRoughness",
                            {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}},
                             {"metallicFactor", 0.0},
                             {"roughnessFactor", 0.3}}}}};
    b.mesh(json::array({{{"attributes", {{"POSITION", positions}}}, {"material", 0}},
                        {{"attributes", {{"POSITION", positions}}}}}));
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf());
    expect_valid(mesh);
    ASSERT_EQ(mesh.materials.size(), 2u);
    const Material& paint = mesh.materials[std::size_t(mesh.primitives[0].material)];
    EXPECT_EQ(paint.name, "Paint");
    EXPECT_EQ(paint.base_color, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
    EXPECT_EQ(paint.metallic, 0.0f);
    EXPECT_FLOAT_EQ(paint.roughness, 0.3f);
    EXPECT_TRUE(paint.glossy());
    EXPECT_FALSE(paint.base_color_texture.present());
    const Material& fallback = mesh.materials[std::size_t(mesh.primitives[1].material)];
    EXPECT_EQ(fallback.name, "default (glTF)");
    EXPECT_EQ(fallback.base_color, glm::vec4(1.0f));
    EXPECT_EQ(fallback.metallic, 1.0f);
    EXPECT_EQ(fallback.roughness, 1.0f);
    EXPECT_TRUE(fallback.glossy());
}

TEST(MeshLoadingGltf, BaseColorTextureIsDecodedToRgba8) {
    GltfBuilder b;
    const std::vector<glm::vec2> uv{{0, 0}, {1, 0}, {0, 1}};
    const int positions = b.positions(kTriangle);
    const int texcoords =
        b.accessor(b.view(uv.data(), uv.size() * sizeof(glm::vec2)), kFloat, 3, "VEC2");
    b.doc["images"] = {{{"uri", std::string("data:image/png;base64,") + kTinyPng}}};
    b.doc["textures"] = {{{"source", 0}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.mesh(json::array(
        {{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", texcoords}}}, {"material", 0}},
         {{"attributes", {{"POSITION", positions}}}, {"material", 0}}}));
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.textures.size(), 1u);
    const Texture& t = mesh.textures[0];
    EXPECT_EQ(t.width, 2);
    EXPECT_EQ(t.height, 2);
    EXPECT_EQ(t.rgba, (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255,
                                                 255, 255, 255, 128}));
    EXPECT_EQ(mesh.materials[0].base_color_texture.texture, 0);
    EXPECT_EQ(mesh.primitives[0].texcoords, uv);
    // Without TEXCOORD_0 under a textured material: (0, 0) everywhere.
    EXPECT_EQ(mesh.primitives[1].texcoords, std::vector<glm::vec2>(3, glm::vec2(0.0f)));
}

TEST(MeshLoadingGltf, NormalizedIntegerTexcoordsAreScaled) {
    GltfBuilder b;
    const std::vector<std::uint16_t> uv{0, 0, 65535, 0, 32768, 65535};
    const int positions = b.positions(kTriangle);
    const int texcoords = b.accessor(b.view(uv.data(), uv.size() * 2), kUnsignedShort, 3, "VEC2");
    b.doc["accessors"][std::size_t(texcoords)]["normalized"] = true;
    b.mesh(json::array({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", texcoords}}}}}));
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    const std::vector<glm::vec2>& t = mesh.primitives[0].texcoords;
    ASSERT_EQ(t.size(), 3u);
    EXPECT_EQ(t[1], glm::vec2(1.0f, 0.0f));
    EXPECT_NEAR(t[2].x, 32768.0f / 65535.0f, 1e-7f);
    EXPECT_EQ(t[2].y, 1.0f);
    b.doc["accessors"][std::size_t(texcoords)]["normalized"] = false;
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::InvalidInput,
                 {"TEXCOORD_0: accessor " + std::to_string(texcoords) +
                  " is of UNSIGNED_SHORT and must be normalized"});
}

TEST(MeshLoadingGltf, HugeTextureHeaderIsRejectedByTheLimitBeforeDecoding) {
    GltfBuilder b;
    b.positions(kTriangle);
    b.doc["images"] = {
        {{"uri", "data:image/png;base64," + base64(png_header(1'000'000, 1'000'000))}}};
    b.doc["textures"] = {{{"source", 0}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}, {"material", 0}}}));
    b.node({{"mesh", 0}});
    // A decoder would fail on the missing pixel data; the limit speaks first.
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::LimitExceeded,
                 {"test.gltf: image 0", "1000000x1000000 pixels, more than the limit of 16777216"});
    // Also in a .glb, from a bufferView.
    GltfBuilder g;
    g.positions(kTriangle);
    const std::vector<std::uint8_t> header = png_header(70'000, 70'000);
    g.doc["images"] = {
        {{"bufferView", g.view(header.data(), header.size())}, {"mimeType", "image/png"}}};
    g.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    g.node({{"mesh", 0}});
    const std::vector<std::uint8_t> glb = g.glb();
    expect_error([&] { load_mesh_memory(as_bytes(glb), "t.glb", MeshFormat::Glb); },
                 ErrorKind::LimitExceeded, {"70000x70000"});
}

TEST(MeshLoadingGltf, TotalTexturePixelsAreLimited) {
    GltfBuilder b;
    b.positions(kTriangle);
    const std::string uri = std::string("data:image/png;base64,") + kTinyPng;
    b.doc["images"] = {{{"uri", uri}}, {{"uri", uri}}};
    b.doc["textures"] = {{{"source", 0}}, {{"source", 1}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
                          {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}}};
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}, {"material", 0}},
                        {{"attributes", {{"POSITION", 0}}}, {"material", 1}}}));
    b.node({{"mesh", 0}});
    MeshLimits limits;
    limits.max_total_texture_pixels = 7;  // two 2x2 images need 8
    expect_error([&] { load_gltf_text(b.gltf(), limits); }, ErrorKind::LimitExceeded,
                 {"more than the limit of 7 pixels"});
    limits.max_total_texture_pixels = 8;
    EXPECT_EQ(load_gltf_text(b.gltf(), limits).textures.size(), 2u);
}

TEST(MeshLoadingGltf, OverLimitCountsAreRejected) {
    const std::vector<glm::vec3> quad{{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                      {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::string two_triangles = single_primitive(quad, json::object());
    MeshLimits limits;
    limits.max_triangles = 1;
    expect_error([&] { load_gltf_text(two_triangles, limits); }, ErrorKind::LimitExceeded,
                 {"more than the limit of 1 triangles"});
    limits = {};
    limits.max_vertices = 5;
    expect_error([&] { load_gltf_text(two_triangles, limits); }, ErrorKind::LimitExceeded,
                 {"POSITION", "limit of vertices"});
    // Instances count: one mesh on 3 nodes is 3 primitives.
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    for (int n = 0; n < 3; ++n) {
        b.node({{"mesh", 0}});
    }
    limits = {};
    limits.max_primitives = 2;
    expect_error(
        [&] {
            load_gltf_text(b.gltf({0, 1, 2}), limits);
        },
        ErrorKind::LimitExceeded, {"more than the limit of 2 primitives"});
}

TEST(MeshLoadingGltf, ZeroAndMissingNormalsAreComputedAndCounted) {
    GltfBuilder b;
    const std::vector<glm::vec3> normals{{0, 0, 0}, {0, 0, 2}, {0, 0, 1}};
    b.mesh(json::array(
        {{{"attributes",
           {{"POSITION", b.positions(kTriangle)}, {"NORMAL", b.positions(normals)}}}}}));
    b.node({{"mesh", 0}});
    const Mesh mesh = load_gltf_text(b.gltf());
    expect_valid(mesh);
    EXPECT_EQ(mesh.repairs.normals_replaced, 1u);
    EXPECT_EQ(mesh.repairs.normals_renormalised, 1u);
    for (const glm::vec3& n : mesh.primitives[0].normals) {
        EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    }
}

TEST(MeshLoadingGltf, ExternalFilesAreNeverReadFromMemory) {
    // A real, valid buffer file: if the loader read it, the asset would load.
    const fs::path dir =
        fs::temp_directory_path() / ("oer-mesh-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"mesh", 0}});
    const fs::path bin = dir / "triangle.bin";
    std::ofstream(bin, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.bin.data()), std::streamsize(b.bin.size()));
    json d = json::parse(b.gltf());
    d["buffers"][0]["uri"] = bin.string();
    expect_error([&] { load_gltf_text(d.dump()); }, ErrorKind::Unsupported,
                 {"external file '" + bin.string() +
                  "' referenced by the asset is not allowed: embed buffers as data: URIs or use "
                  ".glb"});
    // Relative, and from a .glb too.
    d["buffers"][0]["uri"] = "triangle.bin";
    expect_error([&] { load_gltf_text(d.dump()); }, ErrorKind::Unsupported,
                 {"external file 'triangle.bin'"});
    // An image by file name.
    json image = json::parse(b.gltf());
    image["images"] = {{{"uri", (dir / "logo.png").string()}}};
    expect_error([&] { load_gltf_text(image.dump()); }, ErrorKind::Unsupported,
                 {"external file '" + (dir / "logo.png").string() + "'"});
    fs::remove_all(dir);
    // A data: URI of a type tinygltf does not decode is not taken for a file name either.
    json webp = json::parse(b.gltf());
    webp["images"] = {{{"uri", "data:image/webp;base64,UklGRg=="}}};
    expect_error([&] { load_gltf_text(webp.dump()); }, ErrorKind::Unsupported,
                 {"unsupported data: URI 'data:image/webp;base64,UklGRg=='"});
}

// A folder of its own under the temporary directory, removed with everything in it.
struct TemporaryFolder {
    explicit TemporaryFolder(const std::string& name)
        : path(fs::temp_directory_path() /
               ("oer-mesh-test-" + name + "-" + std::to_string(::getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TemporaryFolder() { fs::remove_all(path); }
    fs::path path;
};

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary).write(text.data(), std::streamsize(text.size()));
}

TEST(MeshLoadingGltf, ALocalGltfReadsItsFilesInsideItsFolderOnly) {
    TemporaryFolder root("local");
    const fs::path folder = root.path / "asset";
    fs::create_directories(folder / "buffers");
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"mesh", 0}});
    const std::string bin(reinterpret_cast<const char*>(b.bin.data()), b.bin.size());
    write_file(folder / "buffers" / "triangle.bin", bin);
    write_file(root.path / "outside.bin", bin);  // a valid buffer, but outside the folder
    json d = json::parse(b.gltf());
    const auto load_with_uri = [&](const std::string& uri, const MeshLimits& limits = kUnrefined) {
        d["buffers"][0]["uri"] = uri;
        write_file(folder / "triangle.gltf", d.dump());
        return load_mesh_file((folder / "triangle.gltf").string(), limits);
    };

    // Beside it, in a subfolder: read.
    const Mesh mesh = load_with_uri("buffers/triangle.bin");
    expect_valid(mesh);
    EXPECT_EQ(mesh.triangle_count, 1u);
    EXPECT_EQ(mesh.primitives[0].positions[2], kTriangle[2]);
    // The same bytes as an upload: nothing is read (uploads stay self-contained).
    const std::string text = d.dump();
    expect_error(
        [&] {
            load_mesh_memory(std::as_bytes(std::span(text.data(), text.size())), "upload.gltf",
                             MeshFormat::Gltf);
        },
        ErrorKind::Unsupported, {"external file 'buffers/triangle.bin'"});

    // Out of the folder by "..", by an absolute path, and by a symbolic link inside it.
    const std::string outside = fs::canonical(folder).string();
    expect_error([&] { load_with_uri("../outside.bin"); }, ErrorKind::InvalidInput,
                 {"triangle.gltf: the file '../outside.bin' it references lies outside " + outside +
                  " (no file outside"});
    expect_error([&] { load_with_uri((root.path / "outside.bin").string()); },
                 ErrorKind::InvalidInput,
                 {"the file '" + (root.path / "outside.bin").string() +
                  "' it references is an absolute path: files are named relative to " + outside});
    fs::create_symlink(root.path / "outside.bin", folder / "link.bin");
    expect_error([&] { load_with_uri("link.bin"); }, ErrorKind::InvalidInput,
                 {"the file 'link.bin' it references lies outside " + outside});
    // A link that stays inside the folder is followed.
    fs::create_symlink(folder / "buffers" / "triangle.bin", folder / "inside-link.bin");
    EXPECT_EQ(load_with_uri("inside-link.bin").triangle_count, 1u);
    // Missing, and a URI with a scheme.
    expect_error([&] { load_with_uri("missing.bin"); }, ErrorKind::Io,
                 {"the file 'missing.bin' it references does not exist in " + outside});
    expect_error([&] { load_with_uri("file:///etc/passwd"); }, ErrorKind::InvalidInput,
                 {"the file 'file:///etc/passwd' it references is a URL, not a file name"});
    // Its files count against the limit on bytes, and none is read past it.
    MeshLimits small;
    small.max_bytes = 1024;
    ASSERT_LT(d.dump().size(), small.max_bytes);
    write_file(folder / "buffers" / "large.bin", std::string(4096, '\0'));
    d["buffers"][0]["byteLength"] = 4096;
    expect_error([&] { load_with_uri("buffers/large.bin", small); }, ErrorKind::LimitExceeded,
                 {"the file '",
                  "large.bin' it references would take the asset's files over the "
                  "limit of 1024 bytes"});
}

TEST(MeshLoadingGltf, GlbLoadsLikeGltfAndCorruptContainersAreRejected) {
    GltfBuilder b;
    const std::vector<glm::vec3> strip{{0, 1, 0}, {0, 0, 0}, {1, 1, 0}, {1, 0, 0}};
    b.mesh(json::array({{{"attributes", {{"POSITION", b.positions(strip)}}}, {"mode", 5}}}));
    b.node({{"mesh", 0}});
    const std::vector<std::uint8_t> glb = b.glb();
    const Mesh mesh = load_mesh_memory(as_bytes(glb), "t.glb", MeshFormat::Glb, kUnrefined);
    expect_valid(mesh);
    EXPECT_EQ(mesh.primitives[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}));

    // The BIN chunk claims to reach past the file's end (tinygltf alone would read 8 bytes
    // beyond it).
    std::vector<std::uint8_t> long_bin = glb;
    const std::size_t json_length = long_bin[12] | (long_bin[13] << 8);
    const std::size_t bin_header = 20 + json_length;
    const std::uint32_t claimed = std::uint32_t(long_bin.size() - 20 - json_length);
    std::memcpy(&long_bin[bin_header], &claimed, 4);
    expect_error([&] { load_mesh_memory(as_bytes(long_bin), "t.glb", MeshFormat::Glb); },
                 ErrorKind::InvalidInput, {"BIN chunk runs past the end"});
    for (std::size_t size :
         {std::size_t(0), std::size_t(10), std::size_t(30), glb.size() / 2, glb.size() - 4}) {
        std::vector<std::uint8_t> cut(glb.begin(), glb.begin() + std::ptrdiff_t(size));
        EXPECT_THROW(load_mesh_memory(as_bytes(cut), "t.glb", MeshFormat::Glb), Error) << size;
    }
    const std::string text = "{\"asset\": {\"version\": \"2.0\"}}";
    expect_error([&] { load_mesh_memory(as_bytes(text), "t.glb", MeshFormat::Glb); },
                 ErrorKind::InvalidInput, {"no 'glTF' header"});
}

TEST(MeshLoadingGltf, GarbageAndDeeplyNestedJsonAreRejected) {
    expect_error([] { load_gltf_text("this is not json"); }, ErrorKind::InvalidInput,
                 {"test.gltf: not valid JSON", "line 1, column 2"});
    // Found by tests/fuzz/fuzz_gltf: the JSON parser's message quotes the bytes it stopped at,
    // which the service's problem body could not hold when they are not UTF-8 (a 500).
    try {
        load_gltf_text("{\"asset\": \x83}");
        ADD_FAILURE() << "loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("\\x83"), std::string::npos) << e.what();
        EXPECT_NO_THROW((void)nlohmann::json(std::string(e.what())).dump());
    }
    // Valid JSON, but not what tinygltf needs.
    expect_error([] { load_gltf_text("{\"asset\": 5}"); }, ErrorKind::InvalidInput,
                 {"not a valid glTF 2.0 asset", "asset"});
    expect_error([] { load_gltf_text("{\"asset\": {\"version\": \"1.0\"}}"); },
                 ErrorKind::Unsupported, {"glTF version '1.0'"});
    expect_error([] { load_gltf_text("{\"asset\": {\"version\": \"2.0\"}}"); },
                 ErrorKind::InvalidInput, {"no triangles"});
    const std::string deep =
        "{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + std::string(100000, '[') +
        std::string(100000, ']') + "}";
    expect_error([&] { load_gltf_text(deep); }, ErrorKind::InvalidInput,
                 {"nested more than 128 levels"});
    expect_error(
        [] {
            load_gltf_text(
                "{\"asset\": {\"version\": \"2.0\"}, \"extensionsRequired\": "
                "[\"KHR_texture_basisu\"]}");
        },
        ErrorKind::Unsupported,
        {"requires the extension KHR_texture_basisu", "export them as WebP (glTF-Transform"});
}

// ---------------------------------------------------------------------------------------------
// glTF samples of assimp-testmodels, valid and broken

TEST(MeshLoadingAssimpSamples, BoxTexturedBinaryLoadsWithItsTexture) {
    REQUIRE_ASSIMP_SAMPLES();
    const Mesh mesh = load_sample("BoxTextured-glTF-Binary/BoxTextured.glb");
    expect_valid(mesh);
    // The file's 12 triangles and 24 vertices, refined (mesh_refinement.hpp): 16 x 16 squares of
    // 2 triangles on each face, 17 x 17 vertices.
    EXPECT_EQ(mesh.triangle_count, 6u * 16u * 16u * 2u);
    EXPECT_EQ(mesh.vertex_count, 6u * 17u * 17u);
    ASSERT_EQ(mesh.textures.size(), 1u);
    EXPECT_EQ(mesh.textures[0].width, 211);  // CesiumLogoFlat.png
    EXPECT_EQ(mesh.textures[0].height, 211);
    EXPECT_EQ(mesh.textures[0].rgba.size(), 211u * 211u * 4u);
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].name, "Texture");
    EXPECT_EQ(mesh.materials[0].base_color_texture.texture, 0);
    EXPECT_EQ(mesh.materials[0].metallic, 0.0f);
    EXPECT_EQ(mesh.primitives[0].texcoords.size(), mesh.vertex_count);
    // The root node turns the Z-up box Y-up; the box stays the unit cube.
    EXPECT_EQ(mesh.bounds.min, glm::vec3(-0.5f));
    EXPECT_EQ(mesh.bounds.max, glm::vec3(0.5f));
    EXPECT_EQ(mesh.repairs.normals_replaced, 0u);
    // Every face's normals point out of the box and agree with its winding.
    const Primitive& p = mesh.primitives[0];
    for (std::size_t t = 0; t < p.indices.size() / 3; ++t) {
        const glm::vec3 g = geometric_normal(p, t);
        const glm::vec3 centre =
            (p.positions[p.indices[3 * t]] + p.positions[p.indices[3 * t + 1]] +
             p.positions[p.indices[3 * t + 2]]) /
            3.0f;
        EXPECT_GT(glm::dot(g, centre), 0.0f) << "triangle " << t;
        EXPECT_GT(glm::dot(g, p.normals[p.indices[3 * t]]), 0.0f) << "triangle " << t;
    }
}

TEST(MeshLoadingAssimpSamples, BoxTexturedEmbeddedLoadsTheSame) {
    REQUIRE_ASSIMP_SAMPLES();
    const Mesh glb = load_sample("BoxTextured-glTF-Binary/BoxTextured.glb");
    const Mesh gltf = load_sample("BoxTextured-glTF-Embedded/BoxTextured.gltf");
    expect_valid(gltf);
    EXPECT_EQ(gltf.triangle_count, 6u * 16u * 16u * 2u);  // refined as the .glb's
    ASSERT_EQ(gltf.textures.size(), 1u);
    EXPECT_EQ(gltf.textures[0].width, 211);
    EXPECT_EQ(gltf.textures[0].rgba, glb.textures[0].rgba);
    EXPECT_EQ(gltf.primitives[0].positions, glb.primitives[0].positions);
    EXPECT_EQ(gltf.primitives[0].indices, glb.primitives[0].indices);
    EXPECT_EQ(gltf.primitives[0].texcoords, glb.primitives[0].texcoords);
}

TEST(MeshLoadingAssimpSamples, ALocalGltfLoadsItsBufferAndImageBesideIt) {
    REQUIRE_ASSIMP_SAMPLES();
    // BoxTextured-glTF: a .bin and a .png beside the .gltf, read from its folder; the same as
    // the asset with both embedded.
    const Mesh local = load_sample("BoxTextured-glTF/BoxTextured.gltf");
    const Mesh mesh =
        load_gltf_text(embedded("BoxTextured-glTF/BoxTextured.gltf", {"BoxTextured-glTF"}));
    EXPECT_EQ(local.triangle_count, 6u * 16u * 16u * 2u);  // refined as the .glb's
    ASSERT_EQ(local.textures.size(), 1u);
    EXPECT_EQ(local.textures[0].rgba, mesh.textures[0].rgba);
    EXPECT_EQ(local.primitives[0].positions, mesh.primitives[0].positions);
    // MissingBin: the .bin it names does not exist.
    expect_error([] { load_sample("MissingBin/BoxTextured.gltf"); }, ErrorKind::Io,
                 {"BoxTextured.gltf: the file 'BoxTextured0.bin' it references does not exist"});
    // Uploaded as bytes, the local asset names its first external file.
    const std::string text = [] {
        std::ifstream file(kAssimpGltf / "BoxTextured-glTF/BoxTextured.gltf");
        return std::string(std::istreambuf_iterator<char>(file), {});
    }();
    expect_error([&] { load_gltf_text(text); }, ErrorKind::Unsupported,
                 {"external file 'BoxTextured0.bin' referenced by the asset is not allowed: "
                  "embed buffers as data: URIs or use .glb"});
}

TEST(MeshLoadingAssimpSamples, IndexOutOfRangeIsRejectedNamingThePrimitive) {
    REQUIRE_ASSIMP_SAMPLES();
    expect_error([] { load_sample("IndexOutOfRange/IndexOutOfRange.gltf"); },
                 ErrorKind::InvalidInput,
                 {"mesh 'Mesh' primitive 0: index 255 out of range (24 vertices)"});
    expect_error(
        [] {
            load_gltf_text(embedded("IndexOutOfRange/IndexOutOfRange.gltf", {"IndexOutOfRange"}));
        },
        ErrorKind::InvalidInput, {"mesh 'Mesh' primitive 0: index 255 out of range (24 vertices)"});
    expect_error(
        [] {
            load_gltf_text(
                embedded("IndexOutOfRange/AllIndicesOutOfRange.gltf", {"IndexOutOfRange"}));
        },
        ErrorKind::InvalidInput, {"mesh 'Mesh' primitive 0: index 65535 out of range"});
}

TEST(MeshLoadingAssimpSamples, BoxWithInfinitesIsRejected) {
    REQUIRE_ASSIMP_SAMPLES();
    expect_error([] { load_sample("BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"); },
                 ErrorKind::InvalidInput,
                 {"mesh 'Mesh' primitive 0: vertex 0 has a non-finite position (-inf"});
}

TEST(MeshLoadingAssimpSamples, BoxBadNormalsLoadsWithRepairedNormals) {
    REQUIRE_ASSIMP_SAMPLES();
    const Mesh mesh = load_sample("BoxBadNormals-glTF-Binary/BoxBadNormals.glb");
    expect_valid(mesh);
    EXPECT_EQ(mesh.triangle_count, 6u * 16u * 16u * 2u);  // 12, refined as BoxTextured's
    // Four zero normals (one face) computed, four of length 0.1 (another face) normalised.
    EXPECT_EQ(mesh.repairs.normals_replaced, 4u);
    EXPECT_EQ(mesh.repairs.normals_renormalised, 4u);
    // Every normal now agrees with its faces' winding and points out of the box.
    const Primitive& p = mesh.primitives[0];
    for (std::size_t t = 0; t < p.indices.size() / 3; ++t) {
        const glm::vec3 g = glm::normalize(geometric_normal(p, t));
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(glm::dot(g, p.normals[p.indices[3 * t + k]]), 1.0f, 1e-5f)
                << "triangle " << t;
        }
    }
}

TEST(MeshLoadingAssimpSamples, RecursiveNodesIsRejectedAsACycle) {
    REQUIRE_ASSIMP_SAMPLES();
    expect_error([] { load_sample("RecursiveNodes/RecursiveNodes.gltf"); }, ErrorKind::InvalidInput,
                 {"node graph has a cycle at node 0"});
}

TEST(MeshLoadingAssimpSamples, IncorrectVertexArraysIsRejected) {
    REQUIRE_ASSIMP_SAMPLES();
    // Node 1's mesh has 35 vertices in mode TRIANGLES (node 0's cube is fine); read from its
    // folder or embedded, the same error.
    expect_error([] { load_sample("IncorrectVertexArrays/Cube.gltf"); }, ErrorKind::InvalidInput,
                 {"mesh 'TruncatedCube' primitive 0: vertex count 35 is not a multiple of 3"});
    expect_error(
        [] {
            load_gltf_text(embedded("IncorrectVertexArrays/Cube.gltf", {"IncorrectVertexArrays"}));
        },
        ErrorKind::InvalidInput,
        {"mesh 'TruncatedCube' primitive 0: vertex count 35 is not a multiple of 3"});
}

// Required glTF properties that are absent, or of the wrong shape without a wrong type, are
// named with their path (the samples above cover wrong types).
TEST(MeshLoadingGltf, MissingOrMisshapenPropertiesAreNamed) {
    const std::string asset = R"("asset": {"version": "2.0"})";
    const std::map<std::string, std::string> expected{
        {R"("materials": [{"normalTexture": {"scale": 1}}])",
         "invalid glTF: materials[0].normalTexture.index is required"},
        {R"("meshes": [{}])", "invalid glTF: meshes[0].primitives must be a non-empty array"},
        {R"("meshes": [{"primitives": [{}]}])",
         "invalid glTF: meshes[0].primitives[0].attributes must be an object"},
        {R"("nodes": [{"matrix": [1, 0, 0, 1]}])",
         "invalid glTF: nodes[0].matrix must be an array of 16 numbers"},
    };
    for (const auto& [members, message] : expected) {
        SCOPED_TRACE(members);
        expect_error(
            [&, &members = members] { load_gltf_text("{" + asset + ", " + members + "}"); },
            ErrorKind::InvalidInput, {"test.gltf: " + message});
    }
}

TEST(MeshLoadingAssimpSamples, SchemaFailuresAreRejected) {
    REQUIRE_ASSIMP_SAMPLES();
    // tinygltf alone would take scene 0 instead; the schema check names the property (before
    // the external .bin, which is not even shipped beside it, is noticed).
    expect_error([] { load_sample("SchemaFailures/sceneWrongType.gltf"); }, ErrorKind::InvalidInput,
                 {"sceneWrongType.gltf: invalid glTF: scene must be a non-negative integer, not a "
                  "string"});
}

TEST(MeshLoadingAssimpSamples, WrongTypesAreRejectedNamingTheProperty) {
    REQUIRE_ASSIMP_SAMPLES();
    // tinygltf loads all six, replacing the flawed property by its default.
    const std::map<std::string, std::string> expected{
        {"badArray", "meshes[0].primitives must be a non-empty array, not an object"},
        {"badExtension",
         "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform "
         "must be an object, not a string"},
        {"badNumber", "materials[0].normalTexture.scale must be a number, not a string"},
        {"badObject", "materials[0].pbrMetallicRoughness must be an object, not an array"},
        {"badString", "scenes[0].name must be a string, not 42"},
        {"badUint",
         "materials[0].pbrMetallicRoughness.baseColorTexture.index must be a non-negative "
         "integer, not -1"},
    };
    for (const auto& [file, message] : expected) {
        const std::string relative = "wrongTypes/" + file + ".gltf";
        expect_error([&] { load_sample(relative); }, ErrorKind::InvalidInput,
                     {file + ".gltf: invalid glTF: " + message});
        // Embedded, the same.
        expect_error([&] { load_gltf_text(embedded(relative, {"wrongTypes"})); },
                     ErrorKind::InvalidInput, {message});
    }
}

TEST(MeshLoadingAssimpSamples, PrimitiveModesOfTheAssetGenerator) {
    REQUIRE_ASSIMP_SAMPLES();
    const std::string dir = "glTF-Asset-Generator/Mesh_PrimitiveMode";
    const std::map<int, std::string> rejected{
        {0, "POINTS"}, {1, "LINES"}, {2, "LINE_LOOP"}, {3, "LINE_STRIP"},
        {7, "POINTS"}, {8, "LINES"}, {9, "LINE_LOOP"}, {10, "LINE_STRIP"}};
    for (int n = 0; n <= 15; ++n) {
        const std::string file =
            dir + "/Mesh_PrimitiveMode_" + (n < 10 ? "0" : "") + std::to_string(n) + ".gltf";
        const std::string text = embedded(file, {dir});
        if (rejected.contains(n)) {
            expect_error([&] { load_gltf_text(text); }, ErrorKind::Unsupported,
                         {"mode " + rejected.at(n) + " is not supported (only triangles)"});
            continue;
        }
        // Strips, fans and lists of one quad facing +z: two triangles, wound to face +z.
        const Mesh mesh = load_gltf_text(text, kUnrefined);
        expect_valid(mesh);
        EXPECT_EQ(mesh.triangle_count, 2u) << file;
        const Primitive& p = mesh.primitives[0];
        for (std::size_t t = 0; t < 2; ++t) {
            EXPECT_GT(geometric_normal(p, t).z, 0.0f) << file << " triangle " << t;
            EXPECT_GT(glm::dot(geometric_normal(p, t), p.normals[p.indices[3 * t]]), 0.0f) << file;
        }
    }
}

TEST(MeshLoadingAssimpSamples, LargerBinarySampleLoads) {
    REQUIRE_ASSIMP_SAMPLES();
    const Mesh mesh = load_sample("2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    expect_valid(mesh);
    EXPECT_GT(mesh.triangle_count, 10000u);
    EXPECT_GT(mesh.primitives.size(), 10u);
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST(MeshLoadingObj, QuadIsTriangulatedWithTheDefaultLambertianMaterial) {
    const Mesh mesh = load_obj_text(
        "# a unit quad facing +z\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "f 1 2 3 4\n",
        kUnrefined);
    expect_valid(mesh);
    EXPECT_EQ(mesh.triangle_count, 2u);
    EXPECT_EQ(mesh.vertex_count, 4u);
    ASSERT_EQ(mesh.materials.size(), 1u);
    const Material& m = mesh.materials[0];
    EXPECT_EQ(m.name, "default (OBJ)");
    EXPECT_EQ(m.base_color, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    EXPECT_FALSE(m.glossy());
    EXPECT_FALSE(m.base_color_texture.present());
    const Primitive& p = mesh.primitives[0];
    for (std::size_t t = 0; t < 2; ++t) {
        EXPECT_GT(geometric_normal(p, t).z, 0.0f);
    }
    for (const glm::vec3& n : p.normals) {
        EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    }
    EXPECT_TRUE(p.texcoords.empty());
}

TEST(MeshLoadingObj, RelativeIndicesAndFileNormalsAndTexcoords) {
    const Mesh mesh = load_obj_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 0 1\n"
        "vn 0 0 2\n"
        "f -3/-3/-1 -2/-2/-1 -1/-1/-1\n"
        "v 5 0 0\nv 6 0 0\nv 5 1 0\n"
        "f -3//1 -2//1 -1//1\n",
        kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.primitives.size(), 1u);
    const Primitive& p = mesh.primitives[0];
    EXPECT_EQ(mesh.triangle_count, 2u);
    ASSERT_EQ(p.positions.size(), 6u);  // six distinct (position, normal, texcoord) triples
    EXPECT_EQ(p.positions[3], glm::vec3(5, 0, 0));
    EXPECT_EQ(p.positions[5], glm::vec3(5, 1, 0));
    // Texture coordinates on some corners only: dropped.
    EXPECT_TRUE(p.texcoords.empty());
    EXPECT_FALSE(mesh.warnings.empty());
    // The file's normal, normalised (and counted once per vertex that uses it).
    for (const glm::vec3& n : p.normals) {
        EXPECT_EQ(n, glm::vec3(0, 0, 1));
    }
    EXPECT_EQ(mesh.repairs.normals_renormalised, 6u);

    const Mesh textured = load_obj_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0.5 1\nf 1/1 2/2 3/3\n", kUnrefined);
    EXPECT_EQ(textured.primitives[0].texcoords,
              (std::vector<glm::vec2>{{0, 0}, {1, 0}, {0.5f, 1}}));
}

TEST(MeshLoadingObj, SharedCornersAreOneVertexAndSplitNormalsAreTwo) {
    // Two triangles sharing an edge: 4 vertices; with different normals on the shared edge: 6.
    const Mesh smooth =
        load_obj_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n", kUnrefined);
    EXPECT_EQ(smooth.vertex_count, 4u);
    const Mesh split = load_obj_text(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0.6 0.8\n"
        "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n",
        kUnrefined);
    EXPECT_EQ(split.vertex_count, 6u);
    EXPECT_EQ(split.repairs.normals_renormalised, 0u);
}

TEST(MeshLoadingObj, MissingNormalsAreAngleWeighted) {
    // A 1 x 2 x 3 box of 8 shared corners and 6 quads, each split into 2 triangles by
    // tinyobjloader. Every face meets every corner at a right angle, so angle weighting gives
    // each corner the normalised sum of its three face normals, (+-1, +-1, +-1) / sqrt 3;
    // weighting by area (or counting triangles) would not, the faces and splits differing.
    const Mesh mesh = load_obj_text(
        "v 0 0 0\nv 1 0 0\nv 1 2 0\nv 0 2 0\nv 0 0 3\nv 1 0 3\nv 1 2 3\nv 0 2 3\n"
        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n",
        kUnrefined);
    expect_valid(mesh);
    EXPECT_EQ(mesh.triangle_count, 12u);
    const Primitive& p = mesh.primitives[0];
    ASSERT_EQ(p.positions.size(), 8u);
    const glm::vec3 centre(0.5f, 1.0f, 1.5f);
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
        const glm::vec3 outward = glm::sign(p.positions[i] - centre) / std::sqrt(3.0f);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(p.normals[i][k], outward[k], 1e-5f) << "corner " << i;
        }
    }
    // The faces are wound outward: the signed volume is the box's.
    double volume = 0.0;
    for (std::size_t t = 0; t < p.indices.size(); t += 3) {
        volume += glm::dot(p.positions[p.indices[t]], glm::cross(p.positions[p.indices[t + 1]],
                                                                 p.positions[p.indices[t + 2]])) /
                  6.0;
    }
    EXPECT_NEAR(volume, 6.0, 1e-5);
}

TEST(MeshLoadingObj, IndexOutOfRangeIsRejected) {
    expect_error(
        [] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"); }, ErrorKind::InvalidInput,
        {"test.obj: shape 0 triangle 0: refers to vertex 7, out of range: the file has 3"});
    expect_error([] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"); },
                 ErrorKind::InvalidInput, {"before the first one"});
    // In a quad, tinyobjloader drops the face with a warning: still an error here.
    expect_error([] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 9 3\n"); },
                 ErrorKind::InvalidInput, {"out of range"});
    expect_error([] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n"); },
                 ErrorKind::InvalidInput, {"refers to normal 2, out of range: the file has 1"});
    expect_error([] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"); },
                 ErrorKind::InvalidInput, {"not a valid OBJ file"});
}

// tinyobjloader reads indices into an int: 4294967297 would wrap to 1, a valid vertex, and
// 2147483648 to the most negative int. Every index beyond 31 bits is refused by its line,
// whether a position's, a texture coordinate's or a normal's, relative or not.
TEST(MeshLoadingObj, IndicesBeyond31BitsAreRejectedNotWrapped) {
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
    for (const std::string face :
         {"f 1 2 4294967297", "f 1 2 2147483648", "f 1/4294967297 2/1 3/1",
          "f 1//1 2//1 3//4294967297", "f -1 -2 -4294967299", "f 1 2 99999999999999999999999"}) {
        expect_error([&] { load_obj_text(triangle + face + "\n"); }, ErrorKind::InvalidInput,
                     {"line 6: a face index beyond the largest an OBJ index may be (2147483647)"});
    }
    // The largest index that fits is out of range of this file, and said so as before.
    expect_error([&] { load_obj_text(triangle + "f 1 2 2147483647\n"); }, ErrorKind::InvalidInput,
                 {"out of range"});
}

TEST(MeshLoadingObj, MtllibIsNeverRead) {
    // A real material file that would paint the triangle red, if it were read.
    const fs::path dir =
        fs::temp_directory_path() / ("oer-mesh-mtl-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path mtl = dir / "evil.mtl";
    std::ofstream(mtl) << "newmtl red\nKd 1 0 0\n";
    const Mesh mesh = load_obj_text("mtllib " + mtl.string() +
                                    "\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::remove_all(dir);
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].name, "default (OBJ)");
    EXPECT_EQ(mesh.materials[0].base_color, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    ASSERT_FALSE(mesh.warnings.empty());
    EXPECT_NE(mesh.warnings[0].find("mtllib '" + mtl.string() + "' ignored"), std::string::npos)
        << mesh.warnings[0];
}

// Found by tests/fuzz/fuzz_obj: an mtllib name that is not UTF-8 was quoted as is in the mesh's
// warnings, which the service's answer (JSON) could not hold: the upload was a 500. Such bytes
// are escaped as \xNN, and a long name is cut between characters.
TEST(MeshLoadingObj, WarningsEscapeBytesThatAreNotUtf8) {
    const std::string triangle = "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const Mesh mesh = load_obj_text("mtllib \x8droduct.mtl" + triangle);
    ASSERT_FALSE(mesh.warnings.empty());
    EXPECT_NE(mesh.warnings[0].find("mtllib '\\x8Droduct.mtl' ignored"), std::string::npos)
        << mesh.warnings[0];
    EXPECT_NO_THROW((void)nlohmann::json(mesh.warnings).dump());
    // 150 two-byte characters (300 bytes), quoted up to 200 bytes: 100 characters and "...".
    std::string accented;
    for (int i = 0; i < 150; ++i) {
        accented += "\u00e9";
    }
    const Mesh long_name = load_obj_text("mtllib " + accented + triangle);
    ASSERT_FALSE(long_name.warnings.empty());
    EXPECT_NE(long_name.warnings[0].find("mtllib '" + accented.substr(0, 200) + "...'"),
              std::string::npos)
        << long_name.warnings[0];
    EXPECT_NO_THROW((void)nlohmann::json(long_name.warnings).dump());
}

TEST(MeshLoadingObj, GarbageAndEmptyFilesGiveClearErrors) {
    expect_error([] { load_obj_text(""); }, ErrorKind::InvalidInput, {"test.obj", "empty"});
    expect_error([] { load_obj_text("# nothing but a comment\n\n"); }, ErrorKind::InvalidInput,
                 {"test.obj: the asset has no triangles"});
    expect_error([] { load_obj_text("v 0 0 0\nv 1 0 0\nl 1 2\n"); }, ErrorKind::InvalidInput,
                 {"no triangles"});
    std::mt19937 random(12345);
    for (int trial = 0; trial < 20; ++trial) {
        std::string garbage(4096, '\0');
        for (char& c : garbage) {
            c = char(random() & 0xff);
        }
        if (trial % 2 == 1) {  // lines that look like commands, with nonsense in them
            garbage += "\nf 1 2 x\nv nan inf 1\nf 1/2/3 -7 99999999999\nvn\nvt 1\n";
        }
        EXPECT_THROW(load_obj_text(garbage), Error) << "trial " << trial;
    }
    // A number too large for a float (tinyobjloader reads "nan" as 0, but this as infinity).
    expect_error([] { load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e999 0 0\nf 1 2 4\n"); },
                 ErrorKind::InvalidInput, {"shape 0: vertex 2 has a non-finite position (inf"});
}

TEST(MeshLoadingObj, CountsAreLimitedBeforeParsing) {
    MeshLimits limits;
    limits.max_triangles = 2;
    expect_error(
        [&] {
            load_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 2 0\nf 1 2 3 4 5\n", limits);
        },
        ErrorKind::LimitExceeded, {"3 triangles, more than the limit of 2"});
    std::string huge_face = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
    for (int i = 0; i < 300; ++i) {
        huge_face += ' ';
        huge_face += std::to_string(1 + i % 3);
    }
    expect_error([&] { load_obj_text(huge_face); }, ErrorKind::Unsupported,
                 {"line 4: a face of 300 vertices"});
    // Lines may end with a lone "\r", as tinyobjloader reads them: counted the same way.
    std::string mac = huge_face;
    std::replace(mac.begin(), mac.end(), '\n', '\r');
    expect_error([&] { load_obj_text(mac); }, ErrorKind::Unsupported,
                 {"line 4: a face of 300 vertices"});
    expect_error(
        [&] {
            load_obj_text("v 0 0 0\rv 1 0 0\rv 0 1 0\rv 1 1 0\rf 1 2 3\rf 2 4 3\r\nf 1 2 4\r",
                          limits);
        },
        ErrorKind::LimitExceeded, {"3 triangles, more than the limit of 2"});
}

// ---------------------------------------------------------------------------------------------
// The Stanford bunny (glmark2-data)

TEST(MeshLoadingBunny, LoadsWithComputedUnitNormalsAndFiniteBounds) {
    const std::string path = "/usr/share/glmark2/models/bunny.obj";
    if (!fs::exists(path)) {
        GTEST_SKIP() << "*** glmark2-data is not installed: no " << path
                     << "; loading a real OBJ is NOT tested ***";
    }
    const Mesh mesh = load_mesh_file(path);
    expect_valid(mesh);
    // The file: 34,835 'v' lines and 69,666 triangular 'f' lines, no normals or texcoords; its
    // few edges longer than 1/16 of the diagonal split by the refinement (mesh_refinement.hpp).
    EXPECT_EQ(mesh.triangle_count, 69666u + 6u);
    EXPECT_EQ(mesh.vertex_count, 34835u + 3u);
    EXPECT_EQ(mesh.primitives.size(), 1u);
    EXPECT_TRUE(mesh.primitives[0].texcoords.empty());
    EXPECT_EQ(mesh.materials[0].name, "default (OBJ)");
    // Bounds (also recomputed in expect_valid): the file is scaled to x in [-1, 1], centred.
    EXPECT_EQ(mesh.bounds.min.x, -1.0f);
    EXPECT_EQ(mesh.bounds.max.x, 1.0f);
    EXPECT_NEAR(mesh.bounds.min.y, -0.991233f, 1e-6f);
    EXPECT_NEAR(mesh.bounds.max.y, 0.991233f, 1e-6f);
    EXPECT_NEAR(mesh.bounds.min.z, -0.775047f, 1e-6f);
    EXPECT_NEAR(mesh.bounds.max.z, 0.775047f, 1e-6f);
    // Most of the computed normals point away from the centre of the (star-shaped-ish) bunny.
    const glm::vec3 centre = mesh.bounds.centre();
    std::size_t outward = 0;
    const Primitive& p = mesh.primitives[0];
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
        outward += glm::dot(p.normals[i], p.positions[i] - centre) > 0.0f ? 1 : 0;
    }
    EXPECT_GT(double(outward) / double(p.positions.size()), 0.8);
}

}  // namespace
