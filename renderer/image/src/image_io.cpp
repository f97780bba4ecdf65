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
#include <string_view>
#include <system_error>
#include <vector>

#include "image_io_errors.hpp"
#include "oer/core/enum_names.hpp"
#include "oer/core/error.hpp"

namespace oer {

namespace {

using image_io_detail::fail;
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

void check_header(const OIIO::ImageSpec& spec, const std::string& name, const ImageLimits& limits) {
    if (spec.deep) {
        fail(ErrorKind::Unsupported, name, "deep images are not supported");
    }
    if (spec.depth > 1) {
        fail(ErrorKind::Unsupported, name,
             "volume images (depth " + std::to_string(spec.depth) + ") are not supported");
    }
    if (spec.width <= 0 || spec.height <= 0) {
        fail(
            ErrorKind::InvalidInput, name,
            "invalid image size " + std::to_string(spec.width) + "x" + std::to_string(spec.height));
    }
    if (spec.nchannels < 1) {
        fail(ErrorKind::InvalidInput, name, "image has no channels");
    }
    const std::string size = std::to_string(spec.width) + "x" + std::to_string(spec.height);
    if (spec.width > limits.max_dimension || spec.height > limits.max_dimension) {
        fail(ErrorKind::LimitExceeded, name,
             "image is " + size + ", a side over the limit of " +
                 std::to_string(limits.max_dimension) + " pixels");
    }
    const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
    if (pixels > limits.max_pixels) {
        fail(ErrorKind::LimitExceeded, name,
             "image is " + size + " = " + std::to_string(pixels) + " pixels, over the limit of " +
                 std::to_string(limits.max_pixels));
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

LoadedImage read_opened(OIIO::ImageInput& in, const std::string& name, const ImageLimits& limits) {
    const OIIO::ImageSpec spec = in.spec(0, 0);
    check_header(spec, name, limits);

    // Grey (1 channel) and grey + alpha (2) read their first channel; RGB, RGBA and more read
    // the first three (OpenImageIO orders R, G, B, A first where the file names them).
    const int channels_used = spec.nchannels >= 3 ? 3 : 1;
    LoadedImage result;
    result.image = HdrImage(spec.width, spec.height);
    HdrImage& image = result.image;

    const OIIO::TypeDesc format = spec.format;
    const bool srgb = !is_float_format(format) && !declared_linear(spec);
    if (srgb && format.basetype == OIIO::TypeDesc::UINT8) {
        read_srgb_integers<std::uint8_t>(in, channels_used, OIIO::TypeDesc::UINT8, image, name);
    } else if (srgb && format.basetype == OIIO::TypeDesc::UINT16) {
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
};

OpenAttempt try_open(std::unique_ptr<OIIO::ImageInput> in, OIIO::Filesystem::IOProxy& proxy,
                     const std::string& name) {
    proxy.seek(0);
    OIIO::ImageSpec spec;
    if (in->set_ioproxy(&proxy) && in->open(name, spec, open_config())) {
        return {std::move(in), {}};
    }
    return {nullptr, one_line(in->geterror())};
}

// Opens and reads an image whose bytes come through proxy; head holds its first bytes.
// Readers are tried in this order:
//  1. the format the bytes announce (their signature): if that fails, its reason is the
//     precise one (a truncated or corrupt file of that format) and no other reader is tried;
//  2. the format the name's extension suggests (for formats without a signature, .tga);
//  3. every other reader that checks a signature and reads through an IOProxy;
//  4. for a file on disk (path != nullptr), the readers that cannot use an IOProxy
//     (cineon, dicom, fits, heif, raw, sgi, ...), which open the path themselves.
LoadedImage load_through_proxy(OIIO::Filesystem::IOProxy& proxy, std::span<const std::byte> head,
                               const std::string& name, const std::string* path,
                               const ImageLimits& limits) {
    std::vector<std::string> tried;
    auto attempt = [&](const std::string& format) -> OpenAttempt {
        std::unique_ptr<OIIO::ImageInput> in = proxy_reader(format);
        if (!in || std::find(tried.begin(), tried.end(), in->format_name()) != tried.end()) {
            return {};
        }
        tried.emplace_back(in->format_name());
        return try_open(std::move(in), proxy, name);
    };

    if (const std::string magic = image_format_of(head); !magic.empty()) {
        OpenAttempt opened = attempt(magic);
        if (opened.input) {
            return read_opened(*opened.input, name, limits);
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
            return read_opened(*opened.input, name, limits);
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
            return read_opened(*opened.input, name, limits);
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
                return read_opened(*in, name, limits);
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
        return load_through_proxy(proxy, std::span(head.data(), got), path, &path, limits);
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

LoadedImage load_image_memory(std::span<const std::byte> bytes, const std::string& name,
                              const ImageLimits& limits) {
    if (bytes.empty()) {
        fail(ErrorKind::InvalidInput, name, "empty input");
    }
    return guarded(name, [&] {
        OIIO::geterror();  // start from a clean global error
        OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
        return load_through_proxy(proxy, bytes, name, nullptr, limits);
    });
}

}  // namespace oer
