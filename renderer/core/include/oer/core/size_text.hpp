#pragma once
// Sizes as messages and logs write them: an image's or a frame's as "640x480", a byte count as
// "1.5 MiB" (three significant digits, whole mebibytes from 1000 up).
#include <cstdint>
#include <sstream>
#include <string>

namespace oer {

inline std::string size_text(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

inline std::string mebibytes(std::uint64_t bytes) {
    const double value = double(bytes) / double(1 << 20);
    std::ostringstream text;
    if (value >= 1000.0) {
        text << std::fixed;  // "4096 MiB", not "4.1e+03 MiB"
        text.precision(0);
    } else {
        text.precision(3);
    }
    text << value << " MiB";
    return text.str();
}

}  // namespace oer
