// KHR_materials_variants over HTTP: a product's own variants listed with the mesh, chosen by
// name (variant=NAME, objects[i].variant), drawn exactly as the same asset with the variant's
// materials baked in, changing only what its materials cover, and re-weighing the upload's
// transfer instead of baking another.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <string>

#include "../mesh/gltf_test_assets.hpp"
#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

std::string product_glb(std::optional<int> baked_body = std::nullopt) {
    const std::vector<std::uint8_t> bytes = mesh_testing::variants_product(baked_body).glb();
    return std::string(bytes.begin(), bytes.end());
}

std::string upload_prepared(httplib::Client& client, const std::string& glb) {
    const Json mesh = upload_mesh(client, glb, "model/gltf-binary");
    EXPECT_TRUE(mesh.is_object());
    const std::string id = mesh.is_object() ? mesh.value("id", "") : "";
    EXPECT_EQ(wait_for_preparation(client, id), "ready");
    return id;
}

// A still camera on the axis x = 0: the body (x < -0.1) lands in the left half of the frame,
// the stand (x > 0.1) in the right half.
std::string frame_path(const std::string& mesh, const std::string& extra = "") {
    return "/v1/render?environment=default&mesh=" + mesh +
           "&width=96&height=64&format=png&samples=1&eye=0,1.2,3&target=0,0.4,0" + extra;
}

}  // namespace

TEST(Variants, AreListedWithTheMeshAndRefusedByNameWhenUnknown) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string mesh = upload_prepared(*client, product_glb());
    const Json described =
        expect_conforms("GET", "/v1/meshes/{id}", client->Get(("/v1/meshes/" + mesh).c_str()));
    ASSERT_EQ(described.at("variants").size(), 3u);
    EXPECT_EQ(described.at("variants")[0].at("name"), "Red");
    EXPECT_EQ(described.at("variants")[0].at("swatch").at("base_color"),
              (Json{0.8, 0.05, 0.05, 1.0}));
    EXPECT_EQ(described.at("variants")[1].at("swatch").at("base_color"),
              (Json{0.05, 0.1, 0.8, 1.0}));

    const auto unknown = client->Get(frame_path(mesh, "&variant=Green").c_str());
    expect_problem("GET", "/v1/render", unknown, server::ProblemKind::InvalidParameter);
    ASSERT_TRUE(unknown);
    const Json problem = Json::parse(unknown->body);
    EXPECT_EQ(problem.value("parameter", ""), "variant");
    EXPECT_NE(problem.value("detail", "").find("its variants: 'Red', 'Blue', 'Unchanged'"),
              std::string::npos)
        << unknown->body;
    const auto in_body =
        post_json(*client, "/v1/render",
                  {{"environment", "default"},
                   {"objects", {{{"mesh", "default"}}, {{"mesh", mesh}, {"variant", "Red"}}}},
                   {"width", 32},
                   {"height", 32}});
    EXPECT_EQ(in_body->status, 200) << in_body->body;
    const auto not_a_product_variant =
        post_json(*client, "/v1/render",
                  {{"environment", "default"},
                   {"objects", {{{"mesh", mesh}}, {{"mesh", "default"}, {"variant", "Red"}}}},
                   {"width", 32},
                   {"height", 32}});
    expect_problem("POST", "/v1/render", not_a_product_variant,
                   server::ProblemKind::InvalidParameter);
    EXPECT_EQ(Json::parse(not_a_product_variant->body).value("parameter", ""), "objects/1/variant");
}

