// api/openapi.yaml against the parsers and writers it describes: the same member and parameter
// names, enums, ranges and defaults, and schemas that the documents the api writes satisfy.
//
// The spec is read by tests/support/openapi_spec.hpp (a reader of the plain YAML subset the
// file keeps to), shared with the integration tests. The schema checks cover the keywords the file
// uses for documents (type, enum, pattern, minimum, maximum, minItems, maxItems, required,
// properties, additionalProperties, items, $ref); a full validator checks live answers elsewhere.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "oer/api/mesh_json.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/render_parameters.hpp"
#include "oer/api/render_request.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/api/version.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/mesh/default_product.hpp"
#include "openapi_spec.hpp"
#include "rejected_parameter.hpp"

using namespace oer;
using oer::testing::rejected_member;
using oer::testing::rejected_parameter;
using Json = nlohmann::json;

namespace {

using oer::testing::scalar_json;
using oer::testing::Spec;
using oer::testing::trim;
using oer::testing::unquote;

// "[a, 'b', 3]" -> {"a", "b", "3"}
std::vector<std::string> flow_list(const std::string& text) {
    const auto items = oer::testing::flow_list(text);
    if (!items) {
        ADD_FAILURE() << "not a one-line flow list: " << text;
        return {};
    }
    return *items;
}

const Spec& spec() {
    return oer::testing::openapi_spec();
}

Spec::Block schema(const std::string& name) {
    return spec().at(spec().document(), {"components", "schemas", name});
}

// "camera/orbit/yaw" -> the schema of that member inside RenderRequest.
Spec::Block render_member(const std::string& path) {
    Spec::Block block = schema("RenderRequest");
    std::stringstream in(path);
    for (std::string segment; std::getline(in, segment, '/');) {
        block = segment == "*" ? spec().child(block, "items")
                               : spec().child(spec().child(block, "properties"), segment);
    }
    return block;
}

Spec::Block render_get_parameters() {
    return spec().at(spec().document(), {"paths", "/v1/render", "get", "parameters"});
}

Spec::Block environment_upload_parameters() {
    return spec().at(spec().document(), {"paths", "/v1/environments", "post", "parameters"});
}

// The schema of the query parameter `name` in a block of parameters.
Spec::Block parameter_schema(const Spec::Block& parameters, const std::string& name) {
    for (const Spec::Block& parameter : spec().items(parameters)) {
        if (spec().value(parameter, "name") == name) {
            return spec().child(parameter, "schema");
        }
    }
    return {};
}

bool is_integer(const Json& value) {
    return value.is_number_integer() ||
           (value.is_number_float() && value.get<double>() == std::floor(value.get<double>()));
}

// Checks `value` against the schema keywords this file uses; `where` names it in failures.
void check_document(const Json& value, Spec::Block block, const std::string& where) {
    block = spec().resolved(block);
    ASSERT_TRUE(block.found) << where;
    if (const auto type = spec().value(block, "type")) {
        const bool matches = *type == "object"    ? value.is_object()
                             : *type == "array"   ? value.is_array()
                             : *type == "string"  ? value.is_string()
                             : *type == "boolean" ? value.is_boolean()
                             : *type == "integer" ? is_integer(value)
                             : *type == "number"  ? value.is_number()
                                                  : false;
        ASSERT_TRUE(matches) << where << " is " << value.dump() << ", not of type " << *type;
    }
    if (const auto names = spec().value(block, "enum")) {
        bool listed = false;
        for (const std::string& name : flow_list(*names)) {
            listed = listed || scalar_json(name) == value || Json(name) == value;
        }
        EXPECT_TRUE(listed) << where << " = " << value.dump() << " is not in " << *names;
    }
    if (const auto pattern = spec().value(block, "pattern")) {
        EXPECT_TRUE(std::regex_search(value.get<std::string>(), std::regex(unquote(*pattern))))
            << where << " = " << value.dump() << " does not match " << *pattern;
    }
    if (const auto minimum = spec().value(block, "minimum")) {
        EXPECT_GE(value.get<double>(), std::stod(*minimum)) << where;
    }
    if (const auto maximum = spec().value(block, "maximum")) {
        EXPECT_LE(value.get<double>(), std::stod(*maximum)) << where;
    }
    if (value.is_array()) {
        if (const auto min_items = spec().value(block, "minItems")) {
            EXPECT_GE(value.size(), std::stoul(*min_items)) << where;
        }
        if (const auto max_items = spec().value(block, "maxItems")) {
            EXPECT_LE(value.size(), std::stoul(*max_items)) << where;
        }
        const Spec::Block items = spec().child(block, "items");
        for (std::size_t i = 0; i < value.size(); ++i) {
            check_document(value[i], items, where + "/" + std::to_string(i));
        }
    }
    if (value.is_object()) {
        if (const auto required = spec().value(block, "required")) {
            for (const std::string& name : flow_list(*required)) {
                EXPECT_TRUE(value.contains(name)) << where << " lacks required " << name;
            }
        }
        const Spec::Block properties = spec().child(block, "properties");
        // additionalProperties is either "false" or, with no inline value, the schema of every
        // member not listed.
        const bool closed = spec().value(block, "additionalProperties").has_value();
        const Spec::Block additional = spec().child(block, "additionalProperties");
        for (const auto& [key, member] : value.items()) {
            const Spec::Block property = spec().child(properties, key);
            if (property.found) {
                check_document(member, property, where + "/" + key);
            } else if (!closed && additional.found) {
                check_document(member, additional, where + "/" + key);
            } else {
                EXPECT_NE(spec().value(block, "additionalProperties"), "false")
                    << where << " has " << key << ", which the schema does not allow";
            }
        }
    }
}

// The default a member's schema declares (its own, else its reference's), as JSON.
std::optional<Json> default_of(const Spec::Block& block) {
    if (const auto text = spec().value(block, "default")) {
        return scalar_json(*text);
    }
    const Spec::Block target = spec().resolved(block);
    if (const auto text = spec().value(target, "default")) {
        return scalar_json(*text);
    }
    return std::nullopt;
}

// The values just inside and just outside a schema's bounds and enums, as JSON.
struct Probes {
    std::vector<Json> accepted;
    std::vector<Json> rejected;
};

Probes probes(const Spec::Block& member) {
    const Spec::Block block = spec().resolved(member);
    const bool integer = spec().value(block, "type") == "integer";
    Probes result;
    for (const auto& [key, outwards] : {std::pair{"minimum", -1}, std::pair{"maximum", 1}}) {
        const auto text = spec().value(block, key);
        if (!text) {
            continue;
        }
        if (integer) {
            const long long bound = std::stoll(*text);
            result.accepted.push_back(bound);
            result.rejected.push_back(bound + outwards);
        } else {
            const double bound = std::stod(*text);
            result.accepted.push_back(bound);
            result.rejected.push_back(bound + outwards * (std::abs(bound) * 1e-6 + 1e-12));
        }
    }
    if (const auto names = spec().value(block, "enum")) {
        for (const std::string& name : flow_list(*names)) {
            result.accepted.push_back(scalar_json(name));
        }
        result.rejected.push_back(integer ? Json(3) : Json("bogus"));
    }
    return result;
}

// A query value as text: "on" and 2048 as they would appear in a URL.
std::string query_text(const Json& value) {
    if (value.is_string()) {
        return value.get<std::string>();
    }
    return value.is_number_integer() ? value.dump() : api::number_text(value.get<double>());
}

}  // namespace

