#pragma once
// Parsing of `oer COMMAND ARG... --flag value...`: positional arguments and named values, each
// command declaring which flags take a value and which stand alone.
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "oer/api/invalid_parameter.hpp"

namespace oer::cli {

// A usage mistake: the message is printed with the command's usage, exit status 2.
class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct CommandLine {
    std::vector<std::string> positional;
    std::map<std::string, std::vector<std::string>>
        values;                      // flag (without --) -> values, in order
    std::set<std::string> switches;  // flags without a value that were given

    std::optional<std::string> value(const std::string& flag) const;  // the last one given
    bool has(const std::string& flag) const { return switches.contains(flag); }
};

// valued: flags that take a value (-o is spelled "o"); switches: flags that take none.
CommandLine parse_command_line(const std::vector<std::string>& arguments,
                               const std::set<std::string>& valued,
                               const std::set<std::string>& switches);

// A finite number, and an integer in [low, high]; throw UsageError naming --flag.
double parse_double(const std::string& flag, const std::string& text);
int parse_int(const std::string& flag, const std::string& text, int low, int high);

// A parameter the api's parsers rejected, named as the flag that gave it: "shadow_filter: ..."
// becomes "--shadow-filter: ..." (flags are the api's names with '-' for '_').
UsageError usage_error(const api::InvalidParameter& error);

// "640x480" -> {640, 480}; each in 1..max.
std::pair<int, int> parse_size(const std::string& flag, const std::string& text, int max);

}  // namespace oer::cli
