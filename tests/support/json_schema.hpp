#pragma once
// A JSON-Schema validator for the subset api/openapi.yaml uses (OpenAPI 3.1 is JSON Schema
// 2020-12): type (a name or a list of names, so "null" makes a member nullable), enum, const,
// properties, required, additionalProperties (false or a schema), items, minItems, maxItems,
// minLength, maxLength, minimum, maximum, exclusiveMinimum, exclusiveMaximum, pattern
// (ECMAScript, unanchored as JSON Schema says), $ref (local "#/..." pointers), allOf, anyOf,
// oneOf (exactly one), not. Annotations (description, default, format, contentMediaType, ...)
// are ignored. An unknown assertion keyword is reported as an error, so that the validator
// never passes a document by not understanding its schema.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace oer::testing {

// Every violation as "<json pointer into value>: <what>"; empty when the value matches.
// References are resolved in `root` (the document the schema belongs to).
std::vector<std::string> schema_errors(const nlohmann::json& value, const nlohmann::json& schema,
                                       const nlohmann::json& root);

// The same against the schema at `pointer` ("#/components/schemas/Rig") of api/openapi.yaml.
std::vector<std::string> openapi_schema_errors(const nlohmann::json& value,
                                               const std::string& pointer);

// The node of the spec at a "#/a/b" pointer (with "~1" for "/"), $refs along the way followed.
const nlohmann::json& openapi_node(const std::string& pointer);

// "#/paths/~1v1~1render/get" style escaping of one pointer segment.
std::string pointer_segment(const std::string& key);

}  // namespace oer::testing