TEST(OpenApi, IsPlainYamlAndEveryReferenceResolves) {
    ASSERT_FALSE(spec().lines().empty()) << oer::testing::openapi_path();
    EXPECT_EQ(spec().lines()[0], "openapi: 3.1.0");
    EXPECT_EQ(spec().value(spec().child(spec().document(), "info"), "version"), api::kVersion);
    int references = 0;
    for (const std::string& line : spec().lines()) {
        EXPECT_EQ(line.find('\t'), std::string::npos) << line;
        EXPECT_TRUE(trim(line).empty() || line.find_first_not_of(' ') % 2 == 0)
            << "odd indentation: " << line;
        const std::string text = trim(line);
        if (text.rfind("$ref: ", 0) == 0 || text.rfind("- $ref: ", 0) == 0) {
            const std::string target = text.substr(text.find("'"));
            EXPECT_TRUE(spec().reference(target).found) << "dangling " << target;
            ++references;
        }
    }
    EXPECT_GT(references, 40);
}

TEST(OpenApi, RenderRequestHasExactlyTheParsersMembers) {
    std::map<std::string, std::set<std::string>> parser_levels;
    for (const std::string& path : api::render_json_members()) {
        EXPECT_TRUE(render_member(path).found) << path << " is not in RenderRequest";
        const std::size_t slash = path.rfind('/');
        parser_levels[slash == std::string::npos ? "" : path.substr(0, slash)].insert(
            slash == std::string::npos ? path : path.substr(slash + 1));
    }
    // Each level of the schema lists exactly those members, and no others are allowed.
    for (const auto& [level, members] : parser_levels) {
        const Spec::Block object = level.empty() ? schema("RenderRequest") : render_member(level);
        const std::vector<std::string> keys = spec().keys(spec().child(object, "properties"));
        EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()), members)
            << "at '" << level << "'";
        EXPECT_EQ(spec().value(object, "additionalProperties"), "false") << "at '" << level << "'";
    }
    EXPECT_EQ(parser_levels.size(), 5u);
}

