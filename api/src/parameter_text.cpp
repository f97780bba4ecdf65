#include "oer/api/parameter_text.hpp"

#include <array>
#include <charconv>
#include <cmath>

#include "oer/core/one_line.hpp"

namespace oer::api {

namespace {

constexpr std::size_t kExcerptLength = 64;

// from_chars over the whole text, or nothing.
template <typename Value>
bool read_whole(const std::string& text, Value& value) {
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

}  // namespace

std::string number_text(double value) {
    std::array<char, 32> buffer{};
    const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return error == std::errc() ? std::string(buffer.data(), end) : std::to_string(value);
}

std::string excerpt(const std::string& text) {
    return detail::shortened(detail::valid_utf8(text), kExcerptLength);
}

double parse_number(const std::string& name, const std::string& text, double low, double high) {
    double value = 0.0;
    if (!read_whole(text, value) || !std::isfinite(value)) {
        throw InvalidParameter(name, "expected a finite number, got '" + excerpt(text) + "'");
    }
    if (value < low || value > high) {
        throw InvalidParameter(name, "must be in [" + number_text(low) + ", " + number_text(high) +
                                         "], got " + excerpt(text));
    }
    // -0 and 0 are one value: keep canonical forms (and the ids hashed from them) equal.
    return value + 0.0;
}

long long parse_integer(const std::string& name, const std::string& text, long long low,
                        long long high) {
    long long value = 0;
    if (!read_whole(text, value)) {
        throw InvalidParameter(name, "expected an integer, got '" + excerpt(text) + "'");
    }
    if (value < low || value > high) {
        throw InvalidParameter(name, "must be in " + std::to_string(low) + ".." +
                                         std::to_string(high) + ", got " + excerpt(text));
    }
    return value;
}

glm::dvec3 parse_vector3(const std::string& name, const std::string& text, double low,
                         double high) {
    glm::dvec3 v{0.0};
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t end = i < 2 ? text.find(',', start) : text.size();
        if (end == std::string::npos || (i == 2 && text.find(',', start) != std::string::npos)) {
            throw InvalidParameter(name, "expected x,y,z (three comma-separated numbers), got '" +
                                             excerpt(text) + "'");
        }
        v[i] = parse_number(name, text.substr(start, end - start), low, high);
        start = end + 1;
    }
    return v;
}

bool parse_on_off(const std::string& name, const std::string& text) {
    if (text != "on" && text != "off") {
        throw InvalidParameter(name, "expected on or off, got '" + excerpt(text) + "'");
    }
    return text == "on";
}

}  // namespace oer::api
