// The render request of POST and GET /v1/render: parsing, validation, the canonical document,
// ETags and the conversion to a FrameRequest.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/api/render_request.hpp"
#include "oer/api/version.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/scene/scene_rules.hpp"
#include "rejected_parameter.hpp"

using namespace oer;
using api::InvalidParameter;
using api::MalformedRequest;
using api::RenderSpec;
using oer::testing::rejected_member;
using oer::testing::rejected_parameter;
using Json = nlohmann::json;
using Query = std::multimap<std::string, std::string>;

namespace {

const std::string kRig(64, 'a');
const std::string kMeshA(64, 'b');
const std::string kMeshB = "0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef";

// A body with `member` set to `value` on top of a valid minimal request.
std::string with(const std::string& member, const std::string& value) {
    return R"({"environment": ")" + kRig + R"(", ")" + member + "\": " + value + "}";
}

std::string etag_of_json(const Json& body) {
    return api::render_etag(api::parse_render_json(body.dump()));
}

}  // namespace

TEST(RenderRequest, TheDesignExampleParsesToItsValues) {
    const std::string body = R"({ "environment": ")" + kRig + R"(",
      "objects": [ { "mesh": ")" +
                             kMeshA + R"(",
                     "transform": [2, 0, 0, 0,  0, 2, 0, 0,  0, 0, 2, 0,  1, 2, 3, 1],
                     "base_color": [0.8, 0.1, 0.05] } ],
      "ground": true,
      "camera": { "eye": [0, 1.5, 4], "target": [0, 0.75, 0], "up": [0, 1, 0], "fov_y": 45 },
      "lights": [true, false],
      "width": 512, "height": 512, "format": "jpeg", "quality": 85,
      "exposure": 0, "tonemap": "neutral", "background": "env" })";
    const RenderSpec spec = api::parse_render_json(body);
    EXPECT_EQ(spec.environment, kRig);
    ASSERT_EQ(spec.objects.size(), 1u);
    EXPECT_EQ(spec.objects[0].mesh, kMeshA);
    // Column-major: the last four numbers are the translation column.
    EXPECT_EQ(spec.objects[0].transform[3][0], 1.0);
    EXPECT_EQ(spec.objects[0].transform[3][1], 2.0);
    EXPECT_EQ(spec.objects[0].transform[3][2], 3.0);
    EXPECT_EQ(spec.objects[0].transform[1][1], 2.0);
    EXPECT_EQ(spec.objects[0].transform[0][3], 0.0);
    ASSERT_TRUE(spec.objects[0].base_color.has_value());
    EXPECT_EQ(*spec.objects[0].base_color, glm::dvec3(0.8, 0.1, 0.05));
    EXPECT_EQ(spec.ground, api::GroundChoice::Opaque);
    ASSERT_TRUE(spec.camera.has_value());
    const auto& look_at = std::get<api::LookAtSpec>(spec.camera->placement);
    EXPECT_EQ(look_at.eye, glm::dvec3(0.0, 1.5, 4.0));
    EXPECT_EQ(look_at.target, glm::dvec3(0.0, 0.75, 0.0));
    EXPECT_EQ(look_at.up, glm::dvec3(0.0, 1.0, 0.0));
    EXPECT_EQ(spec.camera->fov_y, 45.0);
    EXPECT_EQ(spec.lights, (std::vector<double>{1.0, 0.0}));
    EXPECT_EQ(spec.width, 512);
    EXPECT_EQ(spec.height, 512);
    EXPECT_EQ(spec.format, api::ImageFormat::Jpeg);
    EXPECT_EQ(spec.quality, 85);
    EXPECT_EQ(spec.exposure, 0.0);
    EXPECT_EQ(spec.tonemap, ToneMapper::Neutral);
    EXPECT_EQ(spec.background.kind, BackgroundKind::Environment);

    const RenderSpec orbit = api::parse_render_json(
        with("camera", R"({ "orbit": { "yaw": 30, "pitch": 15, "distance": 2.5,
                                       "target": [0, 0.8, 0] }, "fov_y": 35 })"));
    const auto& placement = std::get<api::OrbitSpec>(orbit.camera->placement);
    EXPECT_EQ(placement.yaw, 30.0);
    EXPECT_EQ(placement.pitch, 15.0);
    EXPECT_EQ(placement.distance, 2.5);
    EXPECT_EQ(placement.target, glm::dvec3(0.0, 0.8, 0.0));
    EXPECT_EQ(orbit.camera->fov_y, 35.0);
}

TEST(RenderRequest, EveryOtherMemberParses) {
    const RenderSpec spec = api::parse_render_json(R"({"environment": "default",
        "objects": [{"mesh": "default"}, {"mesh": ")" +
                                                   kMeshB + R"("}],
        "ground": false, "occlusion": false, "bounce": "none", "width": 640, "height": 480.0,
        "format": "exr", "quality": 1,
        "exposure": -1.5, "tonemap": "aces", "background": "#FF8000",
        "shadows": {"enabled": false, "resolution": 512, "filter": "hard"},
        "samples": 8, "environment_yaw": -90})");
    EXPECT_EQ(spec.environment, "default");
    ASSERT_EQ(spec.objects.size(), 2u);
    EXPECT_EQ(spec.objects[0].mesh, "default");
    EXPECT_EQ(spec.objects[1].mesh, kMeshB);
    EXPECT_EQ(spec.objects[1].transform, glm::dmat4(1.0));
    EXPECT_FALSE(spec.objects[1].base_color.has_value());
    EXPECT_EQ(spec.ground, api::GroundChoice::Off);
    EXPECT_FALSE(spec.occlusion);
    EXPECT_EQ(spec.bounce, Bounce::None);
    EXPECT_EQ(spec.width, 640);
    EXPECT_EQ(spec.height, 480);
    EXPECT_EQ(spec.format, api::ImageFormat::Exr);
    EXPECT_EQ(spec.quality, 1);
    EXPECT_EQ(spec.exposure, -1.5);
    EXPECT_EQ(spec.tonemap, ToneMapper::Aces);
    EXPECT_EQ(spec.background.kind, BackgroundKind::Color);
    EXPECT_EQ(spec.background.color, glm::vec3(1.0f, 128.0f / 255.0f, 0.0f));
    EXPECT_FALSE(spec.shadows.enabled);
    EXPECT_EQ(spec.shadows.resolution, 512);
    EXPECT_EQ(spec.shadows.filter, ShadowFilter::Hard);
    EXPECT_EQ(spec.samples, 8);
    EXPECT_EQ(spec.environment_yaw, -90.0);
    EXPECT_EQ(api::to_string(spec.background), "#ff8000");
}

TEST(RenderRequest, DefaultsFillTheCanonicalDocument) {
    const RenderSpec spec = api::parse_render_json(R"({"environment": "default"})");
    EXPECT_TRUE(spec.objects.empty());
    EXPECT_FALSE(spec.camera.has_value());
    EXPECT_TRUE(spec.lights.empty());
    EXPECT_TRUE(spec.occlusion);
    EXPECT_EQ(spec.bounce, Bounce::One);
    const Json expected = {{"environment", "default"},
                           {"objects", Json::array()},
                           {"ground", true},
                           {"occlusion", true},
                           {"bounce", "one"},
                           {"lights", Json::array()},
                           {"width", 512},
                           {"height", 512},
                           {"format", "jpeg"},
                           {"quality", 85},
                           {"exposure", 0.0},
                           {"tonemap", "neutral"},
                           {"background", "env"},
                           {"shadows",
                            {{"enabled", true},
                             {"resolution", 2048},
                             {"filter", "pcf"},
                             {"softness", 1.0},
                             {"intensity", 1.0}}},
                           {"samples", 4},
                           {"environment_yaw", 0.0}};
    EXPECT_EQ(api::normalised_render_json(spec), expected);
    EXPECT_EQ(api::normalised_render_json(spec).dump(), expected.dump());

    // An object's transform is filled in as the identity; an orbit's angles default to
    // oer::Orbit's, and its absent target and distance (the automatic framing's) stay absent.
    const Json filled = api::normalised_render_json(api::parse_render_json(
        R"({"environment": "default", "objects": [{"mesh": "default"}],
            "camera": {"orbit": {}}})"));
    EXPECT_EQ(
        filled.at("objects")[0],
        Json({{"mesh", "default"},
              {"transform",
               {1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0}}}));
    EXPECT_EQ(filled.at("camera"),
              Json({{"orbit", {{"yaw", 30.0}, {"pitch", 15.0}}}, {"fov_y", 45.0}}));
    const Json look_at = api::normalised_render_json(
        api::parse_render_json(with("camera", R"({"eye": [-0.0, 1, 2], "target": [0, 0, 0]})")));
    EXPECT_EQ(look_at.at("camera").dump(),
              R"({"eye":[0.0,1.0,2.0],"fov_y":45.0,"target":[0.0,0.0,0.0],"up":[0.0,1.0,0.0]})");
}