TEST(OpenApi, RenderRequestDefaultsAreTheParsers) {
    const Json orbit = api::normalised_render_json(
        api::parse_render_json(R"({"environment": "default", "camera": {"orbit": {}}})"));
    const Json look_at = api::normalised_render_json(api::parse_render_json(
        R"({"environment": "default", "camera": {"eye": [0, 0, 3], "target": [0, 0, 0]}})"));
    int defaults = 0;
    for (const std::string& path : api::render_json_members()) {
        const std::optional<Json> declared = default_of(render_member(path));
        if (!declared || path.find('*') != std::string::npos) {
            continue;
        }
        const Json& canonical =
            path.rfind("camera/", 0) == 0 && path.rfind("camera/orbit", 0) != 0 ? look_at : orbit;
        EXPECT_EQ(canonical.at(Json::json_pointer("/" + path)), *declared) << path;
        ++defaults;
    }
    // The orbit's distance and target have none: absent, they are the automatic framing's.
    EXPECT_EQ(defaults, 23);
    EXPECT_FALSE(default_of(render_member("camera/orbit/distance")).has_value());
    EXPECT_FALSE(default_of(render_member("camera/orbit/target")).has_value());
}

TEST(OpenApi, RenderRequestBoundsAndEnumsAreTheParsers) {
    int probed = 0;
    for (const std::string& path : api::render_json_members()) {
        const Probes values = probes(render_member(path));
        for (const bool accept : {true, false}) {
            for (const Json& value : accept ? values.accepted : values.rejected) {
                Json body = {{"environment", "default"}};
                if (path.rfind("camera/", 0) == 0 && path.rfind("camera/orbit", 0) != 0) {
                    body["camera"] = {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}};
                }
                body[Json::json_pointer("/" + path)] = value;
                EXPECT_EQ(rejected_member(body.dump()), accept ? "" : path) << body.dump();
                ++probed;
            }
        }
    }
    EXPECT_GT(probed, 50);
    const api::RenderLimits limits;
    EXPECT_EQ(spec().value(render_member("width"), "maximum"), std::to_string(limits.max_width));
    EXPECT_EQ(spec().value(render_member("height"), "maximum"), std::to_string(limits.max_height));
    EXPECT_EQ(spec().value(render_member("objects"), "maxItems"),
              std::to_string(limits.max_objects));
    EXPECT_EQ(spec().value(render_member("lights"), "maxItems"), std::to_string(limits.max_lights));
    EXPECT_EQ(flow_list(*spec().value(render_member("shadows/resolution"), "enum")).back(),
              std::to_string(limits.max_shadow_resolution));
    const auto bound = [](const Spec::Block& block, const char* key) {
        return std::stod(spec().value(block, key).value_or("nan"));
    };
    for (const Spec::Block& coordinate :
         {spec().child(schema("Position"), "items"),
          spec().child(render_member("objects/*/transform"), "items")}) {
        EXPECT_EQ(bound(coordinate, "minimum"), -api::kMaxCoordinate);
        EXPECT_EQ(bound(coordinate, "maximum"), api::kMaxCoordinate);
    }
}

