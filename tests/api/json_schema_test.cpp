// The JSON-Schema validator of tests/support (which holds the live server's answers to
// api/openapi.yaml in the integration tests) and the conversion of the spec to JSON: documents
// the api writes pass, and every kind of violation is caught and named.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_schema.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/api/render_request.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/mesh/default_product.hpp"
#include "openapi_spec.hpp"

using namespace oer;
using Json = nlohmann::json;
using oer::testing::openapi_schema_errors;

namespace {

std::string joined(const std::vector<std::string>& errors) {
    std::string text;
    for (const std::string& error : errors) {
        text += error + "\n";
    }
    return text;
}

Json some_rig() {
    RigOptions options;
    options.light_count = 2;
    options.sh_order = 3;
    Json rig = api::rig_to_json(build_rig(make_default_environment(128, 64), {}, options),
                                std::string(64, 'a'));
    return rig;
}

}  // namespace

TEST(JsonSchemaOpenApi, TheWholeSpecConvertsWithItsStructure) {
    const Json& spec = oer::testing::openapi_spec().json();
    EXPECT_EQ(spec.at("openapi"), "3.1.0");
    EXPECT_EQ(spec.at("info").at("version"), "0.1.0");
    EXPECT_TRUE(spec.at("info").at("description").get<std::string>().find("\n\n") !=
                std::string::npos);
    const Json& upload = spec.at("paths").at("/v1/environments").at("post");
    ASSERT_TRUE(upload.at("parameters").is_array());
    EXPECT_EQ(upload.at("parameters")[0].at("name"), "light_count");
    EXPECT_EQ(upload.at("parameters")[0].at("schema").at("oneOf")[1].at("const"), "auto");
    EXPECT_EQ(upload.at("responses").at("201").at("content").at("application/json").at("schema"),
              Json({{"$ref", "#/components/schemas/RigUpload"}}));
    EXPECT_EQ(spec.at("paths").at("/v1/render").at("get").at("parameters")[0],
              Json({{"$ref", "#/components/parameters/IfNoneMatch"}}));
    EXPECT_EQ(upload.at("security"), Json::parse(R"([{}, {"apiKey": []}])"));
    const Json& schemas = spec.at("components").at("schemas");
    EXPECT_EQ(schemas.at("Background").at("pattern"), "^(env|transparent|#[0-9a-fA-F]{6})$");
    EXPECT_EQ(schemas.at("RenderRequest")
                  .at("properties")
                  .at("shadows")
                  .at("properties")
                  .at("resolution")
                  .at("enum"),
              Json::parse("[64, 128, 256, 512, 1024, 2048, 4096, 8192]"));
    EXPECT_EQ(schemas.at("Status").at("properties").at("status").at("enum"),
              Json::parse(R"(["ok", "ready"])"));
    EXPECT_EQ(spec.at("components").at("headers").at("ETag").at("schema").at("pattern"),
              "^\"[0-9a-f]{64}\"$");
    const Json* ground = nullptr;
    for (const Json& parameter : spec.at("paths").at("/v1/render").at("get").at("parameters")) {
        if (parameter.value("name", "") == "ground") {
            ground = &parameter;
        }
    }
    ASSERT_NE(ground, nullptr);
    EXPECT_EQ(ground->at("schema").at("enum"), Json::parse(R"(["on", "off", "shadow"])"));
}

TEST(JsonSchema, DocumentsTheApiWritesMatch) {
    Json rig = some_rig();
    EXPECT_EQ(joined(openapi_schema_errors(rig, "#/components/schemas/Rig")), "");
    rig["cached"] = true;
    EXPECT_EQ(joined(openapi_schema_errors(rig, "#/components/schemas/RigUpload")), "");
    Json mesh = api::mesh_to_json(make_default_product(), "default", MeshFormat::Glb);
    EXPECT_EQ(joined(openapi_schema_errors(mesh, "#/components/schemas/Mesh")), "");
    for (const char* body : {R"({"environment": "default"})",
                             R"({"environment": "default", "camera": {"orbit": {"yaw": 3}}})",
                             R"({"environment": "default", "camera": {"eye": [0, 1, 3],
                                 "target": [0, 1, 0]}, "format": "exr"})"}) {
        const Json request = Json::parse(body);
        EXPECT_EQ(joined(openapi_schema_errors(request, "#/components/schemas/RenderRequest")), "")
            << body;
        EXPECT_EQ(
            joined(openapi_schema_errors(api::normalised_render_json(api::parse_render_json(body)),
                                         "#/components/schemas/RenderRequest")),
            "")
            << body;
    }
}

