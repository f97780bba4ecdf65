#pragma once
// The one reader of checked JSON: members of the expected type, or a failure that names the
// member's path. The render request and stored rigs (api/), glTF (renderer/mesh) and the
// tests' schema support all read through it. It is header-only in core, the library every
// other one may depend on (dependencies point server -> api -> renderer, so the mesh library
// cannot use api/), and oer_core's interface brings nlohmann_json for it.
//
// A caller words its failures through a Wording, so that each keeps its own messages and error
// kinds (tests and clients read them):
//
//   struct Wording {
//       // Throws; path is where the value is, message what is wrong with it.
//       [[noreturn]] void fail(const std::string& path, const std::string& message) const;
//       // The message for a value that is not of the expected kind ("an object", "a number").
//       std::string wrong_type(const std::string& expected, const Json& value) const;
//       // The message for a required member that is absent.
//       std::string missing() const;
//   };
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace oer::checked_json {

using Json = nlohmann::json;

// What a value is, in words for messages.
inline const char* kind_of(const Json& value) {
    switch (value.type()) {
        case Json::value_t::null:
            return "null";
        case Json::value_t::object:
            return "an object";
        case Json::value_t::array:
            return "an array";
        case Json::value_t::string:
            return "a string";
        case Json::value_t::boolean:
            return "a boolean";
        case Json::value_t::number_integer:
        case Json::value_t::number_unsigned:
        case Json::value_t::number_float:
            return "a number";
        default:
            return "another kind of value";
    }
}

// A non-negative integer, also when written as a float (3.0) below 2^53, where a double still
// holds every integer exactly.
inline bool is_index(const Json& value) {
    if (value.is_number_unsigned()) {
        return true;
    }
    if (value.is_number_integer()) {
        return value.get<std::int64_t>() >= 0;
    }
    if (value.is_number_float()) {
        const double v = value.get<double>();
        return v >= 0.0 && v == std::floor(v) && v < 9.007199254740992e15;
    }
    return false;
}

// The member, or nullptr (also when object is not an object).
inline const Json* find(const Json& object, std::string_view name) {
    if (!object.is_object()) {
        return nullptr;
    }
    const auto found = object.find(name);
    return found == object.end() ? nullptr : &*found;
}

// How paths are spelled: "objects/0/mesh" (a JSON Pointer without its leading '/': the API's
// `parameter`), or "meshes[0].primitives" (the glTF specification's own wording).
enum class PathStyle { Slash, Dotted };

inline std::string child(PathStyle style, const std::string& path, std::string_view name) {
    if (path.empty()) {
        return std::string(name);
    }
    return path + (style == PathStyle::Slash ? "/" : ".") + std::string(name);
}

inline std::string child(PathStyle style, const std::string& path, std::size_t index) {
    if (style == PathStyle::Slash) {
        return child(style, path, std::to_string(index));
    }
    return path + "[" + std::to_string(index) + "]";
}

template <typename Wording>
class Reader {
  public:
    Reader(Wording wording, PathStyle style) : wording_(std::move(wording)), style_(style) {}

    [[noreturn]] void fail(const std::string& path, const std::string& message) const {
        wording_.fail(path, message);
    }
    [[noreturn]] void wrong_type(const std::string& path, const std::string& expected,
                                 const Json& value) const {
        fail(path, wording_.wrong_type(expected, value));
    }

    std::string child(const std::string& path, std::string_view name) const {
        return checked_json::child(style_, path, name);
    }
    std::string child(const std::string& path, std::size_t index) const {
        return checked_json::child(style_, path, index);
    }

    // The value when `ok`, else a wrong_type failure expecting `expected`.
    const Json& expect(const Json& value, bool ok, const std::string& path,
                       const std::string& expected) const {
        if (!ok) {
            wrong_type(path, expected, value);
        }
        return value;
    }
    const Json& object(const Json& value, const std::string& path) const {
        return expect(value, value.is_object(), path, "an object");
    }
    const Json& array(const Json& value, const std::string& path) const {
        return expect(value, value.is_array(), path, "an array");
    }
    double number(const Json& value, const std::string& path) const {
        return expect(value, value.is_number(), path, "a number").template get<double>();
    }
    const std::string& string(const Json& value, const std::string& path) const {
        return expect(value, value.is_string(), path, "a string")
            .template get_ref<const std::string&>();
    }
    bool boolean(const Json& value, const std::string& path,
                 const std::string& expected = "a boolean") const {
        return expect(value, value.is_boolean(), path, expected).template get<bool>();
    }
    std::uint64_t index(const Json& value, const std::string& path,
                        const std::string& expected = "a non-negative integer") const {
        expect(value, is_index(value), path, expected);
        return value.is_number_float() ? std::uint64_t(value.get<double>())
                                       : value.get<std::uint64_t>();
    }

    // A required member of an object at `path` (failing as wrong_type when it is no object).
    const Json& member(const Json& value, const std::string& path, std::string_view name) const {
        object(value, path);
        const Json* found = checked_json::find(value, name);
        if (found == nullptr) {
            fail(child(path, name), wording_.missing());
        }
        return *found;
    }

    // The first member of the object whose name is not among `names`, or nullptr.
    static const std::string* unknown_member(const Json& value,
                                             std::span<const std::string_view> names) {
        for (const auto& [key, member] : value.items()) {
            bool known = false;
            for (const std::string_view name : names) {
                known = known || key == name;
            }
            if (!known) {
                return &key;
            }
        }
        return nullptr;
    }

  private:
    Wording wording_;
    PathStyle style_;
};

}  // namespace oer::checked_json
