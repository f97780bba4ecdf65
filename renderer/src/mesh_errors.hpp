#pragma once
// Private to the mesh loaders: their errors, which always name the asset first, and the
// one-line form of a library's (tinygltf's, tinyobjloader's) multi-line messages.
#include <cstddef>
#include <string>

#include "oer/error.hpp"

namespace oer::mesh_detail {

[[noreturn]] inline void fail(ErrorKind kind, const std::string& asset, const std::string& what) {
    throw Error(kind, asset + ": " + what);
}

// Newlines become "; ", and the text is cut at `max_chars` (a library may quote a whole data:
// URI in its message).
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

}  // namespace oer::mesh_detail
