#include "zip_archive.hpp"

#include <array>

#include "oer/core/error.hpp"

namespace oer::server {

namespace {

constexpr std::uint64_t kZip32Limit = 0xffffffffull;
constexpr std::uint32_t kMaxEntries = 0xffff;
// MS-DOS date of 1980-01-01, the format's earliest: an archive of the same frames is then the
// same bytes whenever it is made.
constexpr std::uint16_t kDosDate = (0 << 9) | (1 << 5) | 1;

void put16(std::string& out, std::uint32_t value) {
    out.push_back(char(value & 0xff));
    out.push_back(char((value >> 8) & 0xff));
}

void put32(std::string& out, std::uint32_t value) {
    put16(out, value & 0xffff);
    put16(out, value >> 16);
}

constexpr std::array<std::uint32_t, 256> crc_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t i = 0; i < 256; ++i) {
        std::uint32_t c = i;
        for (int bit = 0; bit < 8; ++bit) {
            c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        }
        table[i] = c;
    }
    return table;
}

// The fields a local header and a central directory record share, from "version needed" on.
void common_fields(std::string& out, std::uint32_t crc, std::uint32_t size, std::size_t name) {
    put16(out, 10);  // version needed: 1.0, stored entries
    put16(out, 0);   // flags
    put16(out, 0);   // method: stored
    put16(out, 0);   // time
    put16(out, kDosDate);
    put32(out, crc);
    put32(out, size);  // compressed
    put32(out, size);  // uncompressed
    put16(out, std::uint32_t(name));
    put16(out, 0);  // extra field
}

}  // namespace

std::uint32_t crc32(std::string_view bytes) {
    static constexpr std::array<std::uint32_t, 256> kTable = crc_table();
    std::uint32_t c = 0xffffffffu;
    for (const char byte : bytes) {
        c = kTable[(c ^ std::uint8_t(byte)) & 0xff] ^ (c >> 8);
    }
    return c ^ 0xffffffffu;
}

std::string ZipWriter::entry(std::string_view name, std::string_view bytes) {
    const std::uint64_t size = 30 + name.size() + bytes.size();
    if (count_ >= kMaxEntries ||
        offset_ + size + central_.size() + 46 + name.size() + 22 > kZip32Limit) {
        throw Error(ErrorKind::LimitExceeded, "the archive is over ZIP32's 4 GiB or 65535 entries");
    }
    const std::uint32_t crc = crc32(bytes);
    std::string local;
    local.reserve(std::size_t(size));
    put32(local, 0x04034b50);
    common_fields(local, crc, std::uint32_t(bytes.size()), name.size());
    local.append(name);
    local.append(bytes);

    put32(central_, 0x02014b50);
    put16(central_, 0x031e);  // made by: UNIX, 3.0
    common_fields(central_, crc, std::uint32_t(bytes.size()), name.size());
    put16(central_, 0);               // comment
    put16(central_, 0);               // disk
    put16(central_, 0);               // internal attributes
    put32(central_, 0100644u << 16);  // external: a regular file, rw-r--r--
    put32(central_, std::uint32_t(offset_));
    central_.append(name);

    offset_ += size;
    ++count_;
    return local;
}

std::string ZipWriter::finish() const {
    std::string end = central_;
    put32(end, 0x06054b50);
    put16(end, 0);  // this disk
    put16(end, 0);  // the directory's disk
    put16(end, count_);
    put16(end, count_);
    put32(end, std::uint32_t(central_.size()));
    put32(end, std::uint32_t(offset_));
    put16(end, 0);  // comment
    return end;
}

}  // namespace oer::server
