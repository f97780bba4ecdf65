// The numbers of a glTF's JSON as the loader stores them (see gltf_values.hpp).
#include "gltf_values.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

#include "mesh_errors.hpp"

namespace oer::mesh_detail {

std::string number_text(double value) {
    std::array<char, 32> buffer{};
    const auto written = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), written.ptr);
}

float unit_factor(const std::string& asset, double value, const std::string& what) {
    if (!std::isfinite(value)) {
        fail(ErrorKind::InvalidInput, asset, what + " is not finite");
    }
    return float(std::clamp(value, 0.0, 1.0));
}

float finite_float(const std::string& asset, double value, const std::string& what) {
    const auto stored = float(value);
    if (!std::isfinite(value) || !std::isfinite(stored)) {
        fail(ErrorKind::InvalidInput, asset,
             what + " " + number_text(value) + " is not finite as a 32-bit float");
    }
    return stored;
}

float non_negative_float(const std::string& asset, double value, const std::string& what) {
    const float stored = finite_float(asset, value, what);
    if (stored < 0.0f) {
        fail(ErrorKind::InvalidInput, asset,
             what + " " + number_text(value) + " is negative (it must be at least 0)");
    }
    return stored;
}

glm::vec2 finite_vec2(const std::string& asset, const tinygltf::Value& value,
                      const std::string& what) {
    if (!value.IsArray() || value.ArrayLen() != 2) {
        fail(ErrorKind::InvalidInput, asset, what + " needs 2 numbers");
    }
    return glm::vec2(finite_float(asset, value.Get(0).GetNumberAsDouble(), what),
                     finite_float(asset, value.Get(1).GetNumberAsDouble(), what));
}

namespace {

// Member `key` of `object`, or null when it is absent and `optional`.
const tinygltf::Value* member(const std::string& asset, const tinygltf::Value& object,
                              const char* key, const std::string& what, bool optional) {
    if (!object.IsObject()) {
        fail(ErrorKind::InvalidInput, asset, what + " must be an object");
    }
    if (!object.Has(key)) {
        if (!optional) {
            fail(ErrorKind::InvalidInput, asset, what + "." + key + " is required");
        }
        return nullptr;
    }
    return &object.Get(key);
}

}  // namespace

std::uint64_t integer_member(const std::string& asset, const tinygltf::Value& object,
                             const char* key, const std::string& what,
                             std::optional<std::uint64_t> fallback) {
    const tinygltf::Value* value = member(asset, object, key, what, fallback.has_value());
    if (value == nullptr) {
        return *fallback;
    }
    const double number = value->IsNumber() ? value->GetNumberAsDouble() : -1.0;
    if (!(number >= 0.0 && number < 9007199254740992.0) || std::floor(number) != number) {
        fail(ErrorKind::InvalidInput, asset, what + "." + key + " must be a non-negative integer");
    }
    return std::uint64_t(number);
}

std::string string_member(const std::string& asset, const tinygltf::Value& object, const char* key,
                          const std::string& what, std::optional<std::string> fallback) {
    const tinygltf::Value* value = member(asset, object, key, what, fallback.has_value());
    if (value == nullptr) {
        return *fallback;
    }
    if (!value->IsString()) {
        fail(ErrorKind::InvalidInput, asset, what + "." + key + " must be a string");
    }
    return value->Get<std::string>();
}

}  // namespace oer::mesh_detail
