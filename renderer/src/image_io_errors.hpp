#pragma once
// Private to image_io*.cpp: the errors of image reading and writing, which always name the
// file (or the in-memory name) first.
#include <string>

#include "oer/error.hpp"

namespace oer::image_io_detail {

[[noreturn]] inline void fail(ErrorKind kind, const std::string& name, const std::string& what) {
    throw Error(kind, name + ": " + what);
}

// OpenImageIO's messages end with newlines and may hold several lines: make them one line,
// so that they embed in ours.
inline std::string trim(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\r')) {
        text.pop_back();
    }
    std::string line;
    for (char c : text) {
        if (c == '\n') {
            line += "; ";
        } else if (c != '\r') {
            line += c;
        }
    }
    return line;
}

}  // namespace oer::image_io_detail