TEST(RenderRequest, TheCanonicalDocumentIsAValidBodyOfTheSameRequest) {
    const std::string body = R"({"environment": ")" + kRig + R"(",
        "objects": [{"mesh": ")" +
                             kMeshA + R"(", "base_color": [0.25, 0.5, 1],
                     "transform": [0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0.5, 0, -0.5, 1]}],
        "camera": {"orbit": {"yaw": -45, "pitch": 60, "distance": 7, "target": [1, 2, 3]}},
        "lights": [false, true, true], "background": "transparent", "format": "png",
        "shadows": {"resolution": 8192}, "samples": 1, "environment_yaw": 12.5})";
    const Json canonical = api::normalised_render_json(api::parse_render_json(body));
    EXPECT_EQ(api::normalised_render_json(api::parse_render_json(canonical.dump())), canonical);
    EXPECT_EQ(canonical.at("lights"), Json({0.0, 1.0, 1.0}));
    EXPECT_EQ(canonical.at("objects")[0].at("base_color"), Json({0.25, 0.5, 1.0}));
}

TEST(RenderRequest, GetAndPostFormsOfOneRequestShareTheEtag) {
    const Json look_at_body = {
        {"environment", kRig},
        {"objects", {{{"mesh", kMeshA}}, {{"mesh", "default"}}}},
        {"camera",
         {{"eye", {0, 1.5, 4}}, {"target", {0, 0.75, 0}}, {"up", {0, 1, 0}}, {"fov_y", 30}}},
        {"lights", {true, false, true}},
        {"width", 800},
        {"height", 600},
        {"format", "png"},
        {"quality", 70},
        {"exposure", 0.5},
        {"tonemap", "aces"},
        {"background", "#102030"},
        {"ground", false},
        {"occlusion", false},
        {"bounce", "none"},
        {"shadows", {{"enabled", true}, {"resolution", 1024}, {"filter", "hard"}}},
        {"samples", 2},
        {"environment_yaw", 45}};
    const Query look_at_query = {{"environment", kRig},     {"mesh", kMeshA},
                                 {"mesh", "default"},       {"eye", "0,1.5,4"},
                                 {"target", "0,0.75,0"},    {"up", "0,1,0"},
                                 {"fov_y", "30"},           {"lights", "1,0,1"},
                                 {"width", "800"},          {"height", "600"},
                                 {"format", "png"},         {"quality", "70"},
                                 {"exposure", "0.5"},       {"tonemap", "aces"},
                                 {"background", "#102030"}, {"ground", "off"},
                                 {"occlusion", "off"},      {"bounce", "none"},
                                 {"shadows", "on"},         {"shadow_resolution", "1024"},
                                 {"shadow_filter", "hard"}, {"samples", "2"},
                                 {"environment_yaw", "45"}};
    const RenderSpec from_json = api::parse_render_json(look_at_body.dump());
    const RenderSpec from_query = api::parse_render_query(look_at_query);
    EXPECT_EQ(api::normalised_render_json(from_query), api::normalised_render_json(from_json));
    EXPECT_EQ(api::render_etag(from_query), api::render_etag(from_json));

    const Json orbit_body = {
        {"environment", "default"},
        {"objects", {{{"mesh", "default"}}}},
        {"camera",
         {{"orbit", {{"yaw", 30}, {"pitch", -10}, {"distance", 2.5}, {"target", {0, 0.8, 0}}}}}}};
    const Query orbit_query = {
        {"environment", "default"}, {"mesh", "default"}, {"yaw", "30"},
        {"pitch", "-10"},           {"distance", "2.5"}, {"target", "0,0.8,0"}};
    EXPECT_EQ(api::render_etag(api::parse_render_query(orbit_query)), etag_of_json(orbit_body));
    // A colour variant: the query's base_color is each object's.
    const Json variant_body = {{"environment", "default"},
                               {"objects", {{{"mesh", kMeshA}, {"base_color", {0.5, 0.1, 0.1}}}}}};
    const Query variant_query = {
        {"environment", "default"}, {"mesh", kMeshA}, {"base_color", "0.5,0.1,0.1"}};
    EXPECT_EQ(api::render_etag(api::parse_render_query(variant_query)), etag_of_json(variant_body));
    EXPECT_NE(
        api::render_etag(api::parse_render_query(variant_query)),
        api::render_etag(api::parse_render_query({{"environment", "default"}, {"mesh", kMeshA}})));
    // The product's own variant: the query's is each object's too, and named in the canonical
    // document.
    const Json red_body = {{"environment", "default"},
                           {"objects", {{{"mesh", kMeshA}, {"variant", "Red"}}}}};
    const Query red_query = {{"environment", "default"}, {"mesh", kMeshA}, {"variant", "Red"}};
    EXPECT_EQ(api::render_etag(api::parse_render_query(red_query)), etag_of_json(red_body));
    EXPECT_EQ(api::normalised_render_json(api::parse_render_query(red_query))
                  .at("objects")[0]
                  .at("variant"),
              "Red");
    EXPECT_FALSE(api::normalised_render_json(api::parse_render_query(variant_query))
                     .at("objects")[0]
                     .contains("variant"));
    // Integers and their float spellings are one number.
    EXPECT_EQ(etag_of_json({{"environment", "default"}, {"width", 512.0}}),
              api::render_etag(api::parse_render_query({{"environment", "default"}})));
}

// A variant's name is one line of 1 to 256 bytes of UTF-8; the query's needs a mesh; a name the
// mesh lacks is refused once the mesh is known, listing the ones it has.
TEST(RenderRequest, VariantNamesAreCheckedAsTextThenAgainstTheMesh) {
    const auto body = [](const Json& name) {
        return Json{{"environment", "default"},
                    {"objects", {{{"mesh", kMeshA}, {"variant", name}}}}}
            .dump();
    };
    for (const Json& bad : {Json(""), Json(std::string(257, 'a')), Json("a\nb"), Json(3)}) {
        EXPECT_THROW(api::parse_render_json(body(bad)), api::InvalidParameter) << bad.dump();
    }
    EXPECT_NO_THROW(api::parse_render_json(body("Velvet – Forest Green ")));
    EXPECT_EQ(rejected_parameter({{"environment", "default"}, {"variant", "Red"}}), "variant");
    EXPECT_EQ(
        rejected_parameter({{"environment", "default"}, {"mesh", kMeshA}, {"variant", "\xff"}}),
        "variant");
    EXPECT_EQ(
        rejected_parameter(
            {{"environment", "default"}, {"mesh", kMeshA}, {"variant", std::string(300, 'x')}}),
        "variant");

    Mesh mesh;
    mesh.variants = {"Red", "Blue"};
    api::ObjectSpec object;
    object.mesh = kMeshA;
    EXPECT_EQ(api::variant_index(object, mesh, "variant"), std::nullopt);
    object.variant = "Blue";
    EXPECT_EQ(api::variant_index(object, mesh, "variant"), 1u);
    // `resolve` refuses naming `parameter`, its message holding `text`.
    const auto expect_refused = [](const std::function<void()>& resolve,
                                   const std::string& parameter, const std::string& text) {
        try {
            resolve();
            ADD_FAILURE() << "accepted; expected a refusal saying '" << text << "'";
        } catch (const api::InvalidParameter& error) {
            EXPECT_EQ(error.parameter(), parameter);
            EXPECT_NE(std::string(error.what()).find(text), std::string::npos) << error.what();
        }
    };
    object.variant = "Green";
    expect_refused([&] { api::variant_index(object, mesh, "objects/0/variant"); },
                   "objects/0/variant", "has no variant 'Green' (its variants: 'Red', 'Blue')");
    mesh.variants.clear();
    EXPECT_THROW(api::variant_index(object, mesh, "variant"), api::InvalidParameter);

    // base_color_material: a name, needing base_color, then one of the mesh's materials.
    EXPECT_EQ(rejected_parameter(
                  {{"environment", "default"}, {"mesh", kMeshA}, {"base_color_material", "Body"}}),
              "base_color_material");
    EXPECT_THROW(api::parse_render_json(
                     Json{{"environment", "default"},
                          {"objects", {{{"mesh", kMeshA}, {"base_color_material", "Body"}}}}}
                         .dump()),
                 api::InvalidParameter);
    mesh.materials.resize(3);
    mesh.materials[0].name = "Stand";
    mesh.materials[1].name = "Body";
    mesh.materials[2].name = "Body";
    api::ObjectSpec recoloured;
    recoloured.mesh = kMeshA;
    recoloured.base_color = glm::dvec3(1.0, 0.0, 0.0);
    EXPECT_EQ(api::base_color_material_index(recoloured, mesh, "p"), std::nullopt);
    recoloured.base_color_material = "Body";
    EXPECT_EQ(api::base_color_material_index(recoloured, mesh, "p"), 1u);
    recoloured.base_color_material = "Lid";
    expect_refused(
        [&] { api::base_color_material_index(recoloured, mesh, "objects/0/base_color_material"); },
        "objects/0/base_color_material",
        "has no material named 'Lid' (its materials: 'Stand', 'Body', 'Body')");
}