// The check of the variants' issue: each variant's frame equals the asset with that variant's
// material baked in, and differs from the others only where its materials are drawn (with the
// bounce off, exactly; with it, by the light the body reflects onto the stand and the ground).
TEST(Variants, EachVariantIsTheAssetWithItsMaterialsBakedInAndBakesNothing) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string mesh = upload_prepared(*client, product_glb());
    const std::string red = upload_prepared(*client, product_glb(2));
    const std::string blue = upload_prepared(*client, product_glb(3));
    const std::string plain = upload_prepared(*client, product_glb(1));
    const double baked = transfers_computed(*client);

    const Rgba8Image red_frame = get_frame(*client, frame_path(mesh, "&variant=Red"));
    const Rgba8Image blue_frame = get_frame(*client, frame_path(mesh, "&variant=Blue"));
    const Rgba8Image unchanged_frame = get_frame(*client, frame_path(mesh, "&variant=Unchanged"));
    const Rgba8Image default_frame = get_frame(*client, frame_path(mesh));
    ASSERT_EQ(red_frame.width, 96);
    const int half = red_frame.width / 2;
    for (const auto& [name, variant, baked_in] :
         {std::tuple{"Red", &red_frame, red}, std::tuple{"Blue", &blue_frame, blue},
          std::tuple{"Unchanged", &unchanged_frame, plain}}) {
        const FrameDifference from_baked = frame_difference(
            *variant, get_frame(*client, frame_path(baked_in)), 0, red_frame.width);
        std::printf(
            "variant %s against the asset with its material baked in: largest %d/255, "
            "mean %.4f\n",
            name, from_baked.largest, from_baked.mean);
        EXPECT_LE(from_baked.largest, 1) << name;
    }
    EXPECT_EQ(frame_difference(unchanged_frame, default_frame, 0, red_frame.width).largest, 0);

    const FrameDifference body = frame_difference(red_frame, blue_frame, 0, half);
    const FrameDifference stand = frame_difference(red_frame, blue_frame, half, red_frame.width);
    std::printf(
        "Red against Blue: body's half largest %d/255 mean %.3f; stand's half largest "
        "%d/255 mean %.3f (the body's reflected light)\n",
        body.largest, body.mean, stand.largest, stand.mean);
    EXPECT_GT(body.largest, 100);
    EXPECT_GT(body.mean, 10.0);
    EXPECT_LE(stand.mean, 1.0);
    const std::string direct_only = "&bounce=none";
    const FrameDifference stand_direct = frame_difference(
        get_frame(*client, frame_path(mesh, "&variant=Red" + direct_only)),
        get_frame(*client, frame_path(mesh, "&variant=Blue" + direct_only)), half, red_frame.width);
    EXPECT_EQ(stand_direct.largest, 0) << "without the bounce, the stand's half must not change";

    // The variants re-weighed the upload's transfer; only bounce=none baked (another scene).
    EXPECT_EQ(transfers_computed(*client), baked + 1.0);
}

// A colour for one named material (base_color_material): the Body recoloured red is the Red
// variant (their materials differ in the base colour alone), the Stand keeps its own; without
// the name, base_color recolours every material.
TEST(Variants, AColourForOneNamedMaterialRecoloursThatMaterialOnly) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string mesh = upload_prepared(*client, product_glb());
    const double baked = transfers_computed(*client);
    const Rgba8Image red_variant = get_frame(*client, frame_path(mesh, "&variant=Red"));
    const std::string red = "&base_color=0.8,0.05,0.05";
    const Rgba8Image body_red =
        get_frame(*client, frame_path(mesh, red + "&base_color_material=Body"));
    const Rgba8Image all_red = get_frame(*client, frame_path(mesh, red));
    ASSERT_EQ(body_red.width, 96);
    const int half = body_red.width / 2;
    const FrameDifference from_variant = frame_difference(body_red, red_variant, 0, body_red.width);
    std::printf("the Body recoloured red against the Red variant: largest %d/255\n",
                from_variant.largest);
    EXPECT_LE(from_variant.largest, 1);
    const FrameDifference stand = frame_difference(body_red, all_red, half, body_red.width);
    EXPECT_GT(stand.largest, 50) << "base_color without a material recolours the stand too";
    EXPECT_EQ(transfers_computed(*client), baked) << "a colour baked a transfer";

    const auto unknown = client->Get(frame_path(mesh, red + "&base_color_material=Lid").c_str());
    expect_problem("GET", "/v1/render", unknown, server::ProblemKind::InvalidParameter);
    ASSERT_TRUE(unknown);
    EXPECT_NE(Json::parse(unknown->body)
                  .value("detail", "")
                  .find("its materials: 'Body', 'Red', 'Blue', 'Stand'"),
              std::string::npos)
        << unknown->body;
}