TEST(JsonSchema, EachKindOfViolationIsCaughtAndNamed) {
    const auto errors = [](const Json& value, const std::string& schema) {
        return joined(openapi_schema_errors(value, "#/components/schemas/" + schema));
    };
    Json rig = some_rig();
    EXPECT_NE(errors(rig, "RigUpload").find("lacks required member \"cached\""),
              std::string::npos);  // allOf + required
    Json extra = rig;
    extra["bogus"] = 1;
    EXPECT_NE(errors(extra, "Rig").find("\"bogus\""), std::string::npos);  // additionalProperties
    Json wrong_type = rig;
    wrong_type["source"]["width"] = "wide";
    EXPECT_NE(errors(wrong_type, "Rig").find("/source/width"), std::string::npos);  // type
    Json fractional = rig;
    fractional["source"]["width"] = 2.5;
    EXPECT_NE(errors(fractional, "Rig").find("/source/width"), std::string::npos);  // integer
    Json out_of_range = rig;
    out_of_range["lights"][0]["luminance_share"] = 1.5;
    EXPECT_NE(errors(out_of_range, "Rig").find("/lights/0/luminance_share"),
              std::string::npos);  // maximum, through $ref and items
    Json short_vector = rig;
    short_vector["lights"][0]["direction"] = {0, 1};
    EXPECT_NE(errors(short_vector, "Rig").find("/lights/0/direction"), std::string::npos);
    Json bad_id = rig;
    bad_id["id"] = std::string(64, 'A');
    EXPECT_NE(errors(bad_id, "Rig").find("/id"), std::string::npos);  // pattern
    Json bad_enum = rig;
    bad_enum["lighting_model"] = "pbr";
    EXPECT_NE(errors(bad_enum, "Rig").find("/lighting_model"), std::string::npos);  // enum
    Json bad_timing = rig;
    bad_timing["timings_ms"]["x"] = -1;
    EXPECT_NE(errors(bad_timing, "Rig").find("/timings_ms/x"),
              std::string::npos);  // additionalProperties as a schema
    Json bad_option = rig;
    bad_option["options"]["light_count"] = "many";
    EXPECT_NE(errors(bad_option, "Rig").find("oneOf"), std::string::npos);  // oneOf, const
    // An orbit camera may not carry look-at members (oneOf with not/anyOf).
    EXPECT_NE(errors(Json::parse(R"({"environment": "default", "camera": {"orbit": {},
                                    "up": [0, 1, 0]}})"),
                     "RenderRequest"),
              "");
    EXPECT_EQ(errors(Json::parse(R"({"environment": "default", "camera": {"orbit": {},
                                    "fov_y": 30}})"),
                     "RenderRequest"),
              "");
    // Nullable types of 3.1 and keywords the validator does not know.
    const Json root = Json::object();
    EXPECT_TRUE(oer::testing::schema_errors(nullptr, {{"type", {"string", "null"}}}, root).empty());
    EXPECT_FALSE(oer::testing::schema_errors(3, {{"type", {"string", "null"}}}, root).empty());
    EXPECT_FALSE(oer::testing::schema_errors(3, {{"multipleOf", 2}}, root).empty());
}

TEST(JsonSchema, ABrokenSchemaThrowsNamingItsKeyword) {
    // A bound written as a string, a pattern as a number: the spec is broken, which is not a
    // violation by the value.
    for (const auto& [schema, keyword] : {std::pair{Json{{"minLength", "3"}}, "minLength"},
                                          {Json{{"pattern", 7}}, "pattern"},
                                          {Json{{"required", "id"}}, "required"}}) {
        SCOPED_TRACE(schema.dump());
        try {
            oer::testing::schema_errors(Json::object(), schema, schema);
            oer::testing::schema_errors("text", schema, schema);
            ADD_FAILURE() << "no exception";
        } catch (const std::runtime_error& error) {
            EXPECT_EQ(std::string(error.what()).find(std::string("schema keyword ") + keyword), 0u)
                << error.what();
        }
    }
}