TEST(RenderRequest, TheEtagIsAQuotedDigestOfTheCanonicalDocumentAndVersion) {
    const RenderSpec spec = api::parse_render_json(R"({"environment": "default"})");
    const std::string etag = api::render_etag(spec);
    EXPECT_EQ(etag, "\"" +
                        api::sha256_hex("oer-render/" + std::string(api::kVersion) + "\n" +
                                        api::normalised_render_json(spec).dump()) +
                        "\"");
    ASSERT_EQ(etag.size(), 66u);
    EXPECT_TRUE(api::is_content_id(etag.substr(1, 64)));
}

TEST(RenderRequest, ChangingAnyOneMemberChangesTheEtag) {
    const Json base = {{"environment", kRig},
                       {"objects", {{{"mesh", kMeshA}}}},
                       {"camera", {{"eye", {0, 1, 3}}, {"target", {0, 0, 0}}}},
                       {"lights", {true, true}}};
    std::vector<Json> variants;
    const auto vary = [&](const Json::json_pointer& member, const Json& value) {
        Json changed = base;
        changed[member] = value;
        variants.push_back(changed);
    };
    vary("/environment"_json_pointer, kMeshB);
    vary("/objects/0/mesh"_json_pointer, kMeshB);
    vary("/objects/0/transform"_json_pointer, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.001, 0, 1});
    vary("/objects/0/base_color"_json_pointer, {1, 1, 1});
    vary("/objects/0/variant"_json_pointer, "Red");
    {
        Json recoloured = base;
        // The base_color variation's colour, on one material only.
        recoloured["objects"][0]["base_color"] = {1, 1, 1};
        recoloured["objects"][0]["base_color_material"] = "Body";
        variants.push_back(recoloured);
    }
    vary("/objects/1"_json_pointer, {{"mesh", kMeshA}});
    vary("/ground"_json_pointer, false);
    vary("/occlusion"_json_pointer, false);
    vary("/bounce"_json_pointer, "none");
    vary("/camera/eye"_json_pointer, {0, 1, 3.0001});
    vary("/camera/target"_json_pointer, {0, 0.5, 0});
    vary("/camera/up"_json_pointer, {0.1, 1, 0});
    vary("/camera/fov_y"_json_pointer, 46);
    vary("/lights"_json_pointer, {true, false});
    vary("/width"_json_pointer, 513);
    vary("/height"_json_pointer, 511);
    vary("/format"_json_pointer, "png");
    vary("/quality"_json_pointer, 86);
    vary("/exposure"_json_pointer, 0.25);
    vary("/tonemap"_json_pointer, "none");
    vary("/background"_json_pointer, "transparent");
    vary("/shadows/enabled"_json_pointer, false);
    vary("/shadows/resolution"_json_pointer, 4096);
    vary("/shadows/filter"_json_pointer, "hard");
    vary("/samples"_json_pointer, 1);
    vary("/environment_yaw"_json_pointer, 1);
    Json orbit = base;
    orbit["camera"] = {{"orbit", {{"yaw", 30}}}};
    variants.push_back(orbit);
    Json auto_framed = base;
    auto_framed.erase("camera");
    variants.push_back(auto_framed);

    std::map<std::string, std::string> seen = {{etag_of_json(base), base.dump()}};
    for (const Json& variant : variants) {
        const std::string etag = etag_of_json(variant);
        EXPECT_FALSE(seen.contains(etag)) << variant.dump() << "\nhas the ETag of\n" << seen[etag];
        seen[etag] = variant.dump();
    }
    EXPECT_EQ(seen.size(), variants.size() + 1);
}

TEST(RenderRequest, ErrorsNameTheMembersPath) {
    const std::string object = R"({"mesh": ")" + kMeshA + R"("})";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"width": 10})", "environment"},
        {R"({"environment": 5})", "environment"},
        {R"({"environment": "ABCDEF"})", "environment"},
        {R"({"environment": ")" + std::string(64, 'A') + R"("})", "environment"},
        {R"({"environment": ")" + std::string(63, 'a') + R"("})", "environment"},
        {with("objects", "[" + object + ", {}]"), "objects/1/mesh"},
        {with("objects", R"([{"mesh": ""}])"), "objects/0/mesh"},
        {with("objects", R"([{"mesh": null}])"), "objects/0/mesh"},
        {with("objects", "[" + object + R"(, {"mesh": "default", "transform": [1, 2, 3]}])"),
         "objects/1/transform"},
        {with("objects", R"([{"mesh": "default", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0,
                                                                0,0,0,1, 0]}])"),
         "objects/0/transform"},
        {with("objects", R"([{"mesh": "default", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0,
                                                                0,0,"1",1]}])"),
         "objects/0/transform/14"},
        {with("objects", R"([{"mesh": "default", "transform": [1,0,0,0, 0,1,0,0, 0,0,0,0,
                                                                0,0,0,1]}])"),
         "objects/0/transform"},
        {with("objects", R"([{"mesh": "default", "base_color": [1, 1.5, 0]}])"),
         "objects/0/base_color/1"},
        {with("objects", R"([{"mesh": "default", "base_color": [1, 1]}])"), "objects/0/base_color"},
        {with("objects", R"({"mesh": "default"})"), "objects"},
        {with("ground", "1"), "ground"},
        {with("occlusion", R"("off")"), "occlusion"},
        {with("occlusion", "0"), "occlusion"},
        {with("bounce", R"("two")"), "bounce"},
        {with("bounce", R"("One")"), "bounce"},
        {with("bounce", "1"), "bounce"},
        {with("camera", R"({"eye": [0, 0, 3], "target": [0, 0, 0], "fov_y": 180})"),
         "camera/fov_y"},
        {with("camera", R"({"eye": [0, 0, 3], "target": [0, 0, 0], "fov_y": "45"})"),
         "camera/fov_y"},
        {with("camera", R"({"eye": [0, 0, 3]})"), "camera/target"},
        {with("camera", R"({"fov_y": 30})"), "camera/eye"},
        {with("camera", R"({"eye": [0, 0, 3], "target": [0, 0, 3]})"), "camera"},
        {with("camera", R"({"eye": [0, 3, 0], "target": [0, 0, 0]})"), "camera"},
        {with("camera", R"({"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1]})"), "camera/up"},
        {with("camera", R"({"eye": [0, 0, 1e7], "target": [0, 0, 0]})"), "camera/eye/2"},
        {with("camera", R"({"orbit": {"pitch": 91}})"), "camera/orbit/pitch"},
        {with("camera", R"({"orbit": {"yaw": 361}})"), "camera/orbit/yaw"},
        {with("camera", R"({"orbit": {"distance": 0}})"), "camera/orbit/distance"},
        {with("camera", R"({"orbit": {"target": [0, 0, "x"]}})"), "camera/orbit/target/2"},
        {with("camera", R"({"orbit": {}, "eye": [0, 0, 3]})"), "camera/eye"},
        {with("camera", R"({"orbit": 30})"), "camera/orbit"},
        {with("lights", R"([true, "1"])"), "lights/1"},
        {with("lights", R"("1,0")"), "lights"},
        {with("width", "0"), "width"},
        {with("width", "4097"), "width"},
        {with("width", "512.5"), "width"},
        {with("width", "\"512\""), "width"},
        {with("height", "-1"), "height"},
        {with("height", "1e300"), "height"},
        {with("format", R"("jpg")"), "format"},
        {with("quality", "101"), "quality"},
        {with("quality", "0"), "quality"},
        {with("exposure", "65"), "exposure"},
        {with("exposure", "null"), "exposure"},
        {with("exposure", R"("NaN")"), "exposure"},
        {with("tonemap", R"("filmic")"), "tonemap"},
        {with("background", R"("#12345")"), "background"},
        {with("background", R"("#12345g")"), "background"},
        {with("background", R"("white")"), "background"},
        {with("shadows", "true"), "shadows"},
        {with("shadows", R"({"resolution": 1000})"), "shadows/resolution"},
        {with("shadows", R"({"resolution": 32})"), "shadows/resolution"},
        {with("shadows", R"({"resolution": 16384})"), "shadows/resolution"},
        {with("shadows", R"({"filter": "soft"})"), "shadows/filter"},
        {with("shadows", R"({"enabled": "yes"})"), "shadows/enabled"},
        {with("samples", "3"), "samples"},
        {with("samples", "16"), "samples"},
        {with("environment_yaw", "400"), "environment_yaw"},
        {"[]", "body"},
        {"\"render\"", "body"},
    };
    for (const auto& [body, member] : cases) {
        EXPECT_EQ(rejected_member(body), member) << body;
    }
}

TEST(RenderRequest, UnknownMembersAreRejectedAtEveryLevel) {
    EXPECT_EQ(rejected_member(with("color", "1")), "color");
    EXPECT_EQ(rejected_member(with("yaw", "10")), "yaw");
    EXPECT_EQ(rejected_member(with("env_yaw", "10")), "env_yaw");
    EXPECT_EQ(rejected_member(with("objects", R"([{"mesh": "default", "scale": 2}])")),
              "objects/0/scale");
    EXPECT_EQ(rejected_member(with("camera", R"({"eye": [0,0,3], "target": [0,0,0], "fov": 30})")),
              "camera/fov");
    EXPECT_EQ(rejected_member(with("camera", R"({"orbit": {"distance": 2, "roll": 5}})")),
              "camera/orbit/roll");
    EXPECT_EQ(rejected_member(with("shadows", R"({"enabled": true, "bias": 0.1})")),
              "shadows/bias");
    try {
        api::parse_render_json(with("widht", "10"));
        FAIL() << "a misspelt member was accepted";
    } catch (const InvalidParameter& error) {
        EXPECT_NE(std::string(error.what()).find("width"), std::string::npos) << error.what();
    }
}

TEST(RenderRequest, UnreadableBodiesAreMalformed) {
    const std::vector<std::string> bodies = {
        "",
        "{",
        R"({"environment": })",
        R"({"environment": "default",})",
        R"({"environment": "default"} trailing)",
        R"({"environment": "default", "exposure": NaN})",
        R"({"environment": "default", "exposure": Infinity})",
        R"({"environment": "default", "exposure": 1e400})",
        R"({"environment": "default", "exposure": -1e400})",
        R"({"environment": 'default'})",
        "{\"environment\": \"default\" /* comment */}",
        std::string(100000, '[') + std::string(100000, ']'),
        R"({"environment": )" + std::string(20, '[') + std::string(20, ']') + "}",
    };
    for (const std::string& body : bodies) {
        EXPECT_THROW(api::parse_render_json(body), MalformedRequest) << body.substr(0, 80);
    }
    try {
        api::parse_render_json("{\n  \"environment\": x}");
        FAIL() << "accepted";
    } catch (const MalformedRequest& error) {
        EXPECT_NE(std::string(error.what()).find("line 2, column"), std::string::npos)
            << error.what();
    }
    // Nesting within the guard's depth is well-formed JSON of the wrong type.
    EXPECT_EQ(rejected_member(with("environment", "[[[[[[[[1]]]]]]]]")), "environment");
}

TEST(RenderRequest, LargeInputsStopAtTheLimits) {
    std::string lights = "[true";
    for (int i = 0; i < 64; ++i) {
        lights += ", false";
    }
    EXPECT_EQ(rejected_member(with("lights", lights + "]")), "lights");
    std::string objects = "[{\"mesh\": \"default\"}";
    for (int i = 0; i < 64; ++i) {
        objects += ", {\"mesh\": \"default\"}";
    }
    EXPECT_EQ(rejected_member(with("objects", objects + "]")), "objects");
    EXPECT_EQ(
        api::parse_render_json(with("objects", objects + "]"), {.max_objects = 65}).objects.size(),
        65u);
    EXPECT_EQ(rejected_member(with("width", "2049")), "");
    try {
        api::parse_render_json(with("width", "2049"), {.max_width = 2048});
        FAIL() << "accepted a width over the limit";
    } catch (const InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "width");
        EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded);
    }
    // A body over the byte limit is refused before it is parsed.
    const std::string huge = with("objects", "[" + std::string(300 << 10, ' ') + "]");
    try {
        api::parse_render_json(huge);
        FAIL() << "accepted an oversized body";
    } catch (const InvalidParameter&) {
        FAIL() << "an oversized body is a limit, not a parameter";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded);
    }
    EXPECT_EQ(rejected_member(huge.substr(0, 1000) + "]}"), "");
    // A body within the byte limit but of more values than any valid request (64 objects of 25
    // values, 64 light switches and under 64 others: 1728) is refused while it is parsed.
    std::string zeros = "[0";
    for (int i = 1; i < 100'000; ++i) {
        zeros += ",0";
    }
    try {
        api::parse_render_json(with("lights", zeros + "]"));
        FAIL() << "accepted 10^5 light switches";
    } catch (const InvalidParameter& error) {
        FAIL() << "counted after parsing: " << error.what();
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded);
        EXPECT_EQ(std::string(error.what()),
                  "render request: the JSON holds more than 1728 values, more than any request "
                  "within the limits (at most 64 objects and 64 light switches)");
    }
    // The largest valid body is within the bound.
    std::string full_objects = "[";
    for (int i = 0; i < 64; ++i) {
        full_objects += std::string(i == 0 ? "" : ",") +
                        R"({"mesh": "default", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
                            "base_color": [0.5, 0.5, 0.5], "base_color_material": "Body",
                            "variant": "Red"})";
    }
    std::string all_on = "[true";
    for (int i = 1; i < 64; ++i) {
        all_on += ",true";
    }
    const std::string largest = R"({"environment": "default", "objects": )" + full_objects +
                                R"(], "lights": )" + all_on + R"(],
        "camera": {"eye": [0, 1, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y": 40},
        "ground": true, "occlusion": false, "width": 64, "height": 64, "format": "png",
        "quality": 90, "exposure": 0, "tonemap": "aces", "background": "transparent",
        "shadows": {"enabled": true, "resolution": 1024, "filter": "pcf", "softness": 0.5,
                    "intensity": 0.5}, "samples": 4,
        "environment_yaw": 10})";
    EXPECT_EQ(api::parse_render_json(largest).objects.size(), 64u);
}

