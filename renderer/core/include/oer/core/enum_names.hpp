#pragma once
// The one way an option's enum is named in text (CLI flags, query parameters, JSON): a table of
// (value, name) pairs per enum, and lookups both ways with a precise error for unknown names.
#include <array>
#include <string>
#include <string_view>
#include <utility>

#include "oer/core/error.hpp"

namespace oer {

template <typename Enum, std::size_t N>
using EnumNames = std::array<std::pair<Enum, std::string_view>, N>;

template <typename Enum, std::size_t N>
std::string name_of(Enum value, const EnumNames<Enum, N>& names) {
    for (const auto& [candidate, name] : names) {
        if (candidate == value) {
            return std::string(name);
        }
    }
    throw Error(ErrorKind::Internal, "enum value " + std::to_string(int(value)) + " has no name");
}

// what names the option in the message: "tone mapper 'filmic' is not one of neutral, aces, none".
template <typename Enum, std::size_t N>
Enum value_named(const std::string& text, const EnumNames<Enum, N>& names, std::string_view what) {
    std::string known;
    for (const auto& [value, name] : names) {
        if (name == text) {
            return value;
        }
        known += (known.empty() ? "" : ", ") + std::string(name);
    }
    throw Error(ErrorKind::InvalidInput,
                std::string(what) + " '" + text + "' is not one of " + known);
}

}  // namespace oer
