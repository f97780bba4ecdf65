#pragma once
// The flags of every `oer` command, parsed by CLI11: each command declares its flags on a
// CLI::App and parse_flags reads the arguments into it; run_command reports errors the same way
// for `oer` and `oer-render`.
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "oer/api/invalid_parameter.hpp"

namespace oer::cli {

// A usage mistake: the message is printed with the command's usage, exit status 2.
class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Reads `arguments` (those after the command's name) into `app`; CLI11's errors (an unknown
// flag, a missing value) throw UsageError. Returns false when --help was asked for and printed.
bool parse_flags(CLI::App& app, const std::vector<std::string>& arguments);

// Declares --FLAG taking one value (the last one given counts), stored through `store`; the
// option, for a description.
CLI::Option* add_value_flag(CLI::App& app, const std::string& flag, const std::string& value_name,
                            std::function<void(const std::string&)> store);

// A finite number; throws UsageError naming --flag.
double parse_double(const std::string& flag, const std::string& text);

// A parameter the api's parsers rejected, named as the flag that gave it: "shadow_filter: ..."
// becomes "--shadow-filter: ..." (flags are the api's names with '-' for '_', unless `flag`
// names it).
UsageError usage_error(const api::InvalidParameter& error, const std::string& flag = {});

// "640x480" -> {640, 480}; each in 1..max.
std::pair<int, int> parse_size(const std::string& flag, const std::string& text, int max);

// Runs `command` with the arguments after its name, reporting its errors on one line as
// "oer NAME: message": exit status 2 for a usage mistake, 1 for any other error.
using Command = int (*)(const std::vector<std::string>& arguments);
int run_command(const std::string& name, Command command,
                const std::vector<std::string>& arguments);

}  // namespace oer::cli