TEST(RenderRequest, QueryErrorsNameTheParameter) {
    const std::vector<std::pair<Query, std::string>> cases = {
        {{{"mesh", "default"}}, "environment"},
        {{{"environment", "default"}, {"environment", "default"}}, "environment"},
        {{{"environment", "default"}, {"color", "red"}}, "color"},
        {{{"environment", "default"}, {"camera", "x"}}, "camera"},
        {{{"environment", "default"}, {"env_yaw", "3"}}, "env_yaw"},
        {{{"environment", "default"}, {"mesh", "default"}, {"mesh", "xyz"}}, "mesh"},
        {{{"environment", "default"}, {"eye", "0,0"}, {"target", "0,0,0"}}, "eye"},
        {{{"environment", "default"}, {"eye", "0,0,3,4"}, {"target", "0,0,0"}}, "eye"},
        {{{"environment", "default"}, {"eye", "0,0,nan"}, {"target", "0,0,0"}}, "eye"},
        {{{"environment", "default"}, {"eye", "0,0,inf"}, {"target", "0,0,0"}}, "eye"},
        {{{"environment", "default"}, {"eye", "0,0,3"}}, "target"},
        {{{"environment", "default"}, {"target", "0,0,3"}}, "eye"},
        {{{"environment", "default"}, {"eye", "0,0,3"}, {"target", "0,0,3"}}, "eye"},
        {{{"environment", "default"}, {"eye", "0,0,3"}, {"yaw", "10"}}, "eye"},
        {{{"environment", "default"}, {"up", "0,1,0"}, {"distance", "2"}}, "up"},
        {{{"environment", "default"}, {"fov_y", "40"}}, "fov_y"},
        {{{"environment", "default"}, {"yaw", "10"}, {"fov_y", "0"}}, "fov_y"},
        {{{"environment", "default"}, {"pitch", "-90.5"}}, "pitch"},
        {{{"environment", "default"}, {"distance", "-1"}}, "distance"},
        {{{"environment", "default"}, {"lights", "1,4.5"}}, "lights"},
        {{{"environment", "default"}, {"lights", ""}}, "lights"},
        {{{"environment", "default"}, {"width", "0x10"}}, "width"},
        {{{"environment", "default"}, {"width", "512.0"}}, "width"},
        {{{"environment", "default"}, {"height", ""}}, "height"},
        {{{"environment", "default"}, {"format", "JPEG"}}, "format"},
        {{{"environment", "default"}, {"quality", "100 "}}, "quality"},
        {{{"environment", "default"}, {"exposure", "1e400"}}, "exposure"},
        {{{"environment", "default"}, {"tonemap", "reinhard"}}, "tonemap"},
        {{{"environment", "default"}, {"background", "#abc"}}, "background"},
        {{{"environment", "default"}, {"ground", "true"}}, "ground"},
        {{{"environment", "default"}, {"occlusion", "false"}}, "occlusion"},
        {{{"environment", "default"}, {"occlusion", ""}}, "occlusion"},
        {{{"environment", "default"}, {"bounce", "two"}}, "bounce"},
        {{{"environment", "default"}, {"bounce", "1"}}, "bounce"},
        {{{"environment", "default"}, {"bounce", "none"}, {"bounce", "one"}}, "bounce"},
        {{{"environment", "default"}, {"shadows", "1"}}, "shadows"},
        {{{"environment", "default"}, {"shadow_resolution", "2047"}}, "shadow_resolution"},
        {{{"environment", "default"}, {"shadow_filter", "PCF"}}, "shadow_filter"},
        {{{"environment", "default"}, {"samples", "6"}}, "samples"},
        {{{"environment", "default"}, {"environment_yaw", "-360.01"}}, "environment_yaw"},
    };
    for (const auto& [query, parameter] : cases) {
        std::string text;
        for (const auto& [name, value] : query) {
            text += name + "=" + value + "&";
        }
        EXPECT_EQ(rejected_parameter(query), parameter) << text;
    }
    Query many = {{"environment", "default"}};
    for (int i = 0; i < 65; ++i) {
        many.insert({"mesh", "default"});
    }
    EXPECT_EQ(rejected_parameter(many), "mesh");
    EXPECT_EQ(rejected_parameter({{"environment", "default"}, {"lights", std::string(200, '1')}}),
              "lights");
}

