#pragma once
// Private to image_io.cpp: what a map's own header claims, read from its bytes before any reader
// sees them, and the fewest bytes that any file making that claim can have (each format's
// derivation is in image_claims.cpp, with the specification it follows). The loader checks the
// claimed size against the limits, then against the bytes, before OpenImageIO opens the file:
// libjpeg allocates a progressive JPEG's coefficients for the whole image when decoding starts,
// which OpenImageIO's JPEG reader does when it opens.
#include <OpenImageIO/filesystem.h>

#include <cstdint>
#include <string>
#include <variant>

namespace oer::image_io_detail {

struct HeaderClaim {
    int width = 0;   // pixels in a row, as the reader decodes them
    int height = 0;  // rows
    // The bytes that hold the encoded pixels (the whole file, or a PNG's IDAT data, or a JPEG's
    // scans), and the fewest of them any file making this claim has; needed is 0 when no lower
    // bound is known (arithmetic-coded JPEG).
    std::uint64_t available = 0;
    std::uint64_t needed = 0;
    std::string minimum;  // how `needed` is made up: "RLE needs at least 4292612 bytes (...)"
    // A buffer of the whole image that the format's reader allocates (a progressive JPEG's
    // coefficients); 0 when it decodes a few rows at a time.
    std::uint64_t reader_bytes = 0;
};

// Why the bytes are not a header of the format: the reader is not tried on them.
struct NotThisFormat {
    std::string reason;
};

// For OpenImageIO's readers "hdr", "openexr", "png" and "jpeg": the claim, or why the bytes are
// not a header of that format. Other formats: std::monostate (no claim is read; their size is
// checked on OpenImageIO's header alone).
using ClaimResult = std::variant<std::monostate, HeaderClaim, NotThisFormat>;
ClaimResult read_claim(const std::string& format, OIIO::Filesystem::IOProxy& proxy);

}  // namespace oer::image_io_detail
