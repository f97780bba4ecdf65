// What a map's header claims, and the fewest bytes that can hold it (see image_claims.hpp).
// Each lower bound is a true minimum for what the reader decodes without an error or warning
// (the loader refuses a file whose reader reported either): a file below it is truncated or
// lies about its size, and is refused before any pixel memory is allocated.
#include "image_claims.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "png_structure.hpp"

namespace oer::image_io_detail {

namespace {

// Arithmetic on claimed sizes, which may be absurd: saturates instead of wrapping.
constexpr std::uint64_t kHuge = std::uint64_t(1) << 62;

std::uint64_t add(std::uint64_t a, std::uint64_t b) {
    return std::min(kHuge, std::min(a, kHuge) + std::min(b, kHuge));
}

std::uint64_t mul(std::uint64_t a, std::uint64_t b) {
    if (a == 0 || b == 0) {
        return 0;
    }
    return a > kHuge / b ? kHuge : a * b;
}

std::uint64_t ceil_div(std::uint64_t a, std::uint64_t b) {
    return a / b + (a % b != 0 ? 1 : 0);
}

bool read_at(OIIO::Filesystem::IOProxy& proxy, std::uint64_t offset, void* out, std::size_t n) {
    return offset <= proxy.size() && n <= proxy.size() - offset &&
           proxy.pread(out, n, std::int64_t(offset)) == n;
}

std::uint32_t little_u32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}

std::int32_t little_i32(const unsigned char* p) {
    return std::int32_t(little_u32(p));
}

// ---------------------------------------------------------------------------------------------
// Radiance RGBE (.hdr), as OpenImageIO 2.4's reader (src/hdr.imageio/hdrinput.cpp) decodes it;
// the format: Greg Ward, "Real Pixels", Graphics Gems II (1991), and the Radiance file formats
// (radiance-online.org, "Radiance File Formats", picture file).
//
// The header is read in "lines" of at most 128 bytes, as the reader's fgets into a 128-byte
// buffer cuts them: a first line (normally "#?RADIANCE"), lines up to a blank one, among them
// "FORMAT=32-bit_rle_rgbe", then the resolution line "-Y H +X W" (any of the 8 orientations:
// the reader takes the first number as the count of scanlines and the second as their length).
//
// Each scanline is decoded on its own. Of width w outside 8..32767 it is flat: 4 bytes (R, G,
// B, shared exponent) per pixel. Of width 8..32767 it is either flat, or "new" RLE: a 4-byte
// start (2, 2, w >> 8, w & 0xff), then each of the 4 channels as packets: a run (a count byte
// 129..255, then one value: up to 127 equal values in 2 bytes) or a literal (a count byte
// 1..128, then that many values: c values in c + 1 bytes). Every packet costs at least 2 bytes
// and covers at most 127 values at that cost (a literal of 128 costs 129), so a channel of w
// values needs at least 2 * ceil(w / 127) bytes, and an RLE scanline 4 + 8 * ceil(w / 127),
// fewer than a flat one's 4 * w from w = 8 on.

class HeaderLines {
  public:
    explicit HeaderLines(OIIO::Filesystem::IOProxy& proxy) : proxy_(proxy) {}
    // The next line as the reader sees it (up to and including '\n', at most 128 bytes); empty
    // at the end of the file.
    std::string next() {
        std::array<char, 128> buffer{};
        const std::size_t got = proxy_.pread(
            buffer.data(), std::min<std::uint64_t>(buffer.size(), proxy_.size() - position_),
            std::int64_t(position_));
        std::string line(buffer.data(), got);
        if (const std::size_t newline = line.find('\n'); newline != std::string::npos) {
            line.resize(newline + 1);
        }
        position_ += line.size();
        return line;
    }
    std::uint64_t position() const { return position_; }