// Found by tests/fuzz/fuzz_render_json: a body that is not UTF-8 was refused with a message
// quoting its bytes, which the service's problem body (JSON) could not hold: a 500. Bytes that
// are not UTF-8 are escaped as \xNN, and excerpts are never cut inside a character.
TEST(RenderRequest, MessagesEscapeBytesThatAreNotUtf8) {
    const auto expect_json_text = [](const std::string& text) {
        EXPECT_NO_THROW((void)Json(text).dump())
            << Json(text).dump(-1, ' ', true, Json::error_handler_t::replace);
    };
    try {
        api::parse_render_json("{\"environment\": \"\xff\"}");
        FAIL() << "accepted";
    } catch (const MalformedRequest& error) {
        EXPECT_NE(std::string(error.what()).find("\\xFF"), std::string::npos) << error.what();
        expect_json_text(error.what());
    }
    try {
        api::parse_render_query({{"environment", "default"}, {"width", "4\xe9\x80"}});
        FAIL() << "accepted";
    } catch (const InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "width");
        EXPECT_NE(std::string(error.what()).find("got '4\\xE9\\x80'"), std::string::npos)
            << error.what();
        expect_json_text(error.what());
    }
    try {
        api::parse_render_query({{"environment", "default"}, {"\xc3", "1"}});
        FAIL() << "accepted";
    } catch (const InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "\\xC3");
        expect_json_text(error.what());
    }
    // 40 two-byte characters (80 bytes): the excerpt of 64 bytes ends after the 32nd.
    std::string accented;
    for (int i = 0; i < 40; ++i) {
        accented += "\u00e9";
    }
    try {
        api::parse_render_query({{"environment", "default"}, {"height", "1" + accented}});
        FAIL() << "accepted";
    } catch (const InvalidParameter& error) {
        EXPECT_NE(std::string(error.what()).find("got '1" + accented.substr(0, 62) + "...'"),
                  std::string::npos)
            << error.what();
        expect_json_text(error.what());
    }
}

// The occlusion switches (occlusion, bounce) say what they accept, in both forms, in the words of
// their neighbours (ground's on/off, tonemap's list of names).
TEST(RenderRequest, OcclusionAndBounceMessagesNameWhatTheyAccept) {
    const auto message = [](const auto& parse) -> std::string {
        try {
            parse();
        } catch (const InvalidParameter& error) {
            return error.what();
        }
        return "accepted";
    };
    EXPECT_EQ(message([] { api::parse_render_json(with("occlusion", R"("on")")); }),
              "occlusion: expected true or false, got string");
    EXPECT_EQ(message([] { api::parse_render_json(with("bounce", R"("two")")); }),
              "bounce: bounce 'two' is not one of none, one");
    EXPECT_EQ(message([] { api::parse_render_json(with("bounce", "true")); }),
              "bounce: expected a string, got boolean");
    EXPECT_EQ(message([] {
                  api::parse_render_query({{"environment", "default"}, {"occlusion", "true"}});
              }),
              "occlusion: expected on or off, got 'true'");
    EXPECT_EQ(message([] {
                  api::parse_render_query({{"environment", "default"}, {"bounce", "two"}});
              }),
              "bounce: bounce 'two' is not one of none, one");
    EXPECT_EQ(api::bounce_from_string(api::to_string(Bounce::None)), Bounce::None);
    EXPECT_EQ(api::bounce_from_string(api::to_string(Bounce::One)), Bounce::One);
}

TEST(RenderRequest, QueryFormReadsEveryParameter) {
    const RenderSpec spec = api::parse_render_query({{"environment", kRig},
                                                     {"mesh", kMeshA},
                                                     {"mesh", kMeshB},
                                                     {"target", "1,2,3"},
                                                     {"distance", "4"},
                                                     {"lights", "0,1"},
                                                     {"background", "transparent"},
                                                     {"shadows", "off"},
                                                     {"occlusion", "off"},
                                                     {"bounce", "none"},
                                                     {"samples", "1"}});
    ASSERT_EQ(spec.objects.size(), 2u);
    EXPECT_EQ(spec.objects[0].mesh, kMeshA);
    EXPECT_EQ(spec.objects[1].mesh, kMeshB);
    const auto& orbit = std::get<api::OrbitSpec>(spec.camera->placement);
    EXPECT_EQ(orbit.yaw, 30.0);
    EXPECT_EQ(orbit.pitch, 15.0);
    EXPECT_EQ(orbit.distance, 4.0);
    EXPECT_EQ(orbit.target, glm::dvec3(1.0, 2.0, 3.0));
    EXPECT_EQ(spec.lights, (std::vector<double>{0.0, 1.0}));
    EXPECT_EQ(spec.background.kind, BackgroundKind::Transparent);
    EXPECT_FALSE(spec.shadows.enabled);
    EXPECT_FALSE(spec.occlusion);
    EXPECT_EQ(spec.bounce, Bounce::None);
    EXPECT_EQ(spec.samples, 1);
    EXPECT_FALSE(api::parse_render_query({{"environment", "default"}}).camera.has_value());
}

TEST(RenderRequest, QueryBaseColorColorsEveryMesh) {
    const RenderSpec spec = api::parse_render_query(
        {{"environment", kRig}, {"mesh", kMeshA}, {"mesh", kMeshB}, {"base_color", "1,0.25,-0"}});
    ASSERT_EQ(spec.objects.size(), 2u);
    for (const api::ObjectSpec& object : spec.objects) {
        EXPECT_EQ(object.base_color, glm::dvec3(1.0, 0.25, 0.0)) << object.mesh;
        EXPECT_EQ(object.transform, glm::dmat4(1.0)) << object.mesh;
    }
    EXPECT_FALSE(
        api::parse_render_query({{"environment", kRig}, {"mesh", kMeshA}}).objects[0].base_color);
    // The other vector parameters' messages, and one of its own without a mesh.
    const auto message = [](const Query& query) -> std::string {
        try {
            api::parse_render_query(query);
        } catch (const InvalidParameter& error) {
            EXPECT_EQ(error.parameter(), "base_color") << error.what();
            return error.what();
        }
        return "accepted";
    };
    const auto with_mesh = [&message](const std::string& color) {
        return message({{"environment", kRig}, {"mesh", kMeshA}, {"base_color", color}});
    };
    EXPECT_EQ(with_mesh("0.5,0.1"),
              "base_color: expected x,y,z (three comma-separated numbers), got '0.5,0.1'");
    EXPECT_EQ(with_mesh("0.5,0.1,0.1,1"),
              "base_color: expected x,y,z (three comma-separated numbers), got '0.5,0.1,0.1,1'");
    EXPECT_EQ(with_mesh("0.5,red,0.1"), "base_color: expected a finite number, got 'red'");
    EXPECT_EQ(with_mesh("0.5,nan,0.1"), "base_color: expected a finite number, got 'nan'");
    EXPECT_EQ(with_mesh("0.5,0.1,1.5"), "base_color: must be in [0, 1], got 1.5");
    EXPECT_EQ(with_mesh("-0.01,0.1,0.1"), "base_color: must be in [0, 1], got -0.01");
    EXPECT_EQ(message({{"environment", kRig}, {"base_color", "0.5,0.1,0.1"}}),
              "base_color: needs a mesh: it sets the base color of every mesh of the query, and "
              "there is none");
    EXPECT_EQ(message({{"environment", kRig},
                       {"mesh", kMeshA},
                       {"base_color", "1,0,0"},
                       {"base_color", "0,1,0"}}),
              "base_color: given more than once");
}

