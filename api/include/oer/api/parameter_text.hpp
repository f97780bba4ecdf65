#pragma once
// Parameter values as text: the query parameters of the API (rig options, GET /v1/render) and
// the flags of `oer` that share their vocabulary. One parser per kind of value, so that every
// place accepts and rejects exactly the same text. Each throws InvalidParameter naming `name`.
#include <string>

#include <glm/vec3.hpp>

#include "oer/api/invalid_parameter.hpp"

namespace oer::api {

// A finite decimal number in [low, high] ("1.5", "-2e3"; not "inf", "nan", "0x1p3" or "").
double parse_number(const std::string& name, const std::string& text, double low, double high);

// A decimal integer in [low, high].
long long parse_integer(const std::string& name, const std::string& text, long long low,
                        long long high);

// "x,y,z": exactly three numbers as parse_number accepts, each in [low, high].
glm::dvec3 parse_vector3(const std::string& name, const std::string& text, double low, double high);

// "on" or "off".
bool parse_on_off(const std::string& name, const std::string& text);

// A number as messages show it: the shortest text that reads back as the same double.
std::string number_text(double value);

// At most 64 characters of a client's text, for messages that echo it.
std::string excerpt(const std::string& text);

// An enum by its name, through one of the renderer's or the api's `*_from_string` functions
// (which throw oer::Error listing the names they know).
template <typename FromString>
auto parse_enum(const std::string& name, const std::string& text, FromString from_string) {
    try {
        return from_string(text);
    } catch (const Error& error) {
        throw InvalidParameter(name, error.what());
    }
}

}  // namespace oer::api