  private:
    OIIO::Filesystem::IOProxy& proxy_;
    std::uint64_t position_ = 0;
};

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// "[+-][XY] <int> [+-][XY] <int>" with the two axes different, whitespace allowed around each
// part (as OpenImageIO's Strutil::parse_values reads it); trailing text is ignored.
std::optional<std::array<long long, 2>> resolution(const std::string& line) {
    std::size_t i = 0;
    auto skip_space = [&] {
        while (i < line.size() && is_space(line[i])) {
            ++i;
        }
    };
    auto axis = [&]() -> char {
        skip_space();
        if (i + 1 < line.size() && (line[i] == '+' || line[i] == '-') &&
            (line[i + 1] == 'X' || line[i + 1] == 'Y')) {
            i += 2;
            return line[i - 1];
        }
        return 0;
    };
    auto number = [&]() -> std::optional<long long> {
        skip_space();
        const bool negative = i < line.size() && line[i] == '-';
        if (i < line.size() && (line[i] == '-' || line[i] == '+')) {
            ++i;
        }
        long long value = 0;
        const std::size_t first = i;
        while (i < line.size() && line[i] >= '0' && line[i] <= '9') {
            value = value * 10 + (line[i] - '0');
            if (value > std::numeric_limits<int>::max()) {
                return std::nullopt;
            }
            ++i;
        }
        if (i == first) {
            return std::nullopt;
        }
        return negative ? -value : value;
    };
    const char first_axis = axis();
    const auto rows = first_axis != 0 ? number() : std::nullopt;
    const char second_axis = rows ? axis() : 0;
    const auto length = second_axis != 0 && second_axis != first_axis ? number() : std::nullopt;
    if (!length) {
        return std::nullopt;
    }
    return std::array<long long, 2>{*rows, *length};
}

ClaimResult radiance_claim(OIIO::Filesystem::IOProxy& proxy) {
    HeaderLines lines(proxy);
    if (lines.next().empty()) {
        return NotThisFormat{"empty file"};
    }
    std::string line = lines.next();
    bool format_line = false;
    for (int count = 0; count < 100 && !line.empty() && line[0] != '\n'; ++count) {
        format_line = format_line || line == "FORMAT=32-bit_rle_rgbe\n";
        line = lines.next();
    }
    if (line.empty()) {
        return NotThisFormat{"the header ends before its blank line"};
    }
    if (!format_line) {
        return NotThisFormat{"no FORMAT=32-bit_rle_rgbe line in the header"};
    }
    if (line != "\n") {
        return NotThisFormat{"no blank line after the header's first 100 lines"};
    }
    const auto size = resolution(lines.next());
    if (!size) {
        return NotThisFormat{"no resolution line (such as \"-Y 512 +X 1024\") after the header"};
    }
    HeaderClaim claim;
    claim.height = int((*size)[0]);
    claim.width = int((*size)[1]);
    const std::uint64_t rows = std::uint64_t(std::max(0, claim.height));
    const std::uint64_t width = std::uint64_t(std::max(0, claim.width));
    const bool rle = width >= 8 && width <= 0x7fff;
    const std::uint64_t per_row = rle ? 4 + 8 * ceil_div(width, 127) : 4 * width;
    claim.available = proxy.size();
    claim.needed = add(lines.position(), mul(rows, per_row));
    claim.minimum = rle ? "RLE needs at least " + std::to_string(claim.needed) +
                              " bytes: the header, then a 4-byte start and 2 bytes per 127 "
                              "pixels of each channel on each of " +
                              std::to_string(rows) + " scanlines"
                        : "flat RGBE pixels need at least " + std::to_string(claim.needed) +
                              " bytes: the header, then 4 bytes a pixel";
    return claim;
}

// ---------------------------------------------------------------------------------------------
// OpenEXR, "The OpenEXR File Layout" (openexr.com, documentation, OpenEXRFileLayout): magic
// 76 2f 31 01, a version field (version 2 in its low byte; flags 0x200 single-part tiled, 0x800
// single-part deep, 0x1000 multi-part), the headers (attributes "name\0type\0" int32 size,
// value; each header ends with an empty name, and a multi-part file's list of headers with an
// empty header), then one chunk offset table per part (an 8-byte offset per chunk), then the
// chunks. OpenEXR 3.1 reads every table when the file is opened.
//
// The chunks of a part: of scanlines, ceil(height / lines per chunk) (lines per chunk by
// compression: NONE, RLE, ZIPS 1; ZIP, PXR24 16; PIZ, B44, B44A, DWAA 32; DWAB 256); of tiles,
// the tiles of every level (ONE_LEVEL, MIPMAP_LEVELS or RIPMAP_LEVELS, rounding down or up, as
// OpenEXR's ImfTiledMisc.cpp computes them). Each chunk starts with its own header: 8 bytes (y,
// data size) for scanlines, 20 (tile x, y, level x, y, data size) for tiles, 28 and 40 for deep
// ones, 4 more in a multi-part file (the part number).
//
// Then the pixels of the first part (the one read), level 0: per channel floor(w / xSampling) *
// floor(h / ySampling) samples of 2 (HALF) or 4 (FLOAT, UINT) bytes. A chunk whose compressed
// data would not be smaller is stored uncompressed, so its data is at least the smaller of the
// two, and the compressed size has these minimums:
//  - NONE: the pixels themselves;
//  - RLE: a 2-byte run expands to at most 128 bytes (ImfRle.cpp: a count byte 0..127 repeats
//    the next byte count + 1 times), so 1/64 of them;
//  - ZIPS, ZIP: zlib's deflate expands at most 1032:1 (a 258-byte match costs at least 2 bits:
//    zlib.net, "zlib Technical Details", maximum compression factor), so 1/1032 of them;
//  - PXR24: deflate of the pixels with FLOAT shortened to 3 bytes, so 1/1032 of that;
//  - B44, B44A: UINT and FLOAT channels are stored as they are; HALF channels in 14-byte (B44)
//    or, when flat, 3-byte (B44A) blocks of 4x4 samples;
//  - PIZ, DWAA, DWAB (wavelet and Huffman with runs, DCT): no simple bound; the table and the
//    chunk headers only.
// Deep parts (refused later, as unsupported) count their table and chunk headers only.

struct ExrChannel {
    int pixel_type = 0;  // 0 UINT, 1 HALF, 2 FLOAT
    std::int32_t x_sampling = 1;
    std::int32_t y_sampling = 1;
};

struct ExrPart {
    std::optional<std::array<std::int32_t, 4>> data_window;  // xMin, yMin, xMax, yMax
    std::optional<int> compression;
    std::optional<std::array<std::uint32_t, 2>> tile_size;
    int tile_mode = 0;  // low 4 bits: level mode; high 4 bits: rounding mode
    std::optional<std::string> type;
    std::optional<std::int32_t> chunk_count;
    std::vector<ExrChannel> channels;
};

class ExrHeaderReader {
  public:
    explicit ExrHeaderReader(OIIO::Filesystem::IOProxy& proxy) : proxy_(proxy) {}

