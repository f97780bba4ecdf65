// KTX2 containers of KHR_texture_basisu: the header and layout checked, the payload named (see
// texture_formats.hpp). The offsets and rules are the KTX 2.0 specification's (Khronos, section
// 3, "File Structure"); those for glTF are KHR_texture_basisu's ("KTX2 file requirements").
#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "oer/core/error.hpp"
#include "texture_formats.hpp"

namespace oer::mesh_detail {

namespace {

constexpr std::array<unsigned char, 12> ktx2_identifier{0xab, 'K',  'T',  'X',  ' ',  '2',
                                                        '0',  0xbb, '\r', '\n', 0x1a, '\n'};

// The header: the identifier, nine 32-bit fields from vkFormat to supercompressionScheme, and
// the index (DFD, key/value data: 32-bit offsets and lengths; supercompression global data:
// 64-bit), 80 bytes; then the level index, 24 bytes a level.
constexpr std::size_t header_bytes = 80;
constexpr std::size_t level_index_entry_bytes = 24;

// supercompressionScheme: BasisLZ carries ETC1S; UASTC is stored as is or
// Zstandard-compressed.
constexpr std::uint32_t scheme_none = 0;
constexpr std::uint32_t scheme_basislz = 1;
constexpr std::uint32_t scheme_zstandard = 2;

// The colour models of the Khronos Data Format (khr_df.h) that KHR_texture_basisu allows.
constexpr std::uint8_t model_etc1s = 163;
constexpr std::uint8_t model_uastc = 166;

std::uint32_t u32(std::span<const std::byte> bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        value |= std::uint32_t(bytes[at + i]) << (8 * i);
    }
    return value;
}

std::uint64_t u64(std::span<const std::byte> bytes, std::size_t at) {
    return std::uint64_t(u32(bytes, at)) | std::uint64_t(u32(bytes, at + 4)) << 32;
}

struct Ktx2Fields {
    std::uint32_t vk_format;
    std::uint32_t width;
    std::uint32_t height;
    std::uint32_t depth;
    std::uint32_t layers;
    std::uint32_t faces;
    std::uint32_t levels;
    std::uint32_t scheme;
    std::uint32_t dfd_offset;
    std::uint32_t dfd_length;
};

Ktx2Fields fields_of(std::span<const std::byte> bytes, const std::string& what) {
    if (bytes.size() < header_bytes) {
        throw Error(ErrorKind::InvalidInput,
                    what + ": truncated KTX2: " + std::to_string(bytes.size()) +
                        " bytes, fewer than its 80-byte header");
    }
    return Ktx2Fields{u32(bytes, 12), u32(bytes, 20), u32(bytes, 24), u32(bytes, 28),
                      u32(bytes, 32), u32(bytes, 36), u32(bytes, 40), u32(bytes, 44),
                      u32(bytes, 48), u32(bytes, 52)};
}

// The DFD's colour model (its first descriptor block's byte 8, after the DFD's total size), or
// 0 when the DFD is too short or outside the file.
std::uint8_t colour_model(std::span<const std::byte> bytes, const Ktx2Fields& f) {
    if (f.dfd_length < 16 || std::uint64_t(f.dfd_offset) + f.dfd_length > bytes.size()) {
        return 0;
    }
    return std::uint8_t(bytes[std::size_t(f.dfd_offset) + 12]);
}

}  // namespace

bool is_ktx2(std::span<const std::byte> bytes) {
    return bytes.size() >= ktx2_identifier.size() &&
           std::memcmp(bytes.data(), ktx2_identifier.data(), ktx2_identifier.size()) == 0;
}

ImageHeader ktx2_header(std::span<const std::byte> bytes, std::uint64_t max_pixels,
                        const std::string& what) {
    const Ktx2Fields f = fields_of(bytes, what);
    check_pixel_count(f.width, f.height, max_pixels, what);
    if (f.depth != 0 || f.layers != 0 || f.faces != 1) {
        throw Error(ErrorKind::Unsupported,
                    what +
                        ": a KTX2 texture of glTF is one 2D image (KHR_texture_basisu), this "
                        "one has pixelDepth " +
                        std::to_string(f.depth) + ", layerCount " + std::to_string(f.layers) +
                        " and faceCount " + std::to_string(f.faces));
    }
    // levelCount: at most log2(max(width, height)) + 1 levels; 0 means one, to be generated.
    const std::uint32_t max_levels = std::uint32_t(std::bit_width(std::max(f.width, f.height)));
    if (f.levels > max_levels) {
        throw Error(ErrorKind::InvalidInput, what + ": the KTX2 header claims " +
                                                 std::to_string(f.levels) + " mip levels, a " +
                                                 std::to_string(f.width) + "x" +
                                                 std::to_string(f.height) + " image has at most " +
                                                 std::to_string(max_levels));
    }
    const std::uint32_t levels = std::max<std::uint32_t>(f.levels, 1);
    if (bytes.size() < header_bytes + levels * level_index_entry_bytes) {
        throw Error(ErrorKind::InvalidInput, what + ": truncated KTX2: its level index of " +
                                                 std::to_string(levels) +
                                                 " levels runs past the end of the file");
    }
    for (std::uint32_t level = 0; level < levels; ++level) {
        const std::size_t at = header_bytes + level * level_index_entry_bytes;
        const std::uint64_t offset = u64(bytes, at);
        const std::uint64_t length = u64(bytes, at + 8);
        if (offset > bytes.size() || length > bytes.size() - offset) {
            throw Error(ErrorKind::InvalidInput,
                        what + ": truncated KTX2: level " + std::to_string(level) + " (" +
                            std::to_string(length) + " bytes at " + std::to_string(offset) +
                            ") runs past the end of the file's " + std::to_string(bytes.size()) +
                            " bytes");
        }
    }
    return ImageHeader{ImageFormat::Ktx2, int(f.width), int(f.height)};
}

void refuse_ktx2_decoding(std::span<const std::byte> bytes, const std::string& what) {
    const Ktx2Fields f = fields_of(bytes, what);
    std::string payload;
    if (f.vk_format != 0) {
        payload = "vkFormat " + std::to_string(f.vk_format) +
                  ", not Basis Universal (KHR_texture_basisu requires VK_FORMAT_UNDEFINED)";
    } else if (f.scheme == scheme_basislz || colour_model(bytes, f) == model_etc1s) {
        payload = "Basis Universal ETC1S";
    } else if (colour_model(bytes, f) == model_uastc) {
        payload = f.scheme == scheme_zstandard ? "Basis Universal UASTC, Zstandard-supercompressed"
                  : f.scheme == scheme_none
                      ? "Basis Universal UASTC"
                      : "Basis Universal UASTC, supercompression " + std::to_string(f.scheme);
    } else {
        payload = "an unknown payload";
    }
    throw Error(ErrorKind::Unsupported,
                what + ": KTX2 textures (KHR_texture_basisu; this one " + payload +
                    ") are not supported: there is no Basis Universal transcoder in this build; "
                    "give the texture a PNG or JPEG fallback source");
}

}  // namespace oer::mesh_detail