TEST(RenderRequest, TheMemberListsMatchTheParsers) {
    const std::vector<std::string>& members = api::render_json_members();
    for (const char* path : {"environment", "objects/*/transform", "camera/fov_y",
                             "camera/orbit/distance", "shadows/filter", "environment_yaw"}) {
        EXPECT_NE(std::find(members.begin(), members.end(), path), members.end()) << path;
    }
    EXPECT_EQ(members.size(), 17u + 5u + 6u + 4u + 5u);
    // Every query parameter is accepted with a valid value (and the ones it needs).
    const std::map<std::string, Query> valid = {
        {"environment", {}},
        {"mesh", {{"mesh", "default"}}},
        {"base_color", {{"mesh", "default"}, {"base_color", "0.5,0.1,0.1"}}},
        {"variant", {{"mesh", "default"}, {"variant", "Red"}}},
        {"base_color_material",
         {{"mesh", "default"}, {"base_color", "1,0,0"}, {"base_color_material", "Body"}}},
        {"eye", {{"eye", "0,0,3"}, {"target", "0,0,0"}}},
        {"target", {{"eye", "0,0,3"}, {"target", "0,0,0"}}},
        {"up", {{"eye", "0,0,3"}, {"target", "0,0,0"}, {"up", "1,0,0"}}},
        {"fov_y", {{"distance", "2"}, {"fov_y", "50"}}},
        {"yaw", {{"yaw", "0"}}},
        {"pitch", {{"pitch", "0"}}},
        {"distance", {{"distance", "2"}}},
        {"camera", {{"mesh", "default"}, {"camera", "asset:0"}}},
        {"lights", {{"lights", "1"}}},
        {"width", {{"width", "64"}}},
        {"height", {{"height", "64"}}},
        {"format", {{"format", "png"}}},
        {"quality", {{"quality", "50"}}},
        {"exposure", {{"exposure", "1"}}},
        {"tonemap", {{"tonemap", "none"}}},
        {"background", {{"background", "env"}}},
        {"ground", {{"ground", "off"}}},
        {"occlusion", {{"occlusion", "off"}}},
        {"bounce", {{"bounce", "none"}}},
        {"shadows", {{"shadows", "off"}}},
        {"shadow_resolution", {{"shadow_resolution", "64"}}},
        {"shadow_filter", {{"shadow_filter", "hard"}}},
        {"shadow_softness", {{"shadow_softness", "0.5"}}},
        {"shadow_intensity", {{"shadow_intensity", "0.5"}}},
        {"samples", {{"samples", "2"}}},
        {"environment_yaw", {{"environment_yaw", "5"}}}};
    for (const std::string& parameter : api::render_query_parameters()) {
        ASSERT_TRUE(valid.contains(parameter)) << parameter;
        Query query = valid.at(parameter);
        query.insert({"environment", "default"});
        EXPECT_EQ(rejected_parameter(query), "") << parameter;
    }
    EXPECT_EQ(api::render_query_parameters().size(), 31u);
}

TEST(RenderRequest, BackgroundsReadAndPrintCanonically) {
    EXPECT_EQ(api::to_string(api::parse_background("background", "env")), "env");
    EXPECT_EQ(api::to_string(api::parse_background("background", "transparent")), "transparent");
    const Background color = api::parse_background("background", "#0A80fF");
    EXPECT_EQ(color.kind, BackgroundKind::Color);
    EXPECT_EQ(color.color, glm::vec3(10.0f / 255.0f, 128.0f / 255.0f, 1.0f));
    EXPECT_EQ(api::to_string(color), "#0a80ff");
    try {
        api::parse_background("bg", "#0A80f");
        FAIL() << "accepted";
    } catch (const InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "bg");
    }
}

namespace {

std::shared_ptr<const Rig> rig_with_lights(std::size_t count) {
    auto rig = std::make_shared<Rig>();
    rig->lights.resize(count);
    return rig;
}

std::vector<std::shared_ptr<const Mesh>> meshes(std::size_t count) {
    std::vector<std::shared_ptr<const Mesh>> list;
    for (std::size_t i = 0; i < count; ++i) {
        list.push_back(std::make_shared<const Mesh>());
    }
    return list;
}

}  // namespace

TEST(RenderRequest, ToFrameRequestConvertsALookAtCamera) {
    const RenderSpec spec = api::parse_render_json(R"({"environment": "default",
        "objects": [{"mesh": "default", "base_color": [0.5, 0.25, 1],
                     "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 2,3,4,1]}, {"mesh": "default"}],
        "camera": {"eye": [1, 2, 3], "target": [0, 1, 0], "up": [0, 0, 1], "fov_y": 60},
        "lights": [false, true], "width": 320, "height": 200, "ground": false,
        "occlusion": false, "bounce": "none",
        "background": "#ff0080", "exposure": 1.5, "tonemap": "none",
        "shadows": {"enabled": false, "resolution": 256, "filter": "hard"}, "samples": 2,
        "environment_yaw": 90})");
    const auto rig = rig_with_lights(2);
    const auto environment = std::make_shared<const HdrImage>();
    const auto resolved = meshes(2);
    const FrameRequest request = api::to_frame_request(spec, rig, environment, resolved);
    EXPECT_EQ(request.rig, rig);
    EXPECT_EQ(request.environment_map, environment);
    ASSERT_EQ(request.objects.size(), 2u);
    EXPECT_EQ(request.objects[0].mesh, resolved[0]);
    EXPECT_EQ(request.objects[1].mesh, resolved[1]);
    EXPECT_EQ(request.objects[0].transform[3], glm::vec4(2.0f, 3.0f, 4.0f, 1.0f));
    EXPECT_EQ(request.objects[1].transform, glm::mat4(1.0f));
    EXPECT_EQ(request.objects[0].base_color, glm::vec3(0.5f, 0.25f, 1.0f));
    EXPECT_FALSE(request.objects[1].base_color.has_value());
    ASSERT_TRUE(request.camera.has_value());
    EXPECT_EQ(request.camera->eye, glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(request.camera->target, glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(request.camera->up, glm::vec3(0.0f, 0.0f, 1.0f));
    EXPECT_EQ(request.camera->fov_y, 60.0f);
    EXPECT_EQ(request.lights, (std::vector<float>{0.0f, 1.0f}));
    EXPECT_EQ(request.width, 320);
    EXPECT_EQ(request.height, 200);
    EXPECT_FALSE(request.ground);
    EXPECT_FALSE(request.occlusion);
    EXPECT_EQ(request.bounce, Bounce::None);
    EXPECT_FALSE(request.transfer) << "the caller bakes or finds the transfer";
    EXPECT_EQ(request.background.kind, BackgroundKind::Color);
    EXPECT_EQ(request.background.color, glm::vec3(1.0f, 0.0f, 128.0f / 255.0f));
    EXPECT_EQ(request.exposure, 1.5);
    EXPECT_EQ(request.tonemap, ToneMapper::None);
    EXPECT_FALSE(request.shadows.enabled);
    EXPECT_EQ(request.shadows.resolution, 256);
    EXPECT_EQ(request.shadows.filter, ShadowFilter::Hard);
    EXPECT_EQ(request.samples, 2);
    EXPECT_EQ(request.environment_yaw, 90.0);
    EXPECT_FALSE(request.linear);
}

TEST(RenderRequest, TheShadowCatchingGroundAndItsShadowsReadInBothForms) {
    const RenderSpec body = api::parse_render_json(
        R"({"environment": "default", "ground": "shadow",
            "shadows": {"softness": 0.25, "intensity": 0.5}})");
    const RenderSpec query = api::parse_render_query({{"environment", "default"},
                                                      {"ground", "shadow"},
                                                      {"shadow_softness", "0.25"},
                                                      {"shadow_intensity", "0.5"}});
    EXPECT_EQ(body.ground, api::GroundChoice::Shadow);
    EXPECT_EQ(api::render_etag(body), api::render_etag(query));
    const Json canonical = api::normalised_render_json(body);
    EXPECT_EQ(canonical.at("ground"), "shadow");
    EXPECT_EQ(canonical.at("shadows").at("softness"), 0.25);
    EXPECT_EQ(canonical.at("shadows").at("intensity"), 0.5);
    // The booleans keep their spelling, so that an opaque ground's document (and ETag) is the
    // one it had before the shadow catcher.
    EXPECT_EQ(api::normalised_render_json(
                  api::parse_render_query({{"environment", "default"}, {"ground", "off"}}))
                  .at("ground"),
              false);
    const FrameRequest frame = api::to_frame_request(body, rig_with_lights(0), nullptr, {});
    EXPECT_TRUE(frame.ground);
    EXPECT_EQ(frame.ground_look, GroundLook::ShadowCatcher);
    EXPECT_EQ(frame.shadows.softness, 0.25);
    EXPECT_EQ(frame.shadows.intensity, 0.5);
    const FrameRequest opaque = api::to_frame_request(
        api::parse_render_json(R"({"environment": "default"})"), rig_with_lights(0), nullptr, {});
    EXPECT_EQ(opaque.ground_look, GroundLook::Opaque);

    EXPECT_EQ(rejected_member(R"({"environment": "default", "ground": "on"})"), "ground");
    EXPECT_EQ(rejected_member(R"({"environment": "default", "ground": 1})"), "ground");
    EXPECT_EQ(rejected_member(R"({"environment": "default", "shadows": {"intensity": 1.5}})"),
              "shadows/intensity");
    EXPECT_EQ(rejected_member(R"({"environment": "default", "shadows": {"softness": -0.1}})"),
              "shadows/softness");
    EXPECT_EQ(rejected_parameter({{"environment", "default"}, {"ground", "true"}}), "ground");
    EXPECT_EQ(rejected_parameter({{"environment", "default"}, {"shadow_softness", "2"}}),
              "shadow_softness");
}

TEST(RenderRequest, ToFrameRequestOccludesAScenesObjectsOnly) {
    const auto occlusion = [](const std::string& body, std::size_t objects) {
        return api::to_frame_request(api::parse_render_json(body), rig_with_lights(1), nullptr,
                                     meshes(objects))
            .occlusion;
    };
    EXPECT_TRUE(occlusion(R"({"environment": "default", "objects": [{"mesh": "default"}]})", 1));
    EXPECT_FALSE(occlusion(R"({"environment": "default", "objects": [{"mesh": "default"}],
                               "occlusion": false})",
                           1));
    // Nothing to occlude, nothing to bake: the unoccluded frame is the same.
    EXPECT_FALSE(occlusion(R"({"environment": "default"})", 0));
}

