#pragma once
// The value readers of a render request, shared by the table of its parameters
// (render_parameters.cpp) and the readers of its structured members (render_members.cpp): each
// checks a value in either form, JSON or query text, and throws InvalidParameter naming the
// member's path or the query parameter it is given.
#include <span>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "oer/api/render_parameters.hpp"
#include "oer/api/render_request.hpp"
#include "oer/core/checked_json.hpp"

namespace oer::api::request_values {

using Json = nlohmann::json;
using Names = std::span<const std::string_view>;

// The ranges both forms check, and api/openapi.yaml states.
struct Range {
    double low;
    double high;
};
inline constexpr Range kCoordinate{-kMaxCoordinate, kMaxCoordinate};
inline constexpr Range kFovY{1.0, 179.0};
inline constexpr Range kAngle{-360.0, 360.0};  // orbit yaw, environment_yaw
inline constexpr Range kPitch{-90.0, 90.0};
inline constexpr Range kDistance{1e-4, 1e6};
inline constexpr Range kExposure{-64.0, 64.0};  // the renderer's limit
inline constexpr Range kColor{0.0, 1.0};
inline constexpr Range kUnitInterval{0.0, 1.0};  // shadow softness and intensity
inline constexpr int kMaxQuality = 100;
inline constexpr int kMinShadowResolution = 64;
// Frame sides beyond this are nonsense rather than over a configured limit.
inline constexpr long long kLargestSide = 1 << 20;

// The request's wording: an InvalidParameter naming the member's path ("objects/0/mesh"),
// "expected <kind>, got <JSON type>".
struct RequestWording {
    [[noreturn]] void fail(const std::string& path, const std::string& message) const;
    std::string wrong_type(const std::string& expected, const Json& value) const;
    std::string missing() const { return "required"; }
};

const checked_json::Reader<RequestWording>& reader();

std::string child(const std::string& path, std::string_view name);
std::string child(const std::string& path, std::size_t index);
const Json* find(const Json& object, std::string_view name);
// A query parameter's value (parameters are unique but for `mesh`), or nullptr.
const std::string* query_value(const RenderQuery& query, std::string_view name);

// Checks shared by both forms, each naming the member or parameter it is given.
std::string checked_id(const std::string& name, const std::string& text);
int checked_resolution(const std::string& name, long long resolution);
int checked_samples(const std::string& name, long long samples);
// A frame side over the configured limit is a size limit (HTTP 413), not a malformed value.
int within_frame_limit(const std::string& name, long long value, int limit);

// The JSON form: each reader checks the type first, then the value, naming the member's path.
double json_number(const Json& value, const std::string& path, Range range);
long long json_integer(const Json& value, const std::string& path, long long low, long long high);
bool json_bool(const Json& value, const std::string& path);
const std::string& json_string(const Json& value, const std::string& path);
glm::dvec3 json_vector3(const Json& value, const std::string& path, Range range);
void require_array(const Json& value, const std::string& path, std::size_t max_size);
// An object whose members are all among `names`; path "" is the body itself.
void require_object(const Json& value, const std::string& path, Names names);

// Canonical numbers: -0 and 0 are one value.
double canonical(double value);
Json vector_json(const glm::dvec3& v);

}  // namespace oer::api::request_values
