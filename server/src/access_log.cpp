#include "access_log.hpp"

#include <array>
#include <cstdio>
#include <string_view>

namespace oer::server {

namespace {

constexpr std::size_t kMaxTarget = 200;

// Control characters would let a client forge log lines.
std::string printable(const std::string& text) {
    std::string out;
    for (const char c : text.substr(0, kMaxTarget)) {
        out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
    }
    if (text.size() > kMaxTarget) {
        out += "...";
    }
    return out;
}

}  // namespace

std::string access_log_line(const std::string& method, const std::string& target, int status,
                            std::size_t bytes, double milliseconds) {
    char numbers[96];
    std::snprintf(numbers, sizeof numbers, " %d %zu B %.1f ms", status, bytes, milliseconds);
    return printable(method_label(method)) + " " + printable(target) + numbers;
}

std::string method_label(const std::string& method) {
    constexpr std::array<std::string_view, 7> kMethods{"GET",    "HEAD",    "POST", "PUT",
                                                       "DELETE", "OPTIONS", "PATCH"};
    for (const std::string_view known : kMethods) {
        if (method == known) {
            return method;
        }
    }
    return "other";
}

}  // namespace oer::server
