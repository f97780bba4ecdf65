#include "png_structure.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>

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

PngLayout failed(std::string error) {
    PngLayout layout;
    layout.error = std::move(error);
    return layout;
}

}  // namespace

PngLayout read_layout(std::uint64_t size, const ByteReader& read) {
    static constexpr std::uint8_t signature[signature_size] = {0x89, 'P',  'N',  'G',
                                                               '\r', '\n', 0x1a, '\n'};
    std::uint8_t head[signature_size];
    if (!read(0, head, signature_size) ||
        !std::equal(signature, signature + signature_size, head)) {
        return failed("not a PNG (no PNG signature)");
    }
    PngLayout layout;
    std::uint64_t at = signature_size;
    bool first = true;
    for (;;) {
        const std::uint64_t remaining = size - at;
        std::uint8_t header[8 + 13];  // length, type, and IHDR's data when it is the first
        if (remaining < 8 || !read(at, header, 8)) {
            return failed("truncated PNG: no IEND chunk in its " + std::to_string(size) + " bytes");
        }
        const std::uint32_t length = big_endian(header);
        if (!is_chunk_type(header + 4)) {
            return failed("corrupt PNG: no chunk type at byte " + std::to_string(at + 4));
        }
        const std::string type(reinterpret_cast<const char*>(header + 4), 4);
        if (length > 0x7fffffffu) {
            return failed("corrupt PNG: chunk " + type + " at byte " + std::to_string(at) +
                          " declares " + std::to_string(length) + " bytes");
        }
        if (first && (type != "IHDR" || length != 13)) {
            return failed("corrupt PNG: the first chunk is " + type + " of " +
                          std::to_string(length) + " bytes, not IHDR of 13");
        }
        // length, type, data, CRC
        if (std::uint64_t(length) + 12 > remaining) {
            return failed("truncated PNG: chunk " + type + " at byte " + std::to_string(at) +
                          " declares " + std::to_string(length) + " bytes, " +
                          std::to_string(remaining < 12 ? 0 : remaining - 12) + " remain");
        }
        if (first) {
            if (!read(at + 8, header + 8, 13)) {
                return failed("truncated PNG: IHDR cannot be read");
            }
            const std::uint8_t* ihdr = header + 8;
            layout.width = big_endian(ihdr);
            layout.height = big_endian(ihdr + 4);
            layout.bit_depth = ihdr[8];
            layout.color_type = ihdr[9];
            layout.interlace = ihdr[12];
        }
        first = false;
        if (type == "IDAT") {
            layout.idat_bytes += length;
        }
        at += std::uint64_t(length) + 12;
        if (type == "IEND") {
            return layout;
        }
    }
}

PngLayout read_layout(std::span<const std::uint8_t> bytes) {
    return read_layout(bytes.size(),
                       [bytes](std::uint64_t offset, std::uint8_t* out, std::size_t n) {
                           if (offset > bytes.size() || n > bytes.size() - offset) {
                               return false;
                           }
                           std::memcpy(out, bytes.data() + offset, n);
                           return true;
                       });
}

}  // namespace oer::png_detail
