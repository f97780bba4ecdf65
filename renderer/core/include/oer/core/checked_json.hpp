#pragma once
// The one parser of untrusted JSON (parse_bounded: element count and nesting bounded while
// parsing) and the one reader of checked JSON: members of the expected type, or a failure that
// names the member's path. The render request and stored rigs (api/), glTF (renderer/mesh) and the
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
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace oer::checked_json {

using Json = nlohmann::json;

// What a document may hold, checked as it is parsed: a document over a bound is refused as soon
// as the parser reaches the value that passes it, before any value is built, so that its
// memory is at most that of max_elements values, whatever the size of its text (a 20 MB array
// of 10^7 zeros would take 160 MB as nlohmann values, more as the objects a reader makes of
// them).
struct JsonBounds {
    std::size_t max_elements = 0;  // values of every kind, objects and arrays included
    int max_depth = 0;             // objects and arrays inside each other (a top-level one: 1)
};

// A document that is not JSON (Syntax), or passes a bound (TooDeep, TooMany), so that each
// caller can answer in its own words and kinds. The message says which and where, without
// nlohmann's "[json.exception.parse_error.101] " tag: "parse error at line 1, column 7: ...",
// "the JSON holds more than 1000 values", "the JSON is nested more than 16 levels deep".
class JsonParseError : public std::runtime_error {
  public:
    enum class Cause { Syntax, TooDeep, TooMany };
    JsonParseError(const std::string& message, Cause cause)
        : std::runtime_error(message), cause_(cause) {}
    Cause cause() const { return cause_; }

  private:
    Cause cause_;
};

namespace detail {

// nlohmann's SAX interface, counting values and nesting without building anything; it stops
// the parse at the value that passes a bound.
class BoundsCounter : public nlohmann::json_sax<Json> {
  public:
    explicit BoundsCounter(const JsonBounds& bounds) : bounds_(bounds) {}

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override { return open(); }
    bool key(string_t&) override { return true; }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t, const std::string&,
                     const nlohmann::detail::exception& error) override {
        const std::string message = error.what();
        const std::size_t tag_end = message.find("] ");
        failure_ =
            JsonParseError(tag_end == std::string::npos ? message : message.substr(tag_end + 2),
                           JsonParseError::Cause::Syntax);
        return false;
    }

    const JsonParseError& failure() const { return failure_; }

  private:
    bool value() {
        if (++values_ > bounds_.max_elements) {
            failure_ = JsonParseError(
                "the JSON holds more than " + std::to_string(bounds_.max_elements) + " values",
                JsonParseError::Cause::TooMany);
            return false;
        }
        return true;
    }
    bool open() {
        if (++depth_ > bounds_.max_depth) {
            failure_ = JsonParseError("the JSON is nested more than " +
                                          std::to_string(bounds_.max_depth) + " levels deep",
                                      JsonParseError::Cause::TooDeep);
            return false;
        }
        return value();
    }
    bool close() {
        --depth_;
        return true;
    }

    JsonBounds bounds_;
    std::size_t values_ = 0;
    int depth_ = 0;
    JsonParseError failure_{"", JsonParseError::Cause::Syntax};
};

}  // namespace detail

// The document, parsed only once a first pass that builds nothing has found it within bounds:
// a document over them costs the time to read up to the value that passes one, and no memory.
// (nlohmann's parser callback would count while building, but it scans the enclosing array
// each time an object in it ends: quadratic, 21 s for an array of 131000 small objects.)
inline Json parse_bounded(std::string_view text, const JsonBounds& bounds) {
    detail::BoundsCounter counter(bounds);
    if (!Json::sax_parse(text, &counter)) {
        throw counter.failure();
    }
    return Json::parse(text);
}

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
        // Through the object's own iterators, whose key() is the stored name (items() gives an
        // array's keys as temporaries, which GCC warns of returning).
        for (auto member = value.begin(); member != value.end(); ++member) {
            bool known = false;
            for (const std::string_view name : names) {
                known = known || member.key() == name;
            }
            if (!known) {
                return &member.key();
            }
        }
        return nullptr;
    }

  private:
    Wording wording_;
    PathStyle style_;
};

}  // namespace oer::checked_json
