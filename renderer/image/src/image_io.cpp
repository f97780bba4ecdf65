// Loading environment maps through OpenImageIO (see oer/image_io.hpp), and repairing them.
#include "oer/image/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>

#include "image_claims.hpp"
#include "image_io_errors.hpp"
#include "oer/core/enum_names.hpp"
#include "oer/core/error.hpp"
#include "oer/core/size_text.hpp"

namespace oer {

namespace {

using image_io_detail::ClaimResult;
using image_io_detail::fail;
using image_io_detail::HeaderClaim;
using image_io_detail::NotThisFormat;
using image_io_detail::one_line;

// ---------------------------------------------------------------------------------------------
// Color: integer-coded pixels are taken as sRGB-encoded (8-bit photographs, a user's JPEG
// probe) and decoded to linear, unless the file says it is linear.

float srgb_to_linear(float c) {
    if (!(c > 0.0f)) {
        return c;  // 0, negative (signed integer formats) and NaN pass through to the repair
    }
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

template <typename T>
const std::vector<float>& srgb_table() {
    static const std::vector<float> table = [] {
        constexpr auto max = std::numeric_limits<T>::max();
        std::vector<float> t(std::size_t(max) + 1);
        for (std::size_t i = 0; i < t.size(); ++i) {
            t[i] = srgb_to_linear(float(double(i) / double(max)));
        }
        return t;
    }();
    return table;
}

bool is_float_format(OIIO::TypeDesc format) {
    return format.basetype == OIIO::TypeDesc::HALF || format.basetype == OIIO::TypeDesc::FLOAT ||
           format.basetype == OIIO::TypeDesc::DOUBLE;
}

bool declared_linear(const OIIO::ImageSpec& spec) {
    const std::string space = spec.get_string_attribute("oiio:ColorSpace");
    return OIIO::Strutil::iequals(space, "linear") || OIIO::Strutil::iequals(space, "scene_linear");
}

// ---------------------------------------------------------------------------------------------
// Validation of the header, before any pixel memory is allocated.

// A claimed size against the limits (the file's own header, then OpenImageIO's).
void check_size(int width, int height, const std::string& name, const ImageLimits& limits) {
    if (width <= 0 || height <= 0) {
        fail(ErrorKind::InvalidInput, name, "invalid image size " + size_text(width, height));
    }
    const std::string size = size_text(width, height);
    if (width > limits.max_dimension || height > limits.max_dimension) {
        fail(ErrorKind::LimitExceeded, name,
             "image is " + size + ", a side over the limit of " +
                 std::to_string(limits.max_dimension) + " pixels");
    }
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    if (pixels > limits.max_pixels) {
        fail(ErrorKind::LimitExceeded, name,
             "image is " + size + " = " + std::to_string(pixels) + " pixels, over the limit of " +
                 std::to_string(limits.max_pixels));
    }
}

// A format's own header, read before its reader sees the bytes: its size against the limits,
// then against the bytes.
void check_claim(const HeaderClaim& claim, std::uint64_t file_bytes, const std::string& name,
                 const ImageLimits& limits) {
    check_size(claim.width, claim.height, name, limits);
    if (claim.available < claim.needed) {
        fail(ErrorKind::InvalidInput, name,
             "claims " + size_text(claim.width, claim.height) + " pixels but " +
                 std::to_string(file_bytes) + " bytes cannot hold them (" + claim.minimum + ")");
    }
}

void check_header(const OIIO::ImageSpec& spec, const std::string& name, const ImageLimits& limits) {
    if (spec.deep) {
        fail(ErrorKind::Unsupported, name, "deep images are not supported");
    }
    if (spec.depth > 1) {
        fail(ErrorKind::Unsupported, name,
             "volume images (depth " + std::to_string(spec.depth) + ") are not supported");
    }
    check_size(spec.width, spec.height, name, limits);
    if (spec.nchannels < 1) {
        fail(ErrorKind::InvalidInput, name, "image has no channels");
    }
}

// ---------------------------------------------------------------------------------------------
// Reading the pixels of an opened input: subimage 0, MIP level 0, as linear RGB float.

// The reader's error, or a generic one when it set none.
std::string reader_error(OIIO::ImageInput& in) {
    std::string message = one_line(in.geterror());
    return message.empty() ? std::string("unknown read error") : message;
}

template <typename T>
void read_srgb_integers(OIIO::ImageInput& in, int channels_used, OIIO::TypeDesc type,
                        HdrImage& image, const std::string& name) {
    const std::size_t pixels = image.pixel_count();
    std::vector<T> raw(pixels * std::size_t(channels_used));
    if (!in.read_image(0, 0, 0, channels_used, type, raw.data())) {
        fail(ErrorKind::InvalidInput, name, "cannot read pixels: " + reader_error(in));
    }
    const std::vector<float>& table = srgb_table<T>();
    for (std::size_t i = 0; i < pixels; ++i) {
        for (int c = 0; c < 3; ++c) {
            const int source = channels_used == 1 ? 0 : c;
            image.pixels[i * 3 + c] = table[raw[i * std::size_t(channels_used) + source]];
        }
    }
}

// Grey (1 channel) and grey + alpha (2) read their first channel; RGB, RGBA and more read the
// first three (OpenImageIO orders R, G, B, A first where the file names them).
int channels_read(const OIIO::ImageSpec& spec) {
    return spec.nchannels >= 3 ? 3 : 1;
}

// Integer pixels taken as sRGB and read as 8 or 16 bits first: their size, or 0 when the pixels
// are read straight into the float image.
std::size_t integer_bytes(const OIIO::ImageSpec& spec) {
    if (is_float_format(spec.format) || declared_linear(spec)) {
        return 0;
    }
    return spec.format.basetype == OIIO::TypeDesc::UINT8    ? 1
           : spec.format.basetype == OIIO::TypeDesc::UINT16 ? 2
                                                            : 0;
}

// See ImageHeader::decode_bytes. OpenImageIO 2.4's ImageInput::read_image (imageinput.cpp)
// converts a scanline image in chunks of max(2^26 / scanline bytes, the "read_chunk" attribute)
// lines, rounded up to a multiple of 64 (or of TIFF's rows per strip), into a buffer of the
// channels read, through a second one of every channel when only some are read (except for
// OpenEXR's reader, which reads a channel range itself); a tiled image a row of tiles at a time.
std::uint64_t decode_bytes(const OIIO::ImageSpec& spec, const std::string& format,
                           std::uint64_t reader_bytes) {
    const std::uint64_t width = std::uint64_t(spec.width);
    const std::uint64_t pixels = width * std::uint64_t(spec.height);
    const int channels = channels_read(spec);
    std::uint64_t bytes = pixels * 3 * sizeof(float) + pixels * channels * integer_bytes(spec);
    const std::uint64_t all_channels = spec.pixel_bytes(true);
    if (spec.tile_width > 0) {
        const std::uint64_t tile_columns =
            (width + std::uint64_t(spec.tile_width) - 1) / std::uint64_t(spec.tile_width);
        bytes += tile_columns * std::uint64_t(spec.tile_width) *
                 std::uint64_t(std::max(1, spec.tile_height)) * all_channels;
    } else {
        const int rows_per_strip = std::max(1, spec.get_int_attribute("tiff:RowsPerStrip", 64));
        std::uint64_t chunk = std::max<std::uint64_t>(
            1, (std::uint64_t(1) << 26) / std::max<std::uint64_t>(1, width * all_channels));
        chunk =
            std::max<std::uint64_t>(chunk, std::uint64_t(OIIO::get_int_attribute("read_chunk")));
        chunk = (chunk + rows_per_strip - 1) / rows_per_strip * rows_per_strip;
        const std::uint64_t lines = std::min<std::uint64_t>(chunk, std::uint64_t(spec.height));
        bytes += lines * width * spec.pixel_bytes(0, channels, true);
        if (channels < spec.nchannels && format != "openexr") {
            bytes += lines * width * all_channels;
        }
    }
    if (format == "png") {
        bytes += spec.image_bytes(true);  // pnginput.cpp: readimg decodes the whole image first
    }
    return bytes + reader_bytes;
}

// The pixels of an input opened and checked by open_checked.
LoadedImage read_pixels(OIIO::ImageInput& in, const std::string& name) {
    const OIIO::ImageSpec spec = in.spec(0, 0);
    const int channels_used = channels_read(spec);
    LoadedImage result;
    result.image = HdrImage(spec.width, spec.height);
    HdrImage& image = result.image;

    const OIIO::TypeDesc format = spec.format;
    const bool srgb = !is_float_format(format) && !declared_linear(spec);
    if (integer_bytes(spec) == 1) {
        read_srgb_integers<std::uint8_t>(in, channels_used, OIIO::TypeDesc::UINT8, image, name);
    } else if (integer_bytes(spec) == 2) {
        read_srgb_integers<std::uint16_t>(in, channels_used, OIIO::TypeDesc::UINT16, image, name);
    } else {
        // Straight into the interleaved RGB buffer: 3 channels, or 1 channel strided by 3
        // floats and then replicated.
        const OIIO::stride_t xstride = OIIO::stride_t(3 * sizeof(float));
        if (!in.read_image(0, 0, 0, channels_used, OIIO::TypeFloat, image.pixels.data(), xstride)) {
            fail(ErrorKind::InvalidInput, name, "cannot read pixels: " + reader_error(in));
        }
        if (channels_used == 1) {
            for (std::size_t i = 0; i < image.pixel_count(); ++i) {
                image.pixels[i * 3 + 1] = image.pixels[i * 3 + 2] = image.pixels[i * 3];
            }
        }
        if (srgb) {  // other integer types (32-bit, signed): rare, decode per value
            for (float& value : image.pixels) {
                value = srgb_to_linear(value);
            }
        }
    }
    // Some readers record a problem and still return true: a set error means a bad file.
    if (in.has_error()) {
        fail(ErrorKind::InvalidInput, name, "error while reading pixels: " + reader_error(in));
    }
    result.repaired = repair_radiance(image);
    result.range = is_float_format(format) ? DynamicRange::High : DynamicRange::Low;
    return result;
}

// Runs OpenImageIO calls, turning any exception escaping them into an oer::Error.
template <typename F>
auto guarded(const std::string& name, F&& body) {
    try {
        return body();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        fail(ErrorKind::LimitExceeded, name, "out of memory while reading the image");
    } catch (const std::exception& e) {
        fail(ErrorKind::InvalidInput, name, std::string("cannot read image: ") + e.what());
    }
}

// ---------------------------------------------------------------------------------------------
// Choosing a reader. Files and memory alike are read through an IOProxy, so that both take
// the same path; a reader that cannot use one would open the given name on disk, so it is only
// ever used for real files (load_through_proxy, step 4).

// The input format named by a format name ("openexr") or one of its extensions ("exr",
// case-insensitive); empty if OpenImageIO has no reader for it. Only known names ever reach
// ImageInput::create, which would otherwise look for a file of that name on disk.
std::string input_format_for(std::string name) {
    OIIO::Strutil::to_lower(name);
    if (name.empty()) {
        return {};
    }
    const std::vector<std::string> inputs =
        OIIO::Strutil::splits(OIIO::get_string_attribute("input_format_list"), ",");
    // "format:ext,ext;format:ext,..."
    for (const std::string& entry :
         OIIO::Strutil::splits(OIIO::get_string_attribute("extension_list"), ";")) {
        const std::size_t colon = entry.find(':');
        const std::string format = entry.substr(0, colon);
        if (format == "null" || std::find(inputs.begin(), inputs.end(), format) == inputs.end()) {
            continue;  // output only, or "null" (an empty image from nothing): never used
        }
        if (name == format) {
            return format;
        }
        if (colon != std::string::npos) {
            for (const std::string& extension :
                 OIIO::Strutil::splits(entry.substr(colon + 1), ",")) {
                if (name == extension) {
                    return format;
                }
            }
        }
    }
    return {};
}

// A reader that can use an IOProxy, for a format or extension name; nullptr otherwise.
std::unique_ptr<OIIO::ImageInput> proxy_reader(const std::string& name) {
    const std::string format = input_format_for(name);
    if (format.empty()) {
        return nullptr;
    }
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(format);
    if (!in || !in->supports("ioproxy")) {
        OIIO::geterror();  // drop any global error left behind
        return nullptr;
    }
    return in;
}

// Open hints for every reader: keep color as stored next to an alpha channel (PNG, TIFF
// would otherwise multiply it by alpha on read; alpha is ignored, not composited).
const OIIO::ImageSpec& open_config() {
    static const OIIO::ImageSpec config = [] {
        OIIO::ImageSpec spec;
        spec.attribute("oiio:UnassociatedAlpha", 1);
        return spec;
    }();
    return config;
}

struct OpenAttempt {
    std::unique_ptr<OIIO::ImageInput> input;
    std::string error;
    std::optional<HeaderClaim> claim;  // what the format's own header said, when it was read
};

// An input and what a load would allocate, every check before reading pixels passed.
struct Opened {
    std::unique_ptr<OIIO::ImageInput> input;
    ImageHeader header;
};

// Opens proxy with `in`. The format's own header is read first (image_claims.hpp) and checked
// against the limits and the bytes, so that no reader allocates for a claim the bytes cannot
// hold; bytes that are not a header of that format are not given to its reader.
OpenAttempt try_open(std::unique_ptr<OIIO::ImageInput> in, OIIO::Filesystem::IOProxy& proxy,
                     const std::string& name, const ImageLimits& limits) {
    OpenAttempt attempt;
    const ClaimResult claim = image_io_detail::read_claim(in->format_name(), proxy);
    if (const auto* refused = std::get_if<NotThisFormat>(&claim)) {
        attempt.error = refused->reason;
        return attempt;
    }
    if (const auto* claimed = std::get_if<HeaderClaim>(&claim)) {
        check_claim(*claimed, proxy.size(), name, limits);
        attempt.claim = *claimed;
    }
    proxy.seek(0);
    OIIO::ImageSpec spec;
    if (in->set_ioproxy(&proxy) && in->open(name, spec, open_config())) {
        attempt.input = std::move(in);
    } else {
        attempt.error = one_line(in->geterror());
    }
    return attempt;
}

// The header of an opened input checked, and what reading it will allocate.
Opened checked(std::unique_ptr<OIIO::ImageInput> in, const std::optional<HeaderClaim>& claim,
               const std::string& name, const ImageLimits& limits) {
    const OIIO::ImageSpec& spec = in->spec(0, 0);
    check_header(spec, name, limits);
    if (claim && (claim->width != spec.width || claim->height != spec.height)) {
        fail(ErrorKind::InvalidInput, name,
             "its header says " + size_text(claim->width, claim->height) + " pixels, " +
                 in->format_name() + "'s reader " + size_text(spec.width, spec.height));
    }
    Opened opened;
    opened.header.format = in->format_name();
    opened.header.width = spec.width;
    opened.header.height = spec.height;
    opened.header.channels = spec.nchannels;
    opened.header.decode_bytes =
        decode_bytes(spec, opened.header.format, claim ? claim->reader_bytes : 0);
    opened.input = std::move(in);
    return opened;
}

// Opens an image whose bytes come through proxy, head holding its first bytes, and checks its
// header. Readers are tried in this order:
//  1. the format the bytes announce (their signature): if that fails, its reason is the
//     precise one (a truncated or corrupt file of that format) and no other reader is tried;
//  2. the format the name's extension suggests (for formats without a signature, .tga);
//  3. every other reader that checks a signature and reads through an IOProxy;
//  4. for a file on disk (path != nullptr), the readers that cannot use an IOProxy
//     (cineon, dicom, fits, heif, raw, sgi, ...), which open the path themselves.
Opened open_checked(OIIO::Filesystem::IOProxy& proxy, std::span<const std::byte> head,
                    const std::string& name, const std::string* path, const ImageLimits& limits) {
    std::vector<std::string> tried;
    auto attempt = [&](const std::string& format) -> OpenAttempt {
        std::unique_ptr<OIIO::ImageInput> in = proxy_reader(format);
        if (!in || std::find(tried.begin(), tried.end(), in->format_name()) != tried.end()) {
            return {};
        }
        tried.emplace_back(in->format_name());
        return try_open(std::move(in), proxy, name, limits);
    };

    if (const std::string magic = image_format_of(head); !magic.empty()) {
        OpenAttempt opened = attempt(magic);
        if (opened.input) {
            return checked(std::move(opened.input), opened.claim, name, limits);
        }
        if (!tried.empty()) {
            fail(ErrorKind::InvalidInput, name,
                 "not a readable " + tried.back() + " image (" + opened.error + ")");
        }
    }
    std::string extension_error;
    const std::string extension = std::filesystem::path(name).extension().string();
    if (extension.size() > 1) {
        OpenAttempt opened = attempt(extension.substr(1));
        if (opened.input) {
            return checked(std::move(opened.input), opened.claim, name, limits);
        }
        if (!opened.error.empty()) {
            extension_error = "; as " + tried.back() + ": " + opened.error;
        }
    }
    const std::vector<std::string> formats =
        OIIO::Strutil::splits(OIIO::get_string_attribute("input_format_list"), ",");
    for (const std::string& format : formats) {
        if (format == "targa") {
            continue;  // has no signature: only by extension
        }
        if (OpenAttempt opened = attempt(format); opened.input) {
            return checked(std::move(opened.input), opened.claim, name, limits);
        }
    }
    if (path != nullptr) {
        for (const std::string& format : formats) {
            if (format == "null" || format == "ffmpeg") {
                continue;  // an empty image from nothing / video: never by guessing
            }
            std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(format);
            if (!in || in->supports("ioproxy")) {
                OIIO::geterror();
                continue;
            }
            OIIO::ImageSpec spec;
            if (in->open(*path, spec, open_config())) {
                return checked(std::move(in), std::nullopt, name, limits);
            }
        }
    }
    fail(ErrorKind::InvalidInput, name,
         "not an image in any format OpenImageIO can read (" + std::to_string(proxy.size()) +
             " bytes" + extension_error + ")");
}

}  // namespace

// -------------------------------------------------------------------------------------------------

RepairCounts repair_radiance(HdrImage& image) {
    RepairCounts counts;
    constexpr float largest = std::numeric_limits<float>::max();
    for (float& value : image.pixels) {
        if (value >= 0.0f && value <= largest) {
            continue;  // the common case: finite and non-negative (NaN fails both tests)
        }
        if (std::isnan(value)) {
            ++counts.nan;
            value = 0.0f;
        } else if (value > 0.0f) {
            ++counts.inf;
            value = largest;
        } else {
            ++counts.negative;  // includes -Inf
            value = 0.0f;
        }
    }
    return counts;
}

LoadedImage load_image_file(const std::string& path, const ImageLimits& limits) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        fail(ErrorKind::Io, path, "no such file");
    }
    if (!std::filesystem::is_regular_file(status)) {
        fail(ErrorKind::Io, path, "not a regular file");
    }
    return guarded(path, [&] {
        OIIO::geterror();  // start from a clean global error
        OIIO::Filesystem::IOFile proxy(path, OIIO::Filesystem::IOProxy::Read);
        if (!proxy.opened()) {
            fail(ErrorKind::Io, path, "cannot open the file for reading");
        }
        if (proxy.size() == 0) {
            fail(ErrorKind::InvalidInput, path, "empty file");
        }
        std::array<std::byte, 16> head{};
        const std::size_t got = proxy.pread(head.data(), head.size(), 0);
        Opened opened = open_checked(proxy, std::span(head.data(), got), path, &path, limits);
        return read_pixels(*opened.input, path);
    });
}