TEST(RenderRequest, ToFrameRequestConvertsAnOrbitAndTheExrFormat) {
    const RenderSpec spec = api::parse_render_query({{"environment", "default"},
                                                     {"mesh", "default"},
                                                     {"yaw", "90"},
                                                     {"pitch", "0"},
                                                     {"distance", "2"},
                                                     {"target", "1,0.5,0"},
                                                     {"fov_y", "30"},
                                                     {"format", "exr"}});
    const FrameRequest request =
        api::to_frame_request(spec, rig_with_lights(3), nullptr, meshes(1));
    ASSERT_TRUE(request.camera.has_value());
    // Yaw 90 turns the eye from +Z to +X (camera.hpp).
    EXPECT_NEAR(glm::length(request.camera->eye - glm::vec3(3.0f, 0.5f, 0.0f)), 0.0f, 1e-5f);
    EXPECT_EQ(request.camera->target, glm::vec3(1.0f, 0.5f, 0.0f));
    EXPECT_EQ(request.camera->fov_y, 30.0f);
    const Camera expected = orbit_camera({90.0f, 0.0f, 2.0f, {1.0f, 0.5f, 0.0f}}, 30.0f);
    EXPECT_EQ(request.camera->eye, expected.eye);
    EXPECT_EQ(request.camera->up, expected.up);
    EXPECT_TRUE(request.linear);
    EXPECT_TRUE(request.lights.empty());
    // No camera: the automatic framing, resolved here as the renderer would (so that the
    // server can name it in X-Oer-Camera); with no objects, of the unit cube about the origin.
    const api::RenderSpec framed = api::parse_render_query({{"environment", "default"}});
    const FrameRequest automatic = api::to_frame_request(framed, rig_with_lights(0), nullptr, {});
    ASSERT_TRUE(automatic.camera.has_value());
    const Camera expected_framing =
        frame_bounds(enclosing_bounds({}), 45.0f, float(framed.width) / float(framed.height));
    EXPECT_EQ(automatic.camera->eye, expected_framing.eye);
    EXPECT_EQ(automatic.camera->target, expected_framing.target);
    EXPECT_NE(automatic.camera->eye, Camera{}.eye) << "not the fixed default camera";
}

namespace {

// NDC (x, y) of a world point through the camera, as the renderer projects it.
glm::vec2 projected(const Camera& camera, float aspect, const glm::vec3& point) {
    const glm::vec4 clip = projection_matrix(camera, aspect, 0.01f, 100.0f) * view_matrix(camera) *
                           glm::vec4(point, 1);
    return glm::vec2(clip) / clip.w;
}

}  // namespace

TEST(RenderRequest, AnOrbitWithoutTargetOrDistanceFramesTheScene) {
    // GET /v1/render?environment=default&mesh=default&yaw=60&pitch=20, 800x600.
    const RenderSpec spec = api::parse_render_query({{"environment", "default"},
                                                     {"mesh", "default"},
                                                     {"yaw", "60"},
                                                     {"pitch", "20"},
                                                     {"width", "800"},
                                                     {"height", "600"}});
    const auto product = std::make_shared<const Mesh>(make_default_product());
    const FrameRequest request =
        api::to_frame_request(spec, rig_with_lights(0), nullptr, {product});
    ASSERT_TRUE(request.camera.has_value());
    const Bounds& bounds = product->bounds;
    const float aspect = 800.0f / 600.0f;
    // The camera expected: the orbit's angles about the bounds' centre, from the automatic
    // framing's distance at that pitch (frame_orbit).
    const Camera automatic =
        frame_orbit(0.0f, 20.0f, std::nullopt, std::nullopt, bounds, 45.0f, aspect);
    const Camera expected = orbit_camera(
        {60.0f, 20.0f, glm::length(automatic.eye - automatic.target), bounds.centre()}, 45.0f);
    EXPECT_NEAR(glm::length(request.camera->eye - expected.eye), 0.0f, 1e-5f);
    EXPECT_EQ(request.camera->target, bounds.centre());
    // The product's bounds project inside the frame, their centre onto the image centre.
    glm::vec2 low(1e9f), high(-1e9f);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec2 p = projected(
            *request.camera, aspect,
            {(corner & 1) ? bounds.max.x : bounds.min.x, (corner & 2) ? bounds.max.y : bounds.min.y,
             (corner & 4) ? bounds.max.z : bounds.min.z});
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    EXPECT_GT(low.x, -1.0f);
    EXPECT_GT(low.y, -1.0f);
    EXPECT_LT(high.x, 1.0f);
    EXPECT_LT(high.y, 1.0f);
    // ... and fill a good part of it: framed, not lost in the distance.
    EXPECT_GT(high.y - low.y, 1.0f);
    EXPECT_NEAR(glm::length(projected(*request.camera, aspect, bounds.centre())), 0.0f, 1e-5f);

    // The objects' transforms count: the product doubled and moved frames about its new centre.
    const RenderSpec moved = api::parse_render_json(R"({"environment": "default",
        "objects": [{"mesh": "default", "transform": [2,0,0,0, 0,2,0,0, 0,0,2,0, 5,0,0,1]}],
        "camera": {"orbit": {"yaw": 60, "pitch": 20}}, "width": 800, "height": 600})");
    const Camera moved_camera =
        *api::to_frame_request(moved, rig_with_lights(0), nullptr, {product}).camera;
    EXPECT_NEAR(glm::length(moved_camera.target - (2.0f * bounds.centre() + glm::vec3(5, 0, 0))),
                0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(moved_camera.eye - moved_camera.target),
                2.0f * glm::length(expected.eye - expected.target), 1e-4f);

    // The framing depends on the aspect ratio, not the size: a 160x120 preview frames alike.
    const RenderSpec preview = api::parse_render_query({{"environment", "default"},
                                                        {"mesh", "default"},
                                                        {"yaw", "60"},
                                                        {"pitch", "20"},
                                                        {"width", "160"},
                                                        {"height", "120"},
                                                        {"samples", "1"}});
    const Camera preview_camera =
        *api::to_frame_request(preview, rig_with_lights(0), nullptr, {product}).camera;
    EXPECT_EQ(preview_camera.eye, request.camera->eye);
    EXPECT_EQ(preview_camera.target, request.camera->target);
}

TEST(RenderRequest, AnOrbitsGivenTargetAndDistanceWin) {
    const auto product = std::make_shared<const Mesh>(make_default_product());
    const RenderSpec spec = api::parse_render_query({{"environment", "default"},
                                                     {"mesh", "default"},
                                                     {"yaw", "60"},
                                                     {"pitch", "20"},
                                                     {"distance", "7"},
                                                     {"target", "1,2,3"}});
    const Camera camera =
        *api::to_frame_request(spec, rig_with_lights(0), nullptr, {product}).camera;
    const Camera expected = orbit_camera({60.0f, 20.0f, 7.0f, {1.0f, 2.0f, 3.0f}}, 45.0f);
    EXPECT_EQ(camera.target, expected.target);
    EXPECT_EQ(camera.eye, expected.eye);
    // A target alone: the distance keeps the whole product in the frame from there.
    const RenderSpec target_only = api::parse_render_query(
        {{"environment", "default"}, {"mesh", "default"}, {"yaw", "0"}, {"target", "0,0,0"}});
    const Camera from_target =
        *api::to_frame_request(target_only, rig_with_lights(0), nullptr, {product}).camera;
    EXPECT_EQ(from_target.target, glm::vec3(0.0f));
    const Bounds& bounds = product->bounds;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec2 p = projected(
            from_target, 1.0f,
            {(corner & 1) ? bounds.max.x : bounds.min.x, (corner & 2) ? bounds.max.y : bounds.min.y,
             (corner & 4) ? bounds.max.z : bounds.min.z});
        EXPECT_LT(std::max(std::abs(p.x), std::abs(p.y)), 1.0f) << "corner " << corner;
    }
}

