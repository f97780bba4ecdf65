#include "command_line.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>

#include "oer/core/error.hpp"

namespace oer::cli {

bool parse_flags(CLI::App& app, const std::vector<std::string>& arguments) {
    std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());  // CLI11's order
    try {
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return false;
    } catch (const CLI::ParseError& error) {
        throw UsageError(error.what());
    }
    return true;
}

CLI::Option* add_value_flag(CLI::App& app, const std::string& flag, const std::string& value_name,
                            std::function<void(const std::string&)> store) {
    return app.add_option_function<std::string>("--" + flag, std::move(store))
        ->type_name(value_name)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
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

UsageError usage_error(const api::InvalidParameter& error, const std::string& flag) {
    std::string name = flag.empty() ? error.parameter() : flag;
    std::replace(name.begin(), name.end(), '_', '-');
    return UsageError("--" + name + std::string(error.what()).substr(error.parameter().size()));
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

int run_command(const std::string& name, Command command,
                const std::vector<std::string>& arguments) {
    try {
        return command(arguments);
    } catch (const UsageError& error) {
        std::cerr << "oer " << name << ": " << error.what() << "\n";
        return 2;
    } catch (const Error& error) {
        std::cerr << "oer " << name << ": " << error.what() << "\n";
        return 1;
    } catch (const std::exception& error) {
        std::cerr << "oer " << name << ": unexpected error: " << error.what() << "\n";
        return 1;
    }
}

}  // namespace oer::cli
