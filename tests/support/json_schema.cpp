#include "json_schema.hpp"

#include <cmath>
#include <cstdint>
#include <regex>
#include <set>
#include <stdexcept>

#include "oer/core/checked_json.hpp"
#include "openapi_spec.hpp"

namespace oer::testing {

using Json = nlohmann::json;

namespace {

const std::set<std::string> kAnnotations = {
    "description", "default", "format",  "contentMediaType", "contentEncoding", "title",
    "examples",    "example", "summary", "deprecated",       "readOnly",        "writeOnly"};

// A schema whose keyword has an argument of the wrong type is a broken spec, not a violation
// by the value: it throws, naming the keyword.
struct SchemaWording {
    [[noreturn]] void fail(const std::string& keyword, const std::string& message) const {
        throw std::runtime_error("schema keyword " + keyword + ": " + message);
    }
    std::string wrong_type(const std::string& expected, const Json& value) const {
        return "expected " + expected + ", got " + value.dump();
    }
    std::string missing() const { return "missing"; }
};

const checked_json::Reader<SchemaWording> read(SchemaWording{}, checked_json::PathStyle::Slash);

const Json& resolve_pointer(const Json& root, const std::string& reference) {
    if (reference.rfind("#", 0) != 0) {
        throw std::runtime_error("only local references are supported: " + reference);
    }
    return root.at(Json::json_pointer(reference.substr(1)));
}

bool is_integer(const Json& value) {
    return value.is_number_integer() ||
           (value.is_number_float() && std::isfinite(value.get<double>()) &&
            value.get<double>() == std::floor(value.get<double>()));
}

bool has_type(const Json& value, const std::string& type) {
    if (type == "object")
        return value.is_object();
    if (type == "array")
        return value.is_array();
    if (type == "string")
        return value.is_string();
    if (type == "boolean")
        return value.is_boolean();
    if (type == "null")
        return value.is_null();
    if (type == "integer")
        return is_integer(value);
    if (type == "number")
        return value.is_number();
    throw std::runtime_error("unknown type in schema: " + type);
}

// JSON equality where 1 and 1.0 are the same number.
bool same(const Json& a, const Json& b) {
    if (a.is_number() && b.is_number()) {
        return a.get<double>() == b.get<double>();
    }
    return a == b;
}

void validate(const Json& value, const Json& schema, const Json& root, const std::string& where,
              std::vector<std::string>& errors, int depth) {
    if (depth > 64) {
        errors.push_back(where + ": schema nesting too deep (a reference cycle?)");
        return;
    }
    if (schema.is_boolean()) {
        if (!schema.get<bool>()) {
            errors.push_back(where + ": not allowed (schema false)");
        }
        return;
    }
    if (!schema.is_object()) {
        errors.push_back(where + ": schema is not an object: " + schema.dump());
        return;
    }
    const auto fail = [&](const std::string& what) {
        errors.push_back((where.empty() ? "/" : where) + ": " + what);
    };
    for (const auto& [keyword, argument] : schema.items()) {
        if (kAnnotations.count(keyword)) {
            continue;
        }
        if (keyword == "$ref") {
            validate(value, resolve_pointer(root, read.string(argument, keyword)), root, where,
                     errors, depth + 1);
        } else if (keyword == "type") {
            bool matches = false;
            if (argument.is_array()) {
                for (const Json& name : argument) {
                    matches = matches || has_type(value, read.string(name, keyword));
                }
            } else {
                matches = has_type(value, read.string(argument, keyword));
            }
            if (!matches) {
                fail(value.dump() + " is not of type " + argument.dump());
                return;  // the other keywords would only repeat the mismatch
            }
        } else if (keyword == "enum") {
            bool listed = false;
            for (const Json& option : read.array(argument, keyword)) {
                listed = listed || same(option, value);
            }
            if (!listed) {
                fail(value.dump() + " is not one of " + argument.dump());
            }
        } else if (keyword == "const") {
            if (!same(argument, value)) {
                fail(value.dump() + " is not " + argument.dump());
            }
        } else if (keyword == "minimum" || keyword == "maximum" || keyword == "exclusiveMinimum" ||
                   keyword == "exclusiveMaximum") {
            if (!value.is_number()) {
                continue;
            }
            const double v = value.get<double>(), bound = read.number(argument, keyword);
            const bool ok = keyword == "minimum"            ? v >= bound
                            : keyword == "maximum"          ? v <= bound
                            : keyword == "exclusiveMinimum" ? v > bound
                                                            : v < bound;
            if (!ok) {
                fail(value.dump() + " violates " + keyword + " " + argument.dump());
            }
        } else if (keyword == "minLength" || keyword == "maxLength") {
            if (!value.is_string()) {
                continue;
            }
            const std::size_t length = value.get<std::string>().size();
            const std::uint64_t bound = read.index(argument, keyword);
            if (keyword == "minLength" ? length < bound : length > bound) {
                fail("length " + std::to_string(length) + " violates " + keyword);
            }
        } else if (keyword == "pattern") {
            if (value.is_string() &&
                !std::regex_search(value.get<std::string>(),
                                   std::regex(read.string(argument, keyword)))) {
                fail(value.dump() + " does not match " + argument.dump());
            }
        } else if (keyword == "minItems" || keyword == "maxItems") {
            if (!value.is_array()) {
                continue;
            }
            const std::uint64_t bound = read.index(argument, keyword);
            if (keyword == "minItems" ? value.size() < bound : value.size() > bound) {
                fail(std::to_string(value.size()) + " items violate " + keyword + " " +
                     argument.dump());
            }
        } else if (keyword == "items") {
            if (!value.is_array()) {
                continue;
            }
            for (std::size_t i = 0; i < value.size(); ++i) {
                validate(value[i], argument, root, where + "/" + std::to_string(i), errors,
                         depth + 1);
            }
        } else if (keyword == "required") {
            if (!value.is_object()) {
                continue;
            }
            for (const Json& name : read.array(argument, keyword)) {
                if (!value.contains(read.string(name, keyword))) {
                    fail("lacks required member " + name.dump());
                }
            }
        } else if (keyword == "properties") {
            if (!value.is_object()) {
                continue;
            }
            for (const auto& [name, member] : value.items()) {
                if (argument.contains(name)) {
                    validate(member, argument.at(name), root, where + "/" + name, errors,
                             depth + 1);
                }
            }
        } else if (keyword == "additionalProperties") {
            if (!value.is_object()) {
                continue;
            }
            const Json properties = schema.value("properties", Json::object());
            for (const auto& [name, member] : value.items()) {
                if (properties.contains(name)) {
                    continue;
                }
                if (argument.is_boolean() && !argument.get<bool>()) {
                    fail("has member \"" + name + "\", which the schema does not allow");
                } else {
                    validate(member, argument, root, where + "/" + name, errors, depth + 1);
                }
            }
        } else if (keyword == "allOf") {
            for (const Json& part : read.array(argument, keyword)) {
                validate(value, part, root, where, errors, depth + 1);
            }
        } else if (keyword == "anyOf" || keyword == "oneOf") {
            int matched = 0;
            std::vector<std::string> reasons;
            for (const Json& part : read.array(argument, keyword)) {
                std::vector<std::string> part_errors;
                validate(value, part, root, where, part_errors, depth + 1);
                matched += part_errors.empty();
                for (const std::string& reason : part_errors) {
                    reasons.push_back(reason);
                }
            }
            if (matched == 0) {
                std::string joined;
                for (const std::string& reason : reasons) {
                    joined += " [" + reason + "]";
                }
                fail(value.dump() + " matches none of " + keyword + ":" + joined);
            } else if (keyword == "oneOf" && matched > 1) {
                fail(value.dump() + " matches " + std::to_string(matched) +
                     " alternatives of oneOf, not exactly one");
            }
        } else if (keyword == "not") {
            std::vector<std::string> part_errors;
            validate(value, argument, root, where, part_errors, depth + 1);
            if (part_errors.empty()) {
                fail(value.dump() + " matches a schema under not: " + argument.dump());
            }
        } else {
            fail("the validator does not know the keyword \"" + keyword + "\"");
        }
    }
}

}  // namespace

std::vector<std::string> schema_errors(const Json& value, const Json& schema, const Json& root) {
    std::vector<std::string> errors;
    validate(value, schema, root, "", errors, 0);
    return errors;
}

const Json& openapi_node(const std::string& pointer) {
    const Json& root = openapi_spec().json();
    const Json* node = &resolve_pointer(root, pointer);
    for (int depth = 0; depth < 64 && node->is_object() && node->contains("$ref"); ++depth) {
        node = &resolve_pointer(root, read.string(node->at("$ref"), "$ref"));
    }
    return *node;
}

std::vector<std::string> openapi_schema_errors(const Json& value, const std::string& pointer) {
    const Json& root = openapi_spec().json();
    return schema_errors(value, resolve_pointer(root, pointer), root);
}

std::string pointer_segment(const std::string& key) {
    std::string escaped;
    for (const char c : key) {
        escaped += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
    }
    return escaped;
}

}  // namespace oer::testing