// With the ground on, an orbit cannot go under the floor (the scene's lowest y): its pitch is
// raised until the eye is kFloorClearanceDegrees above it, and the resolved camera says so; with
// the ground off, it goes where it is asked. A look-at eye under the floor with the ground on is
// a mistake the request names (422), and so is an orbit no pitch keeps above the floor.
TEST(RenderRequest, AnOrbitStaysAboveTheFloorAndALookAtUnderItIsRefused) {
    const auto product = std::make_shared<const Mesh>(make_default_product());
    const float floor = product->bounds.min.y;
    const auto camera_of = [&](Query query) {
        query.insert({{"environment", "default"}, {"mesh", "default"}});
        return api::resolved_camera(api::parse_render_query(query), {product});
    };
    const auto pitch_of = [](const Camera& camera) {
        const glm::vec3 offset = camera.eye - camera.target;
        return glm::degrees(std::asin(offset.y / glm::length(offset)));
    };
    for (const std::string pitch : {"-80", "-45", "-30"}) {
        const Camera clamped = camera_of({{"yaw", "40"}, {"pitch", pitch}});
        const float distance = glm::length(clamped.eye - clamped.target);
        EXPECT_NEAR(clamped.eye.y - floor,
                    distance * std::sin(glm::radians(kFloorClearanceDegrees)), 1e-3f * distance)
            << pitch;
        EXPECT_GT(pitch_of(clamped), std::stof(pitch)) << pitch;
        const Camera free = camera_of({{"yaw", "40"}, {"pitch", pitch}, {"ground", "off"}});
        EXPECT_NEAR(pitch_of(free), std::stof(pitch), 1e-3f);
        EXPECT_LT(free.eye.y, floor) << pitch;
    }
    // A pitch high enough already is left alone, below the target's height too, distance given
    // or not.
    EXPECT_NEAR(pitch_of(camera_of({{"pitch", "-5"}})), -5.0f, 1e-3f);
    const Camera near = camera_of({{"pitch", "-20"}, {"distance", "0.5"}});
    EXPECT_NEAR(pitch_of(near), -20.0f, 1e-3f);
    EXPECT_GT(near.eye.y, floor);
    // The look-at eye at or under the floor: 422 naming the eye.
    const auto refused = [&](const Query& query, const std::string& parameter) {
        try {
            camera_of(query);
            ADD_FAILURE() << "accepted";
        } catch (const api::InvalidParameter& error) {
            EXPECT_EQ(error.parameter(), parameter) << error.what();
            EXPECT_NE(std::string(error.what()).find("floor"), std::string::npos) << error.what();
        }
    };
    refused({{"eye", "0,-0.5,3"}, {"target", "0,1,0"}}, "eye");
    refused({{"eye", "0," + std::to_string(floor) + ",3"}, {"target", "0,1,0"}}, "eye");
    EXPECT_NO_THROW(camera_of({{"eye", "0,-0.5,3"}, {"target", "0,1,0"}, {"ground", "off"}}));
    // An orbit about a point under the floor, close: no pitch clears the floor.
    refused({{"target", "0,-2,0"}, {"distance", "1"}}, "target");
}

TEST(RenderRequest, AnAbsentOrbitTargetAndDistanceStayAbsentAndKeepOneEtag) {
    const Query query = {
        {"environment", "default"}, {"mesh", "default"}, {"yaw", "60"}, {"pitch", "20"}};
    const Json body = {{"environment", "default"},
                       {"objects", {{{"mesh", "default"}}}},
                       {"camera", {{"orbit", {{"yaw", 60}, {"pitch", 20}}}}}};
    const Json canonical = api::normalised_render_json(api::parse_render_query(query));
    EXPECT_EQ(canonical.at("camera"),
              Json({{"orbit", {{"yaw", 60.0}, {"pitch", 20.0}}}, {"fov_y", 45.0}}));
    EXPECT_EQ(api::render_etag(api::parse_render_query(query)), etag_of_json(body));
    EXPECT_EQ(api::normalised_render_json(api::parse_render_json(canonical.dump())), canonical);
    // The framing's distance is not the old default's: asking for distance 3 is another request.
    Query with_distance = query;
    with_distance.insert({"distance", "3"});
    EXPECT_NE(api::render_etag(api::parse_render_query(with_distance)),
              api::render_etag(api::parse_render_query(query)));
}

TEST(RenderRequest, ToFrameRequestChecksTheLightsAndTheResolvedAssets) {
    const RenderSpec spec = api::parse_render_json(
        R"({"environment": "default", "objects": [{"mesh": "default"}], "lights": [true, false]})");
    try {
        api::to_frame_request(spec, rig_with_lights(3), nullptr, meshes(1));
        FAIL() << "accepted 2 switches for 3 lights";
    } catch (const InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "lights");
    }
    EXPECT_NO_THROW(api::to_frame_request(spec, rig_with_lights(2), nullptr, meshes(1)));
    for (const auto& resolved :
         {meshes(0), meshes(2), std::vector<std::shared_ptr<const Mesh>>{nullptr}}) {
        try {
            api::to_frame_request(spec, rig_with_lights(2), nullptr, resolved);
            FAIL() << "accepted " << resolved.size() << " meshes for 1 object";
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::Internal);
        }
    }
    try {
        api::to_frame_request(spec, nullptr, nullptr, meshes(1));
        FAIL() << "accepted no rig";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::Internal);
    }
}

TEST(RenderRequest, LightsAreWeightsInBothForms) {
    // docs/design.md section 2, dimmable lights: true and false are 1 and 0.
    EXPECT_EQ(api::parse_render_json(with("lights", "[true, 0.3, 0, false, 4, 1]")).lights,
              (std::vector<double>{1.0, 0.3, 0.0, 0.0, 4.0, 1.0}));
    EXPECT_EQ(
        api::parse_render_query({{"environment", kRig}, {"lights", "1,0.3,0,4,2.5e-1"}}).lights,
        (std::vector<double>{1.0, 0.3, 0.0, 4.0, 0.25}));
    EXPECT_EQ(api::parse_render_query({{"environment", kRig}, {"lights", "1,0"}}).lights,
              (std::vector<double>{1.0, 0.0}));
    // Out of [0, 4], not a number or an empty entry: 422 naming lights, the index in the path
    // (body) or the message (query).
    for (const auto& [value, member] :
         std::vector<std::pair<std::string, std::string>>{{"[1, 4.001]", "lights/1"},
                                                          {"[-0.5]", "lights/0"},
                                                          {"[1, 1, null]", "lights/2"},
                                                          {R"(["0.5"])", "lights/0"}}) {
        EXPECT_EQ(rejected_member(with("lights", value)), member) << value;
    }
    for (const std::string text : {"1,4.001", "1,-0.5", "1,nan", "1,inf", "1,,1", "1,0.5x"}) {
        try {
            api::parse_render_query({{"environment", kRig}, {"lights", text}});
            ADD_FAILURE() << "accepted lights=" << text;
        } catch (const InvalidParameter& error) {
            EXPECT_EQ(error.parameter(), "lights") << text;
            EXPECT_NE(std::string(error.what()).find("entry 1"), std::string::npos) << error.what();
        }
    }
}

TEST(RenderRequest, OnOffAndTheirWeightsShareTheEtagAndOtherWeightsDoNot) {
    const std::string on_off = etag_of_json({{"environment", kRig}, {"lights", {true, false}}});
    EXPECT_EQ(etag_of_json({{"environment", kRig}, {"lights", {1, 0}}}), on_off);
    EXPECT_EQ(etag_of_json({{"environment", kRig}, {"lights", {1.0, -0.0}}}), on_off);
    EXPECT_EQ(api::render_etag(api::parse_render_query({{"environment", kRig}, {"lights", "1,0"}})),
              on_off);
    EXPECT_NE(etag_of_json({{"environment", kRig}, {"lights", {1, 0.5}}}), on_off);
    EXPECT_NE(etag_of_json({{"environment", kRig}, {"lights", {1, 0.5}}}),
              etag_of_json({{"environment", kRig}, {"lights", {1, 0.25}}}));
    EXPECT_EQ(api::normalised_render_json(api::parse_render_json(with("lights", "[true, 0.5]")))
                  .at("lights"),
              Json({1.0, 0.5}));
}

TEST(RenderRequest, ToFrameRequestPassesTheWeights) {
    const RenderSpec spec = api::parse_render_json(
        R"({"environment": "default", "objects": [{"mesh": "default"}], "lights": [true, 0.25, 4]})");
    EXPECT_EQ(api::to_frame_request(spec, rig_with_lights(3), nullptr, meshes(1)).lights,
              (std::vector<float>{1.0f, 0.25f, 4.0f}));
}

// The specular cube is needed by a glossy material that a primitive draws, under an hdr rig:
// not by a Lambertian mesh, an unused glossy material, or a thesis rig.
TEST(RenderRequest, NeedsSpecularOnlyForADrawnGlossyMaterialUnderAnHdrRig) {
    Mesh lambertian;
    lambertian.materials.resize(2);
    lambertian.materials[0].model = ShadingModel::Lambertian;
    lambertian.materials[1].model = ShadingModel::MetallicRoughness;  // unused
    lambertian.primitives.resize(1);
    lambertian.primitives[0].material = 0;
    Mesh glossy = lambertian;
    glossy.primitives.resize(2);
    glossy.primitives[1].material = 1;

    FrameRequest request;
    request.rig = std::make_shared<const Rig>();
    request.objects.push_back({std::make_shared<const Mesh>(lambertian), glm::mat4(1.0f), {}});
    EXPECT_FALSE(needs_specular(request));
    request.objects.push_back({std::make_shared<const Mesh>(glossy), glm::mat4(1.0f), {}});
    EXPECT_TRUE(needs_specular(request));
    Rig thesis;
    thesis.model = LightingModel::Thesis;
    request.rig = std::make_shared<const Rig>(thesis);
    EXPECT_FALSE(needs_specular(request));
    request.rig = std::make_shared<const Rig>();
    request.objects = {{std::make_shared<const Mesh>(make_default_product()), glm::mat4(1.0f), {}}};
    EXPECT_TRUE(needs_specular(request)) << "the default product's stand is glossy";
}
