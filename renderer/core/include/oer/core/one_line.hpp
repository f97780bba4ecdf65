#pragma once
// Third-party libraries' messages (OpenImageIO, tinygltf, tinyobjloader) can span lines and
// quote whole inputs: one_line makes them embeddable in ours. Messages end up in JSON (the
// service's problem bodies, a mesh's warnings), which holds UTF-8 text only (RFC 8259, section
// 8.1): quoted input that is not UTF-8 is escaped here, so that writing the message never
// fails.
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace oer::detail {

// The length of the well-formed UTF-8 sequence starting at text[i] (RFC 3629, section 4: no
// overlong forms, no surrogates, nothing above U+10FFFF), 0 if there is none.
inline std::size_t utf8_sequence_length(std::string_view text, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    if (lead < 0x80) {
        return 1;
    }
    std::size_t length = 0;
    unsigned char low = 0x80;  // the second byte's range; later bytes are 80..BF
    unsigned char high = 0xBF;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        low = lead == 0xE0 ? 0xA0 : 0x80;
        high = lead == 0xED ? 0x9F : 0xBF;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        low = lead == 0xF0 ? 0x90 : 0x80;
        high = lead == 0xF4 ? 0x8F : 0xBF;
    } else {
        return 0;
    }
    if (i + length > text.size() || byte(i + 1) < low || byte(i + 1) > high) {
        return 0;
    }
    for (std::size_t k = 2; k < length; ++k) {
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) {
            return 0;
        }
    }
    return length;
}

// The text with every byte that is not part of a well-formed UTF-8 sequence written as \xNN.
inline std::string valid_utf8(std::string_view text) {
    std::string valid;
    valid.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        if (const std::size_t length = utf8_sequence_length(text, i); length > 0) {
            valid.append(text.substr(i, length));
            i += length;
        } else {
            char escaped[5];
            std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned char>(text[i]));
            valid += escaped;
            ++i;
        }
    }
    return valid;
}

// UTF-8 text cut to at most max_bytes, never inside a character, with "..." when cut.
inline std::string shortened(std::string text, std::size_t max_bytes) {
    if (text.size() <= max_bytes) {
        return text;
    }
    std::size_t cut = max_bytes;
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) {
        --cut;  // a continuation byte: the character starts before it
    }
    text.resize(cut);
    return text + "...";
}

// Newlines become "; ", trailing separators go, bytes that are not UTF-8 are escaped
// (valid_utf8), and the text is cut at max_chars bytes.
inline std::string one_line(std::string_view text, std::size_t max_chars = 400) {
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
    return shortened(valid_utf8(line), max_chars);
}

}  // namespace oer::detail
