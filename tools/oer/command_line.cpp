#include "command_line.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace oer::cli {

std::optional<std::string> CommandLine::value(const std::string& flag) const {
    const auto found = values.find(flag);
    if (found == values.end() || found->second.empty()) {
        return std::nullopt;
    }
    return found->second.back();
}

CommandLine parse_command_line(const std::vector<std::string>& arguments,
                               const std::set<std::string>& valued,
                               const std::set<std::string>& switches) {
    CommandLine line;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string& argument = arguments[i];
        if (argument.size() < 2 || argument[0] != '-') {
            line.positional.push_back(argument);
            continue;
        }
        std::string flag = argument.substr(argument.rfind('-', 1) + 1);
        std::optional<std::string> inline_value;
        if (const auto equals = flag.find('='); equals != std::string::npos) {
            inline_value = flag.substr(equals + 1);
            flag.resize(equals);
        }
        if (switches.contains(flag) && !inline_value) {
            line.switches.insert(flag);
        } else if (valued.contains(flag)) {
            if (!inline_value && i + 1 >= arguments.size()) {
                throw UsageError(argument + " needs a value");
            }
            line.values[flag].push_back(inline_value ? *inline_value : arguments[++i]);
        } else {
            throw UsageError("unknown option " + argument);
        }
    }
    return line;
}

double parse_double(const std::string& flag, const std::string& text) {
    try {
        std::size_t used = 0;
        const double value = std::stod(text, &used);
        if (used == text.size() && std::isfinite(value)) {
            return value;
        }
    } catch (const std::exception&) {
    }
    throw UsageError("--" + flag + " expects a number, got '" + text + "'");
}

int parse_int(const std::string& flag, const std::string& text, int low, int high) {
    const double value = parse_double(flag, text);
    if (value != std::floor(value) || value < low || value > high) {
        throw UsageError("--" + flag + " expects an integer in " + std::to_string(low) + ".." +
                         std::to_string(high) + ", got '" + text + "'");
    }
    return int(value);
}

UsageError usage_error(const api::InvalidParameter& error) {
    std::string flag = error.parameter();
    std::replace(flag.begin(), flag.end(), '_', '-');
    return UsageError("--" + flag + std::string(error.what()).substr(error.parameter().size()));
}

std::pair<int, int> parse_size(const std::string& flag, const std::string& text, int max) {
    const auto x = text.find('x');
    int width = 0, height = 0;
    const auto parse = [&](std::size_t from, std::size_t to, int& out) {
        const auto [end, error] = std::from_chars(text.data() + from, text.data() + to, out);
        return error == std::errc() && end == text.data() + to && to > from;
    };
    if (x == std::string::npos || !parse(0, x, width) || !parse(x + 1, text.size(), height) ||
        width < 1 || height < 1 || width > max || height > max) {
        throw UsageError("--" + flag + " expects WIDTHxHEIGHT with each in 1.." +
                         std::to_string(max) + ", got '" + text + "'");
    }
    return {width, height};
}

}  // namespace oer::cli
