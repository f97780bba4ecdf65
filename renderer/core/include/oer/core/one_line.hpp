#pragma once
// Third-party libraries' messages (OpenImageIO, tinygltf, tinyobjloader) can span lines and
// quote whole inputs: one_line makes them embeddable in ours.
#include <cstddef>
#include <string>

namespace oer::detail {

// Newlines become "; ", trailing separators go, and the text is cut at max_chars.
inline std::string one_line(const std::string& text, std::size_t max_chars = 400) {
    std::string line;
    for (char c : text) {
        if (c == '\n') {
            line += "; ";
        } else if (c != '\r') {
            line += c;
        }
    }
    while (!line.empty() && (line.back() == ' ' || line.back() == ';')) {
        line.pop_back();
    }
    if (line.size() > max_chars) {
        line.resize(max_chars);
        line += "...";
    }
    return line;
}

}  // namespace oer::detail
