#pragma once
// Sizes as messages and logs write them: an image's or a frame's as "640x480", a byte count as
// "1.5 MiB" (three significant digits).
#include <cstdint>
#include <sstream>
#include <string>

namespace oer {

inline std::string size_text(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

inline std::string mebibytes(std::uint64_t bytes) {
    std::ostringstream text;
    text.precision(3);
    text << double(bytes) / double(1 << 20) << " MiB";
    return text.str();
}

}  // namespace oer