    std::uint64_t position = 8;
    std::string error;

    // A NUL-terminated name of at most 255 characters; nullopt (and error set) otherwise.
    std::optional<std::string> name() {
        std::string text;
        for (;;) {
            char c = 0;
            if (!read_at(proxy_, position, &c, 1)) {
                error = "the header ends inside a name at byte " + std::to_string(position);
                return std::nullopt;
            }
            ++position;
            if (c == '\0') {
                return text;
            }
            if (text.size() == 255) {
                error = "a name longer than 255 bytes at byte " + std::to_string(position);
                return std::nullopt;
            }
            text.push_back(c);
        }
    }

    // One header's attributes, up to its empty name.
    std::optional<ExrPart> part() {
        ExrPart part;
        for (;;) {
            const auto attribute = name();
            if (!attribute) {
                return std::nullopt;
            }
            if (attribute->empty()) {
                return part;
            }
            const auto type = name();
            unsigned char size_bytes[4];
            if (!type || !read_at(proxy_, position, size_bytes, 4)) {
                error = error.empty() ? "the header ends in attribute " + *attribute : error;
                return std::nullopt;
            }
            const std::int32_t size = little_i32(size_bytes);
            position += 4;
            if (size < 0 || std::uint64_t(size) > proxy_.size() - position) {
                error = "attribute " + *attribute + " declares " + std::to_string(size) +
                        " bytes, " + std::to_string(proxy_.size() - position) + " remain";
                return std::nullopt;
            }
            std::vector<unsigned char> value(static_cast<std::size_t>(size));
            read_at(proxy_, position, value.data(), value.size());
            position += std::uint64_t(size);
            if (!keep(part, *attribute, *type, value)) {
                error = "attribute " + *attribute + " of type " + *type + " is malformed";
                return std::nullopt;
            }
        }
    }

  private:
    static bool keep(ExrPart& part, const std::string& attribute, const std::string& type,
                     const std::vector<unsigned char>& value) {
        if (attribute == "dataWindow" && type == "box2i") {
            if (value.size() != 16) {
                return false;
            }
            part.data_window = {little_i32(&value[0]), little_i32(&value[4]), little_i32(&value[8]),
                                little_i32(&value[12])};
        } else if (attribute == "compression" && type == "compression") {
            if (value.size() != 1) {
                return false;
            }
            part.compression = value[0];
        } else if (attribute == "tiles" && type == "tiledesc") {
            if (value.size() != 9) {
                return false;
            }
            part.tile_size = {little_u32(&value[0]), little_u32(&value[4])};
            part.tile_mode = value[8];
        } else if (attribute == "type" && type == "string") {
            part.type = std::string(value.begin(), value.end());
        } else if (attribute == "chunkCount" && type == "int") {
            if (value.size() != 4) {
                return false;
            }
            part.chunk_count = little_i32(&value[0]);
        } else if (attribute == "channels" && type == "chlist") {
            // name\0, int32 pixel type, uchar pLinear, 3 reserved, int32 x and y sampling.
            std::size_t at = 0;
            while (at < value.size() && value[at] != 0) {
                const auto end = std::find(value.begin() + std::ptrdiff_t(at), value.end(), 0);
                at = std::size_t(end - value.begin()) + 1;
                if (end == value.end() || value.size() - at < 16) {
                    return false;
                }
                ExrChannel channel;
                channel.pixel_type = little_i32(&value[at]);
                channel.x_sampling = little_i32(&value[at + 8]);
                channel.y_sampling = little_i32(&value[at + 12]);
                if (channel.x_sampling < 1 || channel.y_sampling < 1) {
                    return false;
                }
                part.channels.push_back(channel);
                at += 16;
            }
        }
        return true;
    }

