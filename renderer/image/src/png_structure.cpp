#include "png_structure.hpp"

#include <algorithm>
#include <cstddef>

namespace oer::png_detail {

namespace {

constexpr std::size_t signature_size = 8;

std::uint32_t big_endian(const std::uint8_t* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
           std::uint32_t(p[3]);
}

bool is_chunk_type(const std::uint8_t* p) {
    for (int i = 0; i < 4; ++i) {
        const bool letter = (p[i] >= 'A' && p[i] <= 'Z') || (p[i] >= 'a' && p[i] <= 'z');
        if (!letter) {
            return false;
        }
    }
    return true;
}

}  // namespace

std::string structure_error(std::span<const std::uint8_t> bytes) {
    static constexpr std::uint8_t signature[signature_size] = {0x89, 'P',  'N',  'G',
                                                               '\r', '\n', 0x1a, '\n'};
    if (bytes.size() < signature_size ||
        !std::equal(signature, signature + signature_size, bytes.begin())) {
        return "not a PNG (no PNG signature)";
    }
    std::size_t at = signature_size;
    bool first = true;
    for (;;) {
        const std::size_t remaining = bytes.size() - at;
        if (remaining < 8) {
            return "truncated PNG: no IEND chunk in its " + std::to_string(bytes.size()) + " bytes";
        }
        const std::uint8_t* header = bytes.data() + at;
        const std::uint32_t length = big_endian(header);
        if (!is_chunk_type(header + 4)) {
            return "corrupt PNG: no chunk type at byte " + std::to_string(at + 4);
        }
        const std::string type(reinterpret_cast<const char*>(header + 4), 4);
        if (length > 0x7fffffffu) {
            return "corrupt PNG: chunk " + type + " at byte " + std::to_string(at) + " declares " +
                   std::to_string(length) + " bytes";
        }
        if (first && (type != "IHDR" || length != 13)) {
            return "corrupt PNG: the first chunk is " + type + " of " + std::to_string(length) +
                   " bytes, not IHDR of 13";
        }
        first = false;
        // length, type, data, CRC
        if (std::uint64_t(length) + 12 > remaining) {
            return "truncated PNG: chunk " + type + " at byte " + std::to_string(at) +
                   " declares " + std::to_string(length) + " bytes, " +
                   std::to_string(remaining < 12 ? 0 : remaining - 12) + " remain";
        }
        at += std::size_t(length) + 12;
        if (type == "IEND") {
            return {};
        }
    }
}

}  // namespace oer::png_detail
