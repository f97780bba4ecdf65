#include "request_values.hpp"

#include <algorithm>
#include <cmath>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"

namespace oer::api::request_values {

void RequestWording::fail(const std::string& path, const std::string& message) const {
    throw InvalidParameter(path, message);
}

std::string RequestWording::wrong_type(const std::string& expected, const Json& value) const {
    return "expected " + expected + ", got " + (value.is_null() ? "null" : value.type_name());
}

const checked_json::Reader<RequestWording>& reader() {
    static const checked_json::Reader<RequestWording> read(RequestWording{},
                                                           checked_json::PathStyle::Slash);
    return read;
}

std::string child(const std::string& path, std::string_view name) {
    return reader().child(path, name);
}

std::string child(const std::string& path, std::size_t index) {
    return reader().child(path, index);
}

const Json* find(const Json& object, std::string_view name) {
    return checked_json::find(object, name);
}

const std::string* query_value(const RenderQuery& query, std::string_view name) {
    const auto found = query.find(std::string(name));
    return found == query.end() ? nullptr : &found->second;
}

std::string checked_id(const std::string& name, const std::string& text) {
    if (text != kDefaultPresetId && !is_content_id(text)) {
        throw InvalidParameter(name, "expected a content id (64 lowercase hex digits) or '" +
                                         std::string(kDefaultPresetId) + "', got '" +
                                         excerpt(text) + "'");
    }
    return text;
}

int checked_resolution(const std::string& name, long long resolution) {
    if ((resolution & (resolution - 1)) != 0) {
        throw InvalidParameter(name, "must be a power of two, got " + std::to_string(resolution));
    }
    return int(resolution);
}

int checked_samples(const std::string& name, long long samples) {
    if (std::find(kSampleCounts.begin(), kSampleCounts.end(), samples) == kSampleCounts.end()) {
        throw InvalidParameter(name, "must be 1, 2, 4 or 8, got " + std::to_string(samples));
    }
    return int(samples);
}

int within_frame_limit(const std::string& name, long long value, int limit) {
    if (value > limit) {
        throw InvalidParameter(
            name, std::to_string(value) + " is over the limit of " + std::to_string(limit),
            ErrorKind::LimitExceeded);
    }
    return int(value);
}

double json_number(const Json& value, const std::string& path, Range range) {
    const double number = reader().number(value, path);
    if (!(number >= range.low && number <= range.high)) {
        reader().fail(path, "must be in [" + number_text(range.low) + ", " +
                                number_text(range.high) + "], got " + excerpt(value.dump()));
    }
    return number;
}

long long json_integer(const Json& value, const std::string& path, long long low, long long high) {
    const double number =
        reader().expect(value, value.is_number(), path, "an integer").get<double>();
    if (number != std::floor(number)) {
        reader().fail(path, "expected an integer, got " + excerpt(value.dump()));
    }
    if (!(number >= double(low) && number <= double(high))) {
        reader().fail(path, "must be in " + std::to_string(low) + ".." + std::to_string(high) +
                                ", got " + excerpt(value.dump()));
    }
    return static_cast<long long>(number);
}

bool json_bool(const Json& value, const std::string& path) {
    return reader().boolean(value, path, "true or false");
}

const std::string& json_string(const Json& value, const std::string& path) {
    return reader().string(value, path);
}

glm::dvec3 json_vector3(const Json& value, const std::string& path, Range range) {
    if (!value.is_array() || value.size() != 3) {
        reader().fail(path, "expected an array of 3 numbers");
    }
    glm::dvec3 v{0.0};
    for (std::size_t i = 0; i < 3; ++i) {
        v[int(i)] = json_number(value[i], child(path, i), range);
    }
    return v;
}

void require_array(const Json& value, const std::string& path, std::size_t max_size) {
    reader().array(value, path);
    if (value.size() > max_size) {
        reader().fail(path, "at most " + std::to_string(max_size) + " entries, got " +
                                std::to_string(value.size()));
    }
}

void require_object(const Json& value, const std::string& path, Names names) {
    reader().object(value, path.empty() ? "body" : path);
    if (const std::string* unknown = reader().unknown_member(value, names)) {
        std::string known;
        for (const std::string_view name : names) {
            known += (known.empty() ? "" : ", ") + std::string(name);
        }
        reader().fail(child(path, excerpt(*unknown)), "unknown member; expected one of " + known);
    }
}

double canonical(double value) {
    return value + 0.0;
}

Json vector_json(const glm::dvec3& v) {
    return Json::array({canonical(v.x), canonical(v.y), canonical(v.z)});
}

}  // namespace oer::api::request_values