TEST(OpenApi, RenderQueryHasExactlyTheParsersParameters) {
    const std::vector<std::string>& parsed = api::render_query_parameters();
    EXPECT_EQ(spec().query_parameters(render_get_parameters()),
              std::set<std::string>(parsed.begin(), parsed.end()));
    EXPECT_EQ(spec().value(parameter_schema(render_get_parameters(), "mesh"), "maxItems"),
              std::to_string(api::RenderLimits{}.max_objects));
    EXPECT_EQ(spec().value(parameter_schema(render_get_parameters(), "lights"), "maxItems"),
              std::to_string(api::RenderLimits{}.max_lights));
    // Bounds, enums and defaults of each parameter are the parser's.
    int probed = 0;
    for (const std::string& name : parsed) {
        const Spec::Block schema_block = parameter_schema(render_get_parameters(), name);
        ASSERT_TRUE(schema_block.found) << name;
        const Probes values = probes(schema_block);
        for (const bool accept : {true, false}) {
            for (const Json& value : accept ? values.accepted : values.rejected) {
                std::multimap<std::string, std::string> query = {{"environment", "default"},
                                                                 {name, query_text(value)}};
                if (name == "fov_y") {
                    query.insert({"distance", "2"});
                }
                EXPECT_EQ(rejected_parameter(query), accept ? "" : name)
                    << name << "=" << query_text(value);
                ++probed;
            }
        }
    }
    EXPECT_GT(probed, 40);
    const Json defaults = api::normalised_render_json(
        api::parse_render_query({{"environment", "default"}, {"distance", "3"}}));
    // Each scalar parameter with a default (the table's rows) declares the canonical document's
    // value at the row's member, a boolean as on or off; an optional one declares none.
    int defaulted = 0;
    for (const api::RenderParameter& row : api::render_parameters()) {
        const bool scalar =
            row.kind == api::ParameterKind::Number || row.kind == api::ParameterKind::Integer ||
            row.kind == api::ParameterKind::Name || row.kind == api::ParameterKind::Boolean ||
            row.kind == api::ParameterKind::Switch;
        if (row.query.empty() || !scalar) {
            continue;
        }
        const std::string name(row.query);
        const std::optional<Json> declared =
            default_of(parameter_schema(render_get_parameters(), name));
        if (row.presence != api::Presence::Defaulted) {
            EXPECT_FALSE(declared.has_value()) << name;
            continue;
        }
        ASSERT_TRUE(declared.has_value()) << name;
        const Json canonical = defaults.at(Json::json_pointer("/" + std::string(row.json)));
        EXPECT_EQ(canonical.is_boolean() ? Json(canonical.get<bool>() ? "on" : "off") : canonical,
                  *declared)
            << name;
        ++defaulted;
    }
    EXPECT_EQ(defaulted, 20);
    EXPECT_FALSE(default_of(parameter_schema(render_get_parameters(), "distance")).has_value());
    EXPECT_EQ(default_of(parameter_schema(render_get_parameters(), "ground")), Json("on"));
    EXPECT_EQ(default_of(parameter_schema(render_get_parameters(), "occlusion")), Json("on"));
    EXPECT_TRUE(defaults.at("occlusion").get<bool>());
    EXPECT_EQ(default_of(parameter_schema(render_get_parameters(), "shadows")), Json("on"));
}

TEST(OpenApi, EnvironmentUploadTakesExactlyTheRigOptions) {
    const std::vector<std::string> names = api::rig_option_names();
    // And the file's name, for its errors (http_exchange.hpp, upload_file_name).
    std::set<std::string> expected(names.begin(), names.end());
    expected.insert("filename");
    EXPECT_EQ(spec().query_parameters(environment_upload_parameters()), expected);
    const Json defaults = api::rig_options_to_json(RigOptions{});
    const std::vector<std::string> keys =
        spec().keys(spec().child(schema("RigOptions"), "properties"));
    EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()),
              std::set<std::string>(names.begin(), names.end()));
    check_document(defaults, schema("RigOptions"), "RigOptions");
    for (const std::string& name : names) {
        EXPECT_TRUE(api::is_rig_option(name)) << name;
        const Spec::Block parameter = parameter_schema(environment_upload_parameters(), name);
        const std::optional<Json> declared = default_of(parameter);
        ASSERT_TRUE(declared.has_value()) << name;
        EXPECT_EQ(defaults.at(name), *declared) << name;
        // halo_percentile may not exceed light_percentile: probe each with the other out of
        // its way.
        const Probes values = probes(parameter);
        for (const bool accept : {true, false}) {
            for (const Json& value : accept ? values.accepted : values.rejected) {
                std::map<std::string, std::string> parameters = {{name, query_text(value)}};
                if (name == "light_percentile") {
                    parameters["halo_percentile"] = "0.5";
                }
                if (name == "halo_percentile") {
                    parameters["light_percentile"] = "0.99999";
                }
                std::string rejected;
                try {
                    api::parse_rig_options(parameters);
                } catch (const api::InvalidParameter& error) {
                    rejected = error.parameter();
                }
                EXPECT_EQ(rejected, accept ? "" : name) << name << "=" << query_text(value);
            }
        }
    }
}

