#pragma once
// A reader for api/openapi.yaml, shared by the unit test that holds the parsers to the spec and
// the integration tests that hold the live server to it.
//
// The file is parsed with yaml-cpp; a Block is one of its nodes. Spec::to_json converts any
// block (or the whole document) into JSON, so that a JSON-Schema validator (json_schema.hpp)
// can work on it.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

namespace oer::testing {

// The source tree's api/openapi.yaml: tests read what is published, not a copy.
const std::filesystem::path& openapi_path();

std::string trim(const std::string& text);
std::string unquote(const std::string& text);
// "[a, 'b', 3]" -> {"a", "b", "3"}; nullopt when text is not a one-line flow list.
std::optional<std::vector<std::string>> flow_list(const std::string& text);
// A YAML scalar or flow list as JSON ("[0, 1, 0]", "512", "true"), or as a string ("jpeg").
nlohmann::json scalar_json(const std::string& text);

class Spec {
  public:
    // One node of the document. An empty block (found == false) has no keys. The node is held
    // by pointer because assigning a YAML::Node rebinds the node it refers to inside the
    // document (yaml-cpp's reference semantics): Blocks must stay assignable views.
    struct Block {
        std::shared_ptr<const YAML::Node> node;
        bool found = false;
    };

    explicit Spec(const std::filesystem::path& path);

    // The file's lines, as written (for checks on its text, such as every $ref).
    const std::vector<std::string>& lines() const { return lines_; }
    Block document() const { return {std::make_shared<const YAML::Node>(root_), true}; }

    Block child(const Block& block, const std::string& key) const;
    Block at(Block block, const std::vector<std::string>& keys) const;
    // The inline value of `key` in a mapping, as written: a scalar ("type: integer" ->
    // "integer", quoted ones with their quotes) or a flow list ("[a, b]"); nullopt for a
    // nested block or a missing key.
    std::optional<std::string> value(const Block& block, const std::string& key) const;
    std::vector<std::string> keys(const Block& block) const;
    // The items of a list.
    std::vector<Block> items(const Block& block) const;
    // Where a "#/components/schemas/Name" reference points.
    Block reference(const std::string& pointer) const;
    // Follows $ref until a block without one.
    Block resolved(Block block) const;
    // The names of the query parameters declared in a block of parameters.
    std::set<std::string> query_parameters(const Block& block) const;

    // The block as JSON: mappings become objects, lists arrays, plain scalars scalar_json,
    // quoted and block scalars strings.
    nlohmann::json to_json(const Block& block) const;
    // The whole document as JSON, converted once.
    const nlohmann::json& json() const;

  private:
    std::vector<std::string> lines_;
    YAML::Node root_;
    mutable std::optional<nlohmann::json> json_;
};

// The published spec, loaded once.
const Spec& openapi_spec();

}  // namespace oer::testing
