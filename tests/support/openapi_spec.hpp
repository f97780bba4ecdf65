#pragma once
// A reader for api/openapi.yaml, shared by the unit test that holds the parsers to the spec and
// the integration tests that hold the live server to it.
//
// No YAML library is installed, and the file keeps to a plain subset (block mappings, two-space
// indentation, one-line flow lists, `|` block scalars; see its head) that a few lines here can
// walk: a key's body is the lines indented under it. Spec::to_json converts any block (or the
// whole document) into JSON, so that a JSON-Schema validator (json_schema.hpp) can work on it.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

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
    // The body of one key: lines [begin, end). An empty block (found == false) has no keys.
    struct Block {
        std::size_t begin = 0;
        std::size_t end = 0;
        bool found = false;
    };

    explicit Spec(const std::filesystem::path& path);

    const std::vector<std::string>& lines() const { return lines_; }
    Block document() const { return {0, lines_.size(), !lines_.empty()}; }

    Block child(const Block& block, const std::string& key) const;
    Block at(Block block, const std::vector<std::string>& keys) const;
    // The inline value of `key` on the block's top level ("type: integer" -> "integer").
    std::optional<std::string> value(const Block& block, const std::string& key) const;
    std::vector<std::string> keys(const Block& block) const;
    // Where a "#/components/schemas/Name" reference points.
    Block reference(const std::string& pointer) const;
    // Follows $ref until a block without one.
    Block resolved(Block block) const;
    // The names of the query parameters declared in a block of parameters.
    std::set<std::string> query_parameters(const Block& block) const;

    // The block as JSON: mappings become objects, "- " lists arrays, scalars scalar_json,
    // `|` block scalars strings. Throws std::runtime_error on a line outside the subset.
    nlohmann::json to_json(const Block& block) const;
    // The whole document as JSON, converted once.
    const nlohmann::json& json() const;

  private:
    static bool skip(const std::string& line);
    static std::size_t indentation(const std::string& line);
    static std::string key_of(const std::string& line);
    std::size_t top_indentation(const Block& block) const;
    // Lines [begin, end) at indentation `indent` (and deeper) as JSON.
    nlohmann::json node(std::size_t begin, std::size_t end) const;

    std::vector<std::string> lines_;
    mutable std::optional<nlohmann::json> json_;
};

// The published spec, loaded once.
const Spec& openapi_spec();

}  // namespace oer::testing