namespace {
constexpr EnumNames<DynamicRange, 2> kRangeNames = {
    {{DynamicRange::High, "hdr"}, {DynamicRange::Low, "ldr"}}};
}  // namespace

std::string to_string(DynamicRange range) {
    return name_of(range, kRangeNames);
}

DynamicRange dynamic_range_from_string(const std::string& name) {
    return value_named(name, kRangeNames, "dynamic range");
}

std::string image_format_of(std::span<const std::byte> bytes) {
    auto starts_with = [&](std::initializer_list<int> magic) {
        if (bytes.size() < magic.size()) {
            return false;
        }
        std::size_t i = 0;
        for (int b : magic) {
            if (std::to_integer<int>(bytes[i++]) != b) {
                return false;
            }
        }
        return true;
    };
    if (starts_with({'#', '?'})) {
        return "hdr";
    }
    if (starts_with({0x76, 0x2f, 0x31, 0x01})) {
        return "openexr";
    }
    if (starts_with({0x89, 'P', 'N', 'G'})) {
        return "png";
    }
    if (starts_with({0xff, 0xd8, 0xff})) {
        return "jpeg";
    }
    if (starts_with({'I', 'I', 0x2a, 0x00}) || starts_with({'M', 'M', 0x00, 0x2a})) {
        return "tiff";
    }
    return {};
}

namespace {

// What reads the bytes with every check passed: the pixels (load) or the header alone (probe).
template <typename Then>
auto through_memory(std::span<const std::byte> bytes, const std::string& name,
                    const ImageLimits& limits, Then then) {
    if (bytes.empty()) {
        fail(ErrorKind::InvalidInput, name, "empty input");
    }
    return guarded(name, [&] {
        OIIO::geterror();  // start from a clean global error
        OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
        Opened opened = open_checked(proxy, bytes, name, nullptr, limits);
        return then(opened);
    });
}

}  // namespace

ImageHeader probe_image_memory(std::span<const std::byte> bytes, const std::string& name,
                               const ImageLimits& limits) {
    return through_memory(bytes, name, limits, [](const Opened& opened) { return opened.header; });
}

LoadedImage load_image_memory(std::span<const std::byte> bytes, const std::string& name,
                              const ImageLimits& limits) {
    return through_memory(bytes, name, limits,
                          [&name](Opened& opened) { return read_pixels(*opened.input, name); });
}

}  // namespace oer