TEST(OpenApi, SchemasDescribeTheDocumentsTheApiWrites) {
    RigOptions options;
    options.light_count = 2;
    options.sh_order = 4;
    options.window = WindowChoice::Hanning;
    Json rig = api::rig_to_json(build_rig(make_default_environment(128, 64), {}, options),
                                std::string(64, 'e'));
    rig["cached"] = false;
    check_document(rig, schema("Rig"), "Rig");
    EXPECT_EQ(rig.at("sh").at("window").at("kind"), "hanning");

    Json mesh = api::mesh_to_json(make_default_product(), "default", MeshFormat::Glb);
    mesh["cached"] = true;
    check_document(mesh, schema("Mesh"), "Mesh");

    for (const char* body :
         {R"({"environment": "default"})",
          R"({"environment": "default", "objects": [{"mesh": "default", "base_color": [1, 0, 0],
              "transform": [2,0,0,0, 0,2,0,0, 0,0,2,0, 1,0,0,1]}], "lights": [false, true],
              "camera": {"orbit": {"yaw": -30, "target": [0, 1, 0]}}, "background": "#FFFFFF"})",
          R"({"environment": "default", "camera": {"eye": [0, 1, 3], "target": [0, 1, 0]},
              "format": "exr", "shadows": {"enabled": false}})",
          R"({"environment": "default", "occlusion": false, "bounce": "none"})"}) {
        check_document(api::normalised_render_json(api::parse_render_json(body)),
                       schema("RenderRequest"), "RenderRequest");
    }
    // The checks bite: a member the schema does not know, or a value outside it, fails.
    EXPECT_NONFATAL_FAILURE(
        check_document({{"environment", "default"}, {"widht", 5}}, schema("RenderRequest"), "x"),
        "widht");
    EXPECT_NONFATAL_FAILURE(check_document({{"environment", "default"}, {"quality", 101}},
                                           schema("RenderRequest"), "x"),
                            "x/quality");
}

// The server asks for the API key, when it has one, on the uploads and deletions only, and on
// the jobs' listing (tests/integration/errors_test.cpp, ApiKey; jobs_test.cpp, JobsListing):
// the spec declares it there, as optional (`{}`
// or the key: without --api-key they are open), says `security: []` everywhere else, and lists
// 401 exactly where it declares the key, so that a generated client neither sends the key
// elsewhere nor expects a 401 that cannot come.
TEST(OpenApi, DeclaresTheApiKeyOnExactlyTheUploadsDeletionsAndJobs) {
    const Json& document = spec().json();
    EXPECT_FALSE(document.contains("security")) << "a top-level security would cover every route";
    const Json optional_key = Json::parse(R"([{}, {"apiKey": []}])");
    std::set<std::string> keyed;
    int operations = 0;
    for (const auto& [path, item] : document.at("paths").items()) {
        for (const auto& [method, operation] : item.items()) {
            ++operations;
            const std::string name = method + " " + path;
            ASSERT_TRUE(operation.contains("security")) << name;
            const Json& security = operation.at("security");
            EXPECT_TRUE(security == Json::array() || security == optional_key)
                << name << ": " << security.dump();
            const bool declares_key = security == optional_key;
            if (declares_key) {
                keyed.insert(name);
            }
            EXPECT_EQ(operation.at("responses").contains("401"), declares_key) << name;
        }
    }
    EXPECT_GT(operations, 10);
    EXPECT_EQ(keyed,
              (std::set<std::string>{"post /v1/environments", "post /v1/meshes", "post /v1/jobs",
                                     "get /v1/jobs", "delete /v1/environments/{id}",
                                     "delete /v1/meshes/{id}", "delete /v1/jobs/{id}"}));
}