    OIIO::Filesystem::IOProxy& proxy_;
};

int lines_per_chunk(int compression) {
    constexpr std::array<int, 10> lines = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
    return compression >= 0 && compression < int(lines.size()) ? lines[std::size_t(compression)]
                                                               : 0;
}

// OpenEXR's levelSize and roundLog2 (ImfTiledMisc.cpp).
std::uint64_t level_size(std::uint64_t size, int level, bool round_up) {
    const std::uint64_t divisor = std::uint64_t(1) << level;
    std::uint64_t result = size / divisor;
    if (round_up && result * divisor < size) {
        ++result;
    }
    return std::max<std::uint64_t>(result, 1);
}

int level_count(std::uint64_t size, bool round_up) {
    int floor_log = 0;
    bool exact = true;
    for (std::uint64_t x = size; x > 1; x >>= 1) {
        exact = exact && (x & 1) == 0;
        ++floor_log;
    }
    return (round_up && !exact ? floor_log + 1 : floor_log) + 1;
}

std::uint64_t tile_count(const ExrPart& part, std::uint64_t width, std::uint64_t height) {
    const std::uint64_t tile_w = std::max<std::uint32_t>(1, (*part.tile_size)[0]);
    const std::uint64_t tile_h = std::max<std::uint32_t>(1, (*part.tile_size)[1]);
    const int mode = part.tile_mode & 0x0f;
    const bool round_up = (part.tile_mode >> 4) == 1;
    auto tiles = [&](int x_level, int y_level) {
        return mul(ceil_div(level_size(width, x_level, round_up), tile_w),
                   ceil_div(level_size(height, y_level, round_up), tile_h));
    };
    std::uint64_t count = 0;
    if (mode == 0) {
        count = tiles(0, 0);
    } else if (mode == 1) {
        for (int level = 0; level < level_count(std::max(width, height), round_up); ++level) {
            count = add(count, tiles(level, level));
        }
    } else {
        for (int y = 0; y < level_count(height, round_up); ++y) {
            for (int x = 0; x < level_count(width, round_up); ++x) {
                count = add(count, tiles(x, y));
            }
        }
    }
    return count;
}

// The version field and every part's header, after the magic number; `end` is the offset just
// after the headers (and a multi-part file's empty header), where the chunk offset tables start.
struct ExrHeaders {
    std::uint32_t version = 0;
    bool multi_part = false;
    std::vector<ExrPart> parts;
    std::uint64_t end = 0;
};

std::variant<ExrHeaders, NotThisFormat> read_exr_headers(OIIO::Filesystem::IOProxy& proxy) {
    unsigned char start[8];
    if (!read_at(proxy, 0, start, 8) || little_u32(start) != 20000630) {
        return NotThisFormat{"no OpenEXR magic number and version"};
    }
    ExrHeaders headers;
    headers.version = little_u32(start + 4);
    if ((headers.version & 0xff) != 2) {
        return NotThisFormat{"OpenEXR file version " + std::to_string(headers.version & 0xff) +
                             " (only 2 exists)"};
    }
    headers.multi_part = (headers.version & 0x1000) != 0;
    ExrHeaderReader reader(proxy);
    do {
        std::optional<ExrPart> part = reader.part();
        if (!part) {
            return NotThisFormat{"corrupt OpenEXR header: " + reader.error};
        }
        headers.parts.push_back(std::move(*part));
        if (headers.multi_part) {
            unsigned char next = 0;
            if (!read_at(proxy, reader.position, &next, 1)) {
                return NotThisFormat{"corrupt OpenEXR header: the list of parts does not end"};
            }
            if (next == 0) {
                ++reader.position;  // the empty header that ends the list
                break;
            }
        }
    } while (headers.multi_part);
    headers.end = reader.position;
    return headers;
}

// A part's size and chunks: how many, and the bytes of each one's own header.
struct ExrPartLayout {
    long long width = 0;
    long long height = 0;
    bool deep = false;
    std::uint64_t chunks = 0;
    std::uint64_t chunk_header_bytes = 0;
};

// The part's chunks: a chunkCount for a type other than scanlines and tiles, else the tiles of
// every level, or the chunks of `lines` scanlines.
std::variant<std::uint64_t, NotThisFormat> exr_chunk_count(const ExrPart& part,
                                                           const std::string& type, bool tiled,
                                                           bool deep, long long width,
                                                           long long height, int lines) {
    if (type != "scanlineimage" && type != "tiledimage" && !deep) {
        if (!part.chunk_count || *part.chunk_count < 0) {
            return NotThisFormat{"OpenEXR part of type " + type + " without a chunkCount"};
        }
        return std::uint64_t(*part.chunk_count);
    }
    if (tiled) {
        if (!part.tile_size || (part.tile_mode & 0x0f) > 2 || (part.tile_mode >> 4) > 1) {
            return NotThisFormat{"corrupt OpenEXR header: a tiled part without valid tiles"};
        }
        return tile_count(part, std::uint64_t(width), std::uint64_t(height));
    }
    return ceil_div(std::uint64_t(height), std::uint64_t(lines));
}

std::variant<ExrPartLayout, NotThisFormat> exr_part_layout(const ExrPart& part,
                                                           std::uint32_t version, bool multi_part) {
    if (!part.data_window || !part.compression) {
        return NotThisFormat{"corrupt OpenEXR header: no dataWindow or compression"};
    }
    ExrPartLayout layout;
    const auto [x_min, y_min, x_max, y_max] = *part.data_window;
    layout.width = (long long)x_max - x_min + 1;
    layout.height = (long long)y_max - y_min + 1;
    if (layout.width < 1 || layout.height < 1 || layout.width > std::numeric_limits<int>::max() ||
        layout.height > std::numeric_limits<int>::max()) {
        return NotThisFormat{"corrupt OpenEXR header: dataWindow of " +
                             std::to_string(layout.width) + "x" + std::to_string(layout.height) +
                             " pixels"};
    }
    const int lines = lines_per_chunk(*part.compression);
    if (lines == 0) {
        return NotThisFormat{"unknown OpenEXR compression " + std::to_string(*part.compression)};
    }
    const std::string type = part.type.value_or((version & 0x800)   ? "deepscanline"
                                                : (version & 0x200) ? "tiledimage"
                                                                    : "scanlineimage");
    const bool tiled = type == "tiledimage" || type == "deeptile";
    layout.deep = type == "deepscanline" || type == "deeptile";
    const auto chunks =
        exr_chunk_count(part, type, tiled, layout.deep, layout.width, layout.height, lines);
    if (const auto* why = std::get_if<NotThisFormat>(&chunks)) {
        return *why;
    }
    layout.chunks = std::get<std::uint64_t>(chunks);
    layout.chunk_header_bytes =
        (tiled ? (layout.deep ? 40 : 20) : (layout.deep ? 28 : 8)) + (multi_part ? 4 : 0);
    return layout;
}

// The pixels of a part's level 0 in the sizes the compressions' bounds start from: as stored
// (plain), with FLOAT shortened to 3 bytes (PXR24), HALF samples in 4x4 blocks and the bytes of
// the other samples (B44).
struct ExrPixelBytes {
    std::uint64_t plain = 0;
    std::uint64_t pxr24 = 0;
    std::uint64_t half_blocks = 0;
    std::uint64_t not_half = 0;
};

ExrPixelBytes exr_pixel_bytes(const ExrPart& part, long long width, long long height) {
    ExrPixelBytes bytes;
    for (const ExrChannel& channel : part.channels) {
        const std::uint64_t samples =
            mul(std::uint64_t(width) / std::uint64_t(channel.x_sampling),
                std::uint64_t(height) / std::uint64_t(channel.y_sampling));
        const bool half = channel.pixel_type == 1;
        bytes.plain = add(bytes.plain, mul(samples, half ? 2 : 4));
        bytes.pxr24 = add(bytes.pxr24, mul(samples, half ? 2 : channel.pixel_type == 2 ? 3 : 4));
        if (half) {
            bytes.half_blocks =
                add(bytes.half_blocks,
                    mul(std::uint64_t(width) / std::uint64_t(channel.x_sampling) / 4,
                        std::uint64_t(height) / std::uint64_t(channel.y_sampling) / 4));
        } else {
            bytes.not_half = add(bytes.not_half, mul(samples, 4));
        }
    }
    return bytes;
}

// The fewest bytes the first part's compressed pixels take, and how that figure is made up.
struct ExrPixelData {
    std::uint64_t bytes = 0;
    std::string words;
};

ExrPixelData exr_pixel_data(const ExrPart& part, long long width, long long height) {
    const ExrPixelBytes pixel_bytes = exr_pixel_bytes(part, width, height);
    const std::string pixels = std::to_string(pixel_bytes.plain) + " bytes of pixels";
    switch (*part.compression) {
        case 0:
            return {pixel_bytes.plain, pixels + " uncompressed"};
        case 1:
            return {pixel_bytes.plain / 64, "RLE data of " + pixels + " (at most 64:1)"};
        case 2:
        case 3:
            return {pixel_bytes.plain / 1032, "deflate data of " + pixels + " (at most 1032:1)"};
        case 5:
            return {pixel_bytes.pxr24 / 1032, "PXR24's deflate data of " +
                                                  std::to_string(pixel_bytes.pxr24) +
                                                  " bytes of pixels (at most 1032:1)"};
        case 6:
        case 7:
            return {add(pixel_bytes.not_half,
                        mul(pixel_bytes.half_blocks, *part.compression == 6 ? 14 : 3)),
                    "B44 data of " + pixels};
        default:
            return {0, "compressed pixels (no lower bound known for PIZ and DWA)"};
    }
}

ClaimResult openexr_claim(OIIO::Filesystem::IOProxy& proxy) {
    const auto read = read_exr_headers(proxy);
    if (const auto* why = std::get_if<NotThisFormat>(&read)) {
        return *why;
    }
    const ExrHeaders& headers = std::get<ExrHeaders>(read);
    HeaderClaim claim;
    std::uint64_t chunks_total = 0;
    std::uint64_t chunk_headers = 0;
    ExrPixelData data;
    for (std::size_t p = 0; p < headers.parts.size(); ++p) {
        const ExrPart& part = headers.parts[p];
        const auto laid_out = exr_part_layout(part, headers.version, headers.multi_part);
        if (const auto* why = std::get_if<NotThisFormat>(&laid_out)) {
            return *why;
        }
        const ExrPartLayout& layout = std::get<ExrPartLayout>(laid_out);
        chunks_total = add(chunks_total, layout.chunks);
        chunk_headers = add(chunk_headers, mul(layout.chunks, layout.chunk_header_bytes));
        if (p == 0 && !layout.deep) {
            claim.width = int(layout.width);
            claim.height = int(layout.height);
            data = exr_pixel_data(part, layout.width, layout.height);
        }
    }
    claim.available = proxy.size();
    claim.needed = add(add(headers.end, mul(chunks_total, 8)), add(chunk_headers, data.bytes));
    claim.minimum = "a chunk offset table of " + std::to_string(chunks_total) + " entries, " +
                    std::to_string(chunks_total) + " chunk headers and the " + data.words +
                    " need at least " + std::to_string(claim.needed) + " bytes";
    return claim;
}

// ---------------------------------------------------------------------------------------------
// PNG (PNG specification, 3rd edition, W3C): IHDR's size, bit depth, color type and interlace
// method give the filtered rows the zlib stream of the IDAT chunks decompresses to: per row,
// a filter byte and ceil(width * bits per pixel / 8) bytes; an interlaced (Adam7) image has a
// row of each of its 7 reduced images (section 8.2). zlib's deflate expands at most 1032:1
// (zlib.net, "zlib Technical Details": a 258-byte match costs at least 2 bits), so the IDAT
// data is at least 1/1032 of the filtered rows.

std::uint64_t filtered_rows(std::uint64_t width, std::uint64_t height, std::uint64_t bits,
                            bool interlaced) {
    auto rows = [&](std::uint64_t w, std::uint64_t h) {
        return w == 0 || h == 0 ? 0 : mul(h, add(1, ceil_div(mul(w, bits), 8)));
    };
    if (!interlaced) {
        return rows(width, height);
    }
    // Adam7 passes: x start, y start, x step, y step.
    constexpr int passes[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                  {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
    std::uint64_t total = 0;
    for (const auto& [x0, y0, dx, dy] : passes) {
        const std::uint64_t w = width > std::uint64_t(x0) ? ceil_div(width - x0, dx) : 0;
        const std::uint64_t h = height > std::uint64_t(y0) ? ceil_div(height - y0, dy) : 0;
        total = add(total, rows(w, h));
    }
    return total;
}

ClaimResult png_claim(OIIO::Filesystem::IOProxy& proxy) {
    const png_detail::PngLayout layout = png_detail::read_layout(
        proxy.size(), [&proxy](std::uint64_t offset, std::uint8_t* out, std::size_t n) {
            return read_at(proxy, offset, out, n);
        });
    if (!layout.error.empty()) {
        return NotThisFormat{layout.error};
    }
    int channels = 0;
    switch (layout.color_type) {
        case 0:  // grey
        case 3:  // palette indices
            channels = 1;
            break;
        case 2:
            channels = 3;
            break;
        case 4:
            channels = 2;
            break;
        case 6:
            channels = 4;
            break;
        default:
            return NotThisFormat{"corrupt PNG: color type " + std::to_string(layout.color_type)};
    }
    if (layout.width > std::uint32_t(std::numeric_limits<int>::max()) ||
        layout.height > std::uint32_t(std::numeric_limits<int>::max())) {
        return NotThisFormat{"corrupt PNG: IHDR says " + std::to_string(layout.width) + "x" +
                             std::to_string(layout.height)};
    }
    HeaderClaim claim;
    claim.width = int(layout.width);
    claim.height = int(layout.height);
    const std::uint64_t rows =
        filtered_rows(layout.width, layout.height, std::uint64_t(channels * layout.bit_depth),
                      layout.interlace != 0);
    claim.available = layout.idat_bytes;
    claim.needed = ceil_div(rows, 1032);
    claim.minimum = "deflate (at most 1032:1) needs at least " + std::to_string(claim.needed) +
                    " bytes of IDAT data for " + std::to_string(rows) +
                    " bytes of filtered rows; the file has " + std::to_string(layout.idat_bytes);
    return claim;
}

// ---------------------------------------------------------------------------------------------
// JPEG (ITU-T T.81): markers from SOI; the frame header (SOFn) gives the size and each
// component's sampling factors; each scan (SOS) is followed by its entropy-coded data, up to
// the next marker other than RSTn (a 0xFF data byte is followed by a stuffed 0x00).
//
// A component of a frame of X x Y samples with sampling factors h, v (largest hmax, vmax) has
// ceil(ceil(X * h / hmax) / 8) x ceil(ceil(Y * v / vmax) / 8) blocks of 8x8 (A.2.2, A.1.1). With
// Huffman coding every block's DC difference is coded in some scan, with a code of at least 1
// bit (F.1.2.1; also a progressive file's first DC scan, G.1.2.1): at least 1 bit per block. A
// progressive file missing a component's DC scan decodes, but with libjpeg's warning "Inconsistent
// progression sequence", which the loader refuses, like "Premature end of data". With arithmetic
// coding (SOF9 to SOF15) a decision can cost 1/20000 of a bit (Annex D's smallest probability
// estimate), which bounds nothing useful: those files are checked against the limits only.
//
// libjpeg decodes a progressive file, or one whose first scan does not hold every component,
// into a buffer of the whole image's coefficients (64 of 2 bytes per block, each component's
// blocks rounded up to its sampling factors: jdcoefct.c, jinit_d_coef_controller) as decoding
// starts; a single interleaved scan is decoded a row of blocks at a time.

class JpegCursor {
  public:
    explicit JpegCursor(OIIO::Filesystem::IOProxy& proxy) : proxy_(proxy) {}
    std::optional<unsigned char> next() {
        if (at_ >= end_) {
            start_ += end_;
            end_ = std::size_t(std::min<std::uint64_t>(buffer_.size(), proxy_.size() - start_));
            at_ = 0;
            if (end_ == 0 || proxy_.pread(buffer_.data(), end_, std::int64_t(start_)) != end_) {
                end_ = 0;
                return std::nullopt;
            }
        }
        return buffer_[at_++];
    }
    std::uint64_t position() const { return start_ + at_; }

  private:
    OIIO::Filesystem::IOProxy& proxy_;
    std::array<unsigned char, 1 << 16> buffer_{};
    std::uint64_t start_ = 0;
    std::size_t end_ = 0;
    std::size_t at_ = 0;
};

struct JpegComponent {
    int h = 1;
    int v = 1;
};

bool is_restart(int code) {
    return code >= 0xD0 && code <= 0xD7;
}

// SOF0 to SOF15 except DHT (C4), JPG (C8) and DAC (CC).
bool is_frame_header(int code) {
    return code >= 0xC0 && code <= 0xCF && code != 0xC4 && code != 0xC8 && code != 0xCC;
}

// The code of the next marker: after 0xFF and any fill bytes 0xFF (libjpeg skips, and warns
// of, stray bytes before it).
std::optional<int> next_marker(JpegCursor& in) {
    auto b = in.next();
    while (b && *b != 0xFF) {
        b = in.next();
    }
    while (b == 0xFF) {
        b = in.next();
    }
    return b ? std::optional<int>(*b) : std::nullopt;
}

// A marker segment's bytes after its 2-byte length field (fewer where the data ends first).
std::vector<unsigned char> segment_body(JpegCursor& in, int length) {
    std::vector<unsigned char> segment;
    for (int i = 2; i < length; ++i) {
        const auto b = in.next();
        if (!b) {
            break;
        }
        segment.push_back(*b);
    }
    return segment;
}

// What the markers up to EOI (or the end of the data) say: the first frame header's marker,
// size and components, how many components the first scan holds, and the bytes of every scan's
// entropy-coded data.
struct JpegStructure {
    std::optional<int> frame_marker;
    int width = 0;
    int height = 0;
    std::vector<JpegComponent> components;
    std::optional<int> first_scan_components;
    std::uint64_t scan_bytes = 0;
};

// The frame header (SOFn, B.2.2): the size and each component's sampling factors.
std::optional<NotThisFormat> read_frame_header(int code, const std::vector<unsigned char>& segment,
                                               JpegStructure& jpeg) {
    if (segment.size() < 6 || segment.size() < 6 + std::size_t(segment[5]) * 3) {
        return NotThisFormat{"corrupt JPEG: a short frame header"};
    }
    jpeg.frame_marker = code;
    jpeg.height = segment[1] << 8 | segment[2];
    jpeg.width = segment[3] << 8 | segment[4];
    for (int c = 0; c < segment[5]; ++c) {
        const unsigned char factors = segment[6 + std::size_t(c) * 3 + 1];
        jpeg.components.push_back({std::max(1, factors >> 4), std::max(1, factors & 0x0f)});
    }
    return std::nullopt;
}

// A scan's entropy-coded data, up to a marker that is neither a stuffed 0x00 nor RSTn: its bytes
// are added to `scan_bytes`; the marker's code is returned (nullopt at the end of the data).
std::optional<int> skip_scan_data(JpegCursor& in, std::uint64_t& scan_bytes) {
    for (auto b = in.next(); b;) {
        if (*b != 0xFF) {
            ++scan_bytes;
            b = in.next();
            continue;
        }
        auto after = in.next();
        while (after == 0xFF) {
            after = in.next();
        }
        if (after && (*after == 0x00 || is_restart(*after))) {
            scan_bytes += 2;
            b = in.next();
            continue;
        }
        return after;
    }
    return std::nullopt;
}

std::variant<JpegStructure, NotThisFormat> read_jpeg_structure(OIIO::Filesystem::IOProxy& proxy) {
    JpegCursor in(proxy);
    const auto soi_ff = in.next(), soi = in.next();
    if (soi_ff != 0xFF || soi != 0xD8) {
        return NotThisFormat{"no JPEG start of image"};
    }
    JpegStructure jpeg;
    std::optional<int> marker = next_marker(in);
    while (marker && *marker != 0xD9) {  // up to EOI, or the end of the data
        const int code = *marker;
        if (is_restart(code) || code == 0x01 || code == 0xD8) {
            marker = next_marker(in);  // no length
            continue;
        }
        const auto high = in.next(), low = in.next();
        if (!low) {
            break;
        }
        const int length = *high << 8 | *low;
        if (length < 2) {
            return NotThisFormat{"corrupt JPEG: a segment of length " + std::to_string(length)};
        }
        const std::vector<unsigned char> segment = segment_body(in, length);
        if (is_frame_header(code) && !jpeg.frame_marker) {
            if (const auto why = read_frame_header(code, segment, jpeg)) {
                return *why;
            }
        }
        if (code != 0xDA) {
            marker = next_marker(in);
            continue;
        }
        if (!jpeg.first_scan_components && !segment.empty()) {
            jpeg.first_scan_components = segment[0];
        }
        marker = skip_scan_data(in, jpeg.scan_bytes);
    }
    return jpeg;
}

// The 8x8 blocks of every component (A.2.2, A.1.1), and those of libjpeg's coefficient buffer,
// each component's rounded up to its sampling factors.
struct JpegBlocks {
    std::uint64_t coded = 0;
    std::uint64_t buffered = 0;
};

JpegBlocks jpeg_blocks(const JpegStructure& jpeg) {
    int h_max = 1, v_max = 1;
    for (const JpegComponent& component : jpeg.components) {
        h_max = std::max(h_max, component.h);
        v_max = std::max(v_max, component.v);
    }
    JpegBlocks blocks;
    for (const JpegComponent& component : jpeg.components) {
        const std::uint64_t columns =
            ceil_div(ceil_div(std::uint64_t(jpeg.width) * std::uint64_t(component.h), h_max), 8);
        const std::uint64_t rows =
            ceil_div(ceil_div(std::uint64_t(jpeg.height) * std::uint64_t(component.v), v_max), 8);
        blocks.coded += columns * rows;
        blocks.buffered += (ceil_div(columns, component.h) * std::uint64_t(component.h)) *
                           (ceil_div(rows, component.v) * std::uint64_t(component.v));
    }
    return blocks;
}

ClaimResult jpeg_claim(OIIO::Filesystem::IOProxy& proxy) {
    const auto read = read_jpeg_structure(proxy);
    if (const auto* why = std::get_if<NotThisFormat>(&read)) {
        return *why;
    }
    const JpegStructure& jpeg = std::get<JpegStructure>(read);
    if (!jpeg.frame_marker || jpeg.components.empty()) {
        return NotThisFormat{"no JPEG frame header before the end of the data"};
    }
    const int frame_marker = *jpeg.frame_marker;
    HeaderClaim claim;
    claim.width = jpeg.width;
    claim.height = jpeg.height;
    const JpegBlocks blocks = jpeg_blocks(jpeg);
    const bool progressive = frame_marker == 0xC2 || frame_marker == 0xC6 || frame_marker == 0xCA ||
                             frame_marker == 0xCE;
    if (progressive || jpeg.first_scan_components.value_or(0) < int(jpeg.components.size())) {
        claim.reader_bytes = blocks.buffered * 64 * 2;
    }
    claim.available = jpeg.scan_bytes;
    if (frame_marker >= 0xC9) {
        return claim;  // arithmetic coding: no useful lower bound
    }
    claim.needed = ceil_div(blocks.coded, 8);
    claim.minimum =
        "Huffman coding needs at least 1 bit per 8x8 block: " + std::to_string(claim.needed) +
        " bytes of scan data for " + std::to_string(blocks.coded) + " blocks; the file has " +
        std::to_string(jpeg.scan_bytes);
    return claim;
}

}  // namespace

ClaimResult read_claim(const std::string& format, OIIO::Filesystem::IOProxy& proxy) {
    if (format == "hdr") {
        return radiance_claim(proxy);
    }
    if (format == "openexr") {
        return openexr_claim(proxy);
    }
    if (format == "png") {
        return png_claim(proxy);
    }
    if (format == "jpeg") {
        return jpeg_claim(proxy);
    }
    return std::monostate{};
}

}  // namespace oer::image_io_detail
