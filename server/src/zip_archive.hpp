#pragma once
// A ZIP archive written entry by entry, so that a job's frames are streamed one at a time
// instead of held together (GET /v1/jobs/{id}/zip). Entries are stored, not deflated: the
// frames are PNG, JPEG or EXR, compressed already, so deflate would spend CPU for a few
// percent; and the format's stored method with its CRC-32 is a hundred lines, where libzip
// (Debian's libzip-dev) would be one more library to build against and ship for it, and wants
// a seekable file or the whole archive in memory. PKWARE's APPNOTE 6.3: local header and data
// per entry, then the central directory and its end record; ZIP32 (under 4 GiB and 65535
// entries: a job is bounded far below both), names in ASCII.
#include <cstdint>
#include <string>
#include <string_view>

namespace oer::server {

// CRC-32 of ISO-HDLC (ZIP's and PNG's), polynomial 0xEDB88320 reflected.
std::uint32_t crc32(std::string_view bytes);

class ZipWriter {
  public:
    // The local header and bytes of one more entry: the archive's next bytes. Throws
    // oer::Error (LimitExceeded) past ZIP32's 4 GiB or 65535 entries.
    std::string entry(std::string_view name, std::string_view bytes);
    // The central directory and its end record: the archive's last bytes.
    std::string finish() const;

  private:
    std::string central_;
    std::uint64_t offset_ = 0;
    std::uint32_t count_ = 0;
};

}  // namespace oer::server
