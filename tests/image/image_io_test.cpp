#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "process_memory.hpp"

using namespace oer;
namespace fs = std::filesystem;

namespace {

// A directory of its own under the system's temp dir, removed with everything in it.
class TempDir {
  public:
    TempDir() {
        static int counter = 0;
        const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
        path_ =
            fs::temp_directory_path() / ("oer-image-io-test-" + std::to_string(::getpid()) + "-" +
                                         std::to_string(counter++) + "-" + std::to_string(now));
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path_ / name).string(); }

  private:
    fs::path path_;
};

std::vector<std::byte> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

void write_bytes(const std::string& path, std::span<const std::byte> bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::vector<std::byte> bytes_of(const std::string& text) {
    std::vector<std::byte> bytes(text.size());
    std::memcpy(bytes.data(), text.data(), text.size());
    return bytes;
}

// Deterministic pseudo-random numbers (a 64-bit LCG), so that failures reproduce.
struct Lcg {
    std::uint64_t state;
    std::uint32_t next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return std::uint32_t(state >> 33);
    }
    float uniform() { return float(next()) / float(1u << 31); }  // [0, 1)
};

// A map of smooth-ish HDR noise, over several decades of radiance.
HdrImage noise_image(int w, int h, std::uint64_t seed) {
    HdrImage image(w, h);
    Lcg rng{seed};
    for (float& v : image.pixels) {
        v = std::exp2(rng.uniform() * 16.0f - 8.0f);  // 1/256 .. 256
    }
    return image;
}

// Runs body, expects an oer::Error of the given kind whose message contains needle.
void expect_error(const std::function<void()>& body, ErrorKind kind, const std::string& needle,
                  const std::string& context) {
    try {
        body();
        ADD_FAILURE() << context << ": no error thrown";
    } catch (const Error& e) {
        EXPECT_EQ(int(e.kind()), int(kind)) << context << ": " << e.what();
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
            << context << ": message '" << e.what() << "' does not contain '" << needle << "'";
    } catch (const std::exception& e) {
        ADD_FAILURE() << context << ": not an oer::Error: " << e.what();
    }
}

bool have_oiiotool() {
    static const bool found = std::system("oiiotool --help > /dev/null 2>&1") == 0;
    return found;
}

void run(const std::string& command) {
    ASSERT_EQ(std::system((command + " > /dev/null 2>&1").c_str()), 0) << command;
}

float srgb_decode(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

long max_rss_kb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

// End of an OpenEXR single-part header: magic and version, then attributes
// (name\0 type\0 int32 size, value) up to an empty name.
std::size_t exr_header_end(const std::vector<std::byte>& bytes) {
    std::size_t i = 8;
    auto skip_string = [&] {
        while (bytes.at(i) != std::byte{0}) {
            ++i;
        }
        ++i;
    };
    while (bytes.at(i) != std::byte{0}) {
        skip_string();  // name
        skip_string();  // type
        std::uint32_t size = 0;
        std::memcpy(&size, &bytes.at(i), 4);
        i += 4 + size;
    }
    return i + 1;
}

// End of a Radiance header: the line after the resolution string "-Y H +X W".
std::size_t hdr_header_end(const std::vector<std::byte>& bytes) {
    const std::string text(reinterpret_cast<const char*>(bytes.data()),
                           std::min<std::size_t>(bytes.size(), 4096));
    const std::size_t resolution = text.find("\n-Y ");
    return text.find('\n', resolution + 1) + 1;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Round trips

TEST(ImageIo, ExrRoundTripIsExactInFloat) {
    TempDir dir;
    HdrImage image = noise_image(37, 19, 1);
    image.at(0, 0)[0] = 0.0f;
    image.at(1, 0)[1] = 65504.0f * 4.0f;  // beyond half range: float is kept
    image.at(2, 0)[2] = 1e-7f;
    const std::string path = dir.file("round.exr");
    write_image_file(image, path);
    const LoadedImage loaded = load_image_file(path);
    ASSERT_EQ(loaded.image.width, 37);
    ASSERT_EQ(loaded.image.height, 19);
    EXPECT_EQ(loaded.image.pixels, image.pixels);
    EXPECT_EQ(loaded.repaired.nan + loaded.repaired.inf + loaded.repaired.negative, 0u);

    const LoadedImage from_memory = load_image_memory(read_bytes(path), "round.exr");
    EXPECT_EQ(from_memory.image.pixels, image.pixels);
}

TEST(ImageIo, HdrRoundTripWithinRgbePrecision) {
    TempDir dir;
    const HdrImage image = noise_image(64, 32, 2);
    const std::string path = dir.file("round.hdr");
    write_image_file(image, path);
    for (const LoadedImage& loaded :
         {load_image_file(path), load_image_memory(read_bytes(path), "round.hdr")}) {
        ASSERT_EQ(loaded.image.width, 64);
        ASSERT_EQ(loaded.image.height, 32);
        // RGBE: an 8-bit mantissa per channel and a shared exponent set by the largest channel,
        // so every channel is within 1/128 of the pixel's largest channel (rounding or
        // truncation of the mantissa, whichever the writer uses).
        for (std::size_t i = 0; i < image.pixel_count(); ++i) {
            const glm::vec3 a = image.rgb(i), b = loaded.image.rgb(i);
            const float largest = std::max({a.r, a.g, a.b});
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(b[c], a[c], largest / 128.0f) << "pixel " << i << " channel " << c;
            }
            EXPECT_NEAR(b[0] / a[0], 1.0f, 0.01f + 2.0f * largest / a[0] / 256.0f);
        }
    }
}

TEST(ImageIo, PngIsQuantisedAndDecodedFromSrgb) {
    TempDir dir;
    HdrImage image(256, 1);
    for (int x = 0; x < 256; ++x) {
        image.at(x, 0)[0] = float(x) / 255.0f;
        image.at(x, 0)[1] = 1.0f - float(x) / 255.0f;
        image.at(x, 0)[2] = x % 2 ? 2.0f : -1.0f;  // clamped to 1 and 0
    }
    const std::string path = dir.file("ramp.png");
    write_image_file(image, path);
    const LoadedImage loaded = load_image_file(path);
    for (int x = 0; x < 256; ++x) {
        const float* p = loaded.image.at(x, 0);
        EXPECT_NEAR(p[0], srgb_decode(float(x) / 255.0f), 1e-6f) << x;
        EXPECT_NEAR(p[1], srgb_decode(1.0f - float(x) / 255.0f), 1e-6f) << x;
        EXPECT_NEAR(p[2], x % 2 ? 1.0f : 0.0f, 1e-6f) << x;
    }
}

TEST(ImageIo, JpegIsDecodedFromSrgb) {
    TempDir dir;
    HdrImage image(16, 8);
    std::fill(image.pixels.begin(), image.pixels.end(), 0.5f);
    const std::string path = dir.file("grey.jpg");
    write_image_file(image, path);
    const LoadedImage loaded = load_image_memory(read_bytes(path), "grey.jpg");
    ASSERT_EQ(loaded.image.width, 16);
    for (float v : loaded.image.pixels) {
        EXPECT_NEAR(v, srgb_decode(0.5f), 0.01f);  // 0.214, JPEG's own error is ~1/255
    }
}

TEST(ImageIo, FormatComesFromTheBytesBeforeTheName) {
    TempDir dir;
    const HdrImage image = noise_image(8, 4, 9);
    const std::string exr = dir.file("map.exr");
    write_image_file(image, exr);
    const std::string misnamed = dir.file("map.png");
    fs::rename(exr, misnamed);
    EXPECT_EQ(load_image_file(misnamed).image.pixels, image.pixels);
    EXPECT_EQ(load_image_memory(read_bytes(misnamed), "no-extension").image.pixels, image.pixels);
}

TEST(ImageIo, MapsOfAnyAspectAreAccepted) {
    TempDir dir;
    for (auto [w, h] : {std::pair{1, 1}, {2, 1}, {30, 7}, {5, 40}}) {
        const HdrImage image = noise_image(w, h, 3);
        const std::string path = dir.file("odd.exr");
        write_image_file(image, path);
        const LoadedImage loaded = load_image_file(path);
        EXPECT_EQ(loaded.image.width, w);
        EXPECT_EQ(loaded.image.height, h);
        EXPECT_EQ(loaded.image.pixels, image.pixels);
    }
}

// ---------------------------------------------------------------------------------------------
// Channel layouts and pixel types, made with oiiotool

TEST(ImageIo, GreyRgbaHalfAndMipmappedInputs) {
    if (!have_oiiotool()) {
        GTEST_SKIP() << "*** oiiotool not found (package openimageio-tools): grey, RGBA, half "
                        "and mipmapped inputs are NOT tested ***";
    }
    TempDir dir;
    struct Case {
        std::string file, command;
        glm::vec3 expected;
        float tolerance;
    };
    const std::vector<Case> cases = {
        {"grey.exr", "--pattern constant:color=0.25 8x4 1 -d half", {0.25f, 0.25f, 0.25f}, 0},
        {"grey_alpha.exr",
         "--pattern constant:color=0.75,0.5 8x4 2 -d float",
         {0.75f, 0.75f, 0.75f},
         0},
        {"rgba.exr",
         "--pattern constant:color=0.1,0.2,0.3,0.9 8x4 4 -d float",
         {0.1f, 0.2f, 0.3f},
         0},
        {"half.exr",
         "--pattern constant:color=1.5,2.5,1000 8x4 3 -d half",
         {1.5f, 2.5f, 1000.0f},
         0},
        {"rgba_half.exr", "--pattern constant:color=3,2,1,0 8x4 4 -d half", {3, 2, 1}, 0},
        {"five.exr", "--pattern constant:color=1,2,3,4,5 8x4 5 -d float", {1, 2, 3}, 0},
        // 16-bit PNG: integer, so sRGB-decoded (0.5 quantises to 32768 / 65535).
        {"grey16.png", "--pattern constant:color=0.5 8x4 1 -d uint16",
         glm::vec3(srgb_decode(32768.0f / 65535.0f)), 1e-6f},
        // Color next to alpha is taken as stored (not multiplied by alpha): 255, 0, 128.
        {"rgba8.png",
         "--pattern constant:color=1,0,0.5,0.5 8x4 4 -d uint8 --attrib oiio:UnassociatedAlpha 1",
         {1.0f, 0.0f, srgb_decode(128.0f / 255.0f)},
         1e-6f},
        // No signature: found by its extension.
        {"rgb8.tga",
         "--pattern constant:color=1,0.2,0 8x4 3 -d uint8",
         {1.0f, srgb_decode(51.0f / 255.0f), 0.0f},
         1e-6f},
        {"rgb.tif", "--pattern constant:color=2,0.5,0.125 8x4 3 -d float", {2, 0.5f, 0.125f}, 0},
        {"mip.exr", "--pattern constant:color=4,5,6 8x4 3 -d half -otex", {4, 5, 6}, 0},
    };
    // One oiiotool run writes every file (each start costs a few hundred ms).
    std::string command = "oiiotool";
    for (const Case& c : cases) {
        // "-otex" is an output flag of its own; the others take "-o".
        const bool tex = c.command.ends_with("-otex");
        command += " " + c.command + (tex ? " " : " -o ") + dir.file(c.file);
    }
    run(command);
    for (const Case& c : cases) {
        const std::string path = dir.file(c.file);
        for (const LoadedImage& loaded :
             {load_image_file(path), load_image_memory(read_bytes(path), c.file)}) {
            ASSERT_EQ(loaded.image.width, 8) << c.file;
            ASSERT_EQ(loaded.image.height, 4) << c.file;
            for (std::size_t i = 0; i < loaded.image.pixel_count(); ++i) {
                for (int k = 0; k < 3; ++k) {
                    EXPECT_NEAR(loaded.image.rgb(i)[k], c.expected[k], c.tolerance)
                        << c.file << " pixel " << i << " channel " << k;
                }
            }
        }
    }
}

TEST(ImageIo, MultiPartFileReadsTheFirstSubimage) {
    if (!have_oiiotool()) {
        GTEST_SKIP() << "*** oiiotool not found (package openimageio-tools): multi-part EXR "
                        "is NOT tested ***";
    }
    TempDir dir;
    const std::string path = dir.file("multi.exr");
    run("oiiotool --pattern constant:color=1,2,3 6x3 3 --pattern constant:color=7,8,9 6x3 3 "
        "--siappend -d float -o " +
        path);
    const LoadedImage loaded = load_image_file(path);
    ASSERT_EQ(loaded.image.width, 6);
    ASSERT_EQ(loaded.image.height, 3);
    EXPECT_EQ(loaded.image.rgb(0), glm::vec3(1, 2, 3));
}

// ---------------------------------------------------------------------------------------------
// Repair

TEST(ImageIo, RepairCountsEachComponent) {
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    constexpr float inf = std::numeric_limits<float>::infinity();
    constexpr float big = std::numeric_limits<float>::max();
    HdrImage image(2, 1);
    image.pixels = {nan, inf, -inf, -2.0f, 0.5f, nan};
    const RepairCounts counts = repair_radiance(image);
    EXPECT_EQ(counts.nan, 2u);
    EXPECT_EQ(counts.inf, 1u);
    EXPECT_EQ(counts.negative, 2u);
    EXPECT_EQ(image.pixels, (std::vector<float>{0.0f, big, 0.0f, 0.0f, 0.5f, 0.0f}));

    // Already clean: nothing changes, nothing counted; -0 is not negative radiance.
    HdrImage clean(1, 1);
    clean.pixels = {0.0f, -0.0f, big};
    const RepairCounts none = repair_radiance(clean);
    EXPECT_EQ(none.nan + none.inf + none.negative, 0u);
    EXPECT_EQ(clean.pixels[2], big);
}

TEST(ImageIo, LoadsRepairAndReportNonFinitePixels) {
    TempDir dir;
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    constexpr float inf = std::numeric_limits<float>::infinity();
    constexpr float big = std::numeric_limits<float>::max();
    HdrImage one(1, 1);
    one.pixels = {nan, inf, -3.0f};
    HdrImage two(2, 1);
    two.pixels = {-inf, 1.0f, nan, nan, -0.25f, inf};
    struct Case {
        const HdrImage* image;
        RepairCounts expected;
        std::vector<float> repaired;
    };
    for (const Case& c : {Case{&one, {1, 1, 1}, {0.0f, big, 0.0f}},
                          Case{&two, {2, 1, 2}, {0.0f, 1.0f, 0.0f, 0.0f, 0.0f, big}}}) {
        const std::string path = dir.file("bad.exr");
        write_image_file(*c.image, path);
        for (const LoadedImage& loaded :
             {load_image_file(path), load_image_memory(read_bytes(path), "bad.exr")}) {
            EXPECT_EQ(loaded.repaired.nan, c.expected.nan);
            EXPECT_EQ(loaded.repaired.inf, c.expected.inf);
            EXPECT_EQ(loaded.repaired.negative, c.expected.negative);
            EXPECT_EQ(loaded.image.pixels, c.repaired);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Broken input

TEST(ImageIo, TruncatedFilesAreRejected) {
    TempDir dir;
    const HdrImage image = noise_image(256, 128, 4);
    for (const std::string extension : {".hdr", ".exr"}) {
        const std::string name = "whole" + extension;
        const std::string path = dir.file(name);
        write_image_file(image, path);
        const std::vector<std::byte> bytes = read_bytes(path);
        ASSERT_GT(bytes.size(), 1000u);
        ASSERT_NO_THROW(load_image_memory(bytes, name));  // the whole file is fine

        const std::size_t header =
            extension == ".hdr" ? hdr_header_end(bytes) : exr_header_end(bytes);
        ASSERT_GT(header, 10u);
        ASSERT_LT(header, 2000u);
        const std::size_t n = bytes.size();
        for (const std::size_t cut :
             {std::size_t(1), std::size_t(4), header - 1, header, header + 1, header + 8,
              header + 200, n / 4, n / 2, 3 * n / 4, n - 64, n - 1}) {
            const std::string cut_name = "cut-" + std::to_string(cut) + extension;
            const std::span<const std::byte> part(bytes.data(), cut);
            expect_error([&] { load_image_memory(part, cut_name); }, ErrorKind::InvalidInput,
                         cut_name, cut_name + " from memory");
            const std::string cut_path = dir.file(cut_name);
            write_bytes(cut_path, part);
            expect_error([&] { load_image_file(cut_path); }, ErrorKind::InvalidInput, cut_path,
                         cut_name + " from a file");
        }
    }
}

TEST(ImageIo, GarbageIsRejected) {
    TempDir dir;
    Lcg rng{5};
    std::vector<std::byte> random(4096);
    for (std::byte& b : random) {
        b = std::byte(rng.next() & 0xff);
    }
    std::vector<std::byte> png = bytes_of("\x89PNG\r\n\x1a\n");
    png.insert(png.end(), random.begin(), random.end());
    std::vector<std::byte> exr = {std::byte{0x76}, std::byte{0x2f}, std::byte{0x31},
                                  std::byte{0x01}};
    exr.insert(exr.end(), random.begin(), random.end());
    const std::vector<std::pair<std::string, std::vector<std::byte>>> cases = {
        {"random.bin", random},
        {"random.hdr", random},
        {"random.tga", random},
        {"empty.exr", {}},
        {"png-then-garbage.png", png},
        {"exr-then-garbage.exr", exr},
        {"radiance-no-size.hdr", bytes_of("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")},
        {"radiance-zero.hdr",
         bytes_of("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 10\n\x02\x02\x00\x0a")},
        {"text.txt", bytes_of("This is not an image, just a sentence long enough to sniff.\n")},
    };
    for (const auto& [name, bytes] : cases) {
        expect_error([&bytes = bytes, &name = name] { load_image_memory(bytes, name); },
                     ErrorKind::InvalidInput, name, name + " from memory");
        const std::string path = dir.file(name);
        write_bytes(path, bytes);
        expect_error([&] { load_image_file(path); }, ErrorKind::InvalidInput, path,
                     name + " from a file");
    }
}

TEST(ImageIo, MissingFileIsAnIoError) {
    TempDir dir;
    const std::string path = dir.file("does-not-exist.exr");
    expect_error([&] { load_image_file(path); }, ErrorKind::Io, path, "missing file");
    expect_error([&] { load_image_file(dir.file("")); }, ErrorKind::Io, "", "a directory");
}

TEST(ImageIo, HugeRadianceHeaderFailsFastWithoutAllocating) {
    const std::vector<std::byte> bytes = bytes_of(
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1000000 +X 1000000\n\x02\x02\x40\x00\x80\x01"
        "\x02\x03\x04\x05\x06\x07");
    // Warm up OpenImageIO (plugin tables, thread pool) so that they are not counted.
    EXPECT_THROW(load_image_memory(bytes, "warm-up.hdr"), Error);

    const long rss_before = max_rss_kb();
    const auto start = std::chrono::steady_clock::now();
    expect_error([&] { load_image_memory(bytes, "huge.hdr"); }, ErrorKind::LimitExceeded,
                 "huge.hdr: image is 1000000x1000000", "default limits");
    // With the side limit raised, the pixel count (10^12, in 64-bit arithmetic) is caught.
    ImageLimits wide;
    wide.max_dimension = 2000000;
    expect_error([&] { load_image_memory(bytes, "huge.hdr", wide); }, ErrorKind::LimitExceeded,
                 "huge.hdr: image is 1000000x1000000 = 1000000000000 pixels, over the limit of " +
                     std::to_string(wide.max_pixels),
                 "side limit raised");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 1.0);
    EXPECT_LT(max_rss_kb() - rss_before, 100 * 1024) << "peak memory grew";

    TempDir dir;
    const std::string path = dir.file("huge.hdr");
    write_bytes(path, bytes);
    expect_error([&] { load_image_file(path); }, ErrorKind::LimitExceeded, path, "from a file");
}

// A tiny valid EXR (4x2, one zip chunk) whose dataWindow claims another size.
std::vector<std::byte> exr_claiming(const TempDir& dir, std::int32_t width, std::int32_t height) {
    const std::string path = dir.file("tiny.exr");
    write_image_file(noise_image(4, 2, 6), path);
    std::vector<std::byte> bytes = read_bytes(path);
    const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    const std::size_t at = text.find(std::string("dataWindow\0box2i\0", 17));
    if (at == std::string::npos) {
        ADD_FAILURE() << "no dataWindow attribute in the EXR header";
        return {};
    }
    // box2i: xMin, yMin, xMax, yMax, after the attribute's int32 size.
    const std::int32_t window[4] = {0, 0, width - 1, height - 1};
    std::memcpy(&bytes[at + 17 + 4], window, sizeof window);
    return bytes;
}

// Found by tests/fuzz/fuzz_image: an EXR attribute whose name is not UTF-8 was quoted as is in
// the error, which the service's problem body (JSON) could not hold: a 500. Such bytes are
// escaped as \xNN.
TEST(ImageIo, ErrorsEscapeHeaderBytesThatAreNotUtf8) {
    TempDir dir;
    const std::string path = dir.file("tiny.exr");
    write_image_file(noise_image(4, 2, 6), path);
    std::vector<std::byte> bytes = read_bytes(path);
    const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    const std::string attribute("compression\0compression\0", 24);
    const std::size_t at = text.find(attribute);
    ASSERT_NE(at, std::string::npos) << "no compression attribute in the EXR header";
    bytes[at] = std::byte{0x9A};  // the name's first byte
    const std::int32_t size = 0x7FFFFFFF;
    std::memcpy(&bytes[at + attribute.size()], &size, sizeof size);
    try {
        load_image_memory(bytes, "upload.exr");
        FAIL() << "loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("\\x9Aompression"), std::string::npos) << e.what();
        EXPECT_NO_THROW((void)nlohmann::json(std::string(e.what())).dump());
    }
}

TEST(ImageIo, ExrHeaderOverTheLimitsFailsFast) {
    TempDir dir;
    // 40000 x 16 is still one 16-line zip chunk, so OpenEXR accepts the header: our checks must
    // reject it before any pixel is read.
    const std::vector<std::byte> wide = exr_claiming(dir, 40000, 16);
    expect_error([&] { load_image_memory(wide, "wide.exr"); }, ErrorKind::LimitExceeded,
                 "wide.exr: image is 40000x16", "side over the limit");
    ImageLimits limits;
    limits.max_pixels = 100000;
    const std::vector<std::byte> many = exr_claiming(dir, 30000, 16);
    expect_error([&] { load_image_memory(many, "many.exr", limits); }, ErrorKind::LimitExceeded,
                 "many.exr: image is 30000x16 = 480000 pixels, over the limit of 100000",
                 "pixel count over the limit");

    // 10^6 x 10^6: OpenEXR may reject the inconsistent file itself (its line offset table does
    // not fit); if it does not, the limits do. Either way fast and without a big allocation.
    const std::vector<std::byte> huge = exr_claiming(dir, 1000000, 1000000);
    EXPECT_THROW(load_image_memory(huge, "warm-up.exr"), Error);
    const long rss_before = max_rss_kb();
    const auto start = std::chrono::steady_clock::now();
    try {
        load_image_memory(huge, "huge.exr");
        ADD_FAILURE() << "a 10^6 x 10^6 EXR with 8 pixels of data loaded";
    } catch (const Error& e) {
        EXPECT_TRUE(e.kind() == ErrorKind::LimitExceeded || e.kind() == ErrorKind::InvalidInput)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("huge.exr"), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
    EXPECT_LT(max_rss_kb() - rss_before, 100 * 1024) << "peak memory grew";
}

TEST(ImageIo, LimitsAreCheckedAgainstTheHeader) {
    TempDir dir;
    const std::string path = dir.file("map.exr");
    write_image_file(noise_image(300, 200, 7), path);
    ImageLimits limits;
    limits.max_pixels = 50000;
    expect_error([&] { load_image_file(path, limits); }, ErrorKind::LimitExceeded,
                 path + ": image is 300x200 = 60000 pixels, over the limit of 50000",
                 "pixel limit");
    limits.max_pixels = 60000;  // exactly at the limit: fine
    EXPECT_EQ(load_image_file(path, limits).image.width, 300);
    limits.max_dimension = 299;
    expect_error([&] { load_image_memory(read_bytes(path), "map.exr", limits); },
                 ErrorKind::LimitExceeded, "map.exr: image is 300x200", "side limit");
}

// ---------------------------------------------------------------------------------------------
// Claims against the bytes: a file at the fewest bytes its claim needs loads, one byte fewer is
// refused (image_claims.cpp derives each minimum).

std::size_t ceil_div(std::size_t a, std::size_t b) {
    return (a + b - 1) / b;
}

// The message of a refused claim, up to the parenthesis that explains the minimum.
std::string claim_refusal(const std::string& name, int width, int height, std::size_t bytes) {
    return name + ": claims " + std::to_string(width) + "x" + std::to_string(height) +
           " pixels but " + std::to_string(bytes) + " bytes cannot hold them (";
}

TEST(ImageIo, RadianceRleAtItsMinimumLoadsAndAByteLessIsRefused) {
    // A constant map: OpenImageIO's writer codes each channel of a scanline as runs of 127,
    // which is the minimum: a 4-byte start and 2 bytes per 127 pixels of each channel.
    TempDir dir;
    HdrImage image(1000, 37);
    std::fill(image.pixels.begin(), image.pixels.end(), 0.75f);
    const std::string path = dir.file("flat.hdr");
    write_image_file(image, path);
    const std::vector<std::byte> bytes = read_bytes(path);
    const std::size_t minimum = hdr_header_end(bytes) + 37 * (4 + 8 * ceil_div(1000, 127));
    ASSERT_EQ(bytes.size(), minimum);
    EXPECT_EQ(load_image_memory(bytes, "flat.hdr").image.pixels, image.pixels);
    const std::span<const std::byte> short_one(bytes.data(), bytes.size() - 1);
    expect_error([&] { load_image_memory(short_one, "short.hdr"); }, ErrorKind::InvalidInput,
                 claim_refusal("short.hdr", 1000, 37, minimum - 1) + "RLE needs at least " +
                     std::to_string(minimum) + " bytes",
                 "one byte under the minimum");
}

TEST(ImageIo, UncompressedExrAtItsMinimumLoadsAndAByteLessIsRefused) {
    if (!have_oiiotool()) {
        GTEST_SKIP() << "*** oiiotool not found (package openimageio-tools): the uncompressed "
                        "EXR's minimum is NOT tested ***";
    }
    // Uncompressed, the file is its header, the chunk offset table, each scanline's 8-byte
    // chunk header and the pixels: exactly the minimum.
    TempDir dir;
    const std::string path = dir.file("plain.exr");
    run("oiiotool --pattern constant:color=1,2,3 64x32 3 -d half --compression none -o " + path);
    const std::vector<std::byte> bytes = read_bytes(path);
    const std::size_t minimum = exr_header_end(bytes) + 32 * 8 + 32 * 8 + 64 * 32 * 3 * 2;
    ASSERT_EQ(bytes.size(), minimum);
    EXPECT_EQ(load_image_memory(bytes, "plain.exr").image.rgb(0), glm::vec3(1, 2, 3));
    const std::span<const std::byte> short_one(bytes.data(), bytes.size() - 1);
    expect_error([&] { load_image_memory(short_one, "short.exr"); }, ErrorKind::InvalidInput,
                 claim_refusal("short.exr", 64, 32, minimum - 1) +
                     "a chunk offset table of 32 entries, 32 chunk headers and the 12288 bytes of "
                     "pixels uncompressed need at least " +
                     std::to_string(minimum) + " bytes)",
                 "one byte under the minimum");
}

// A progressive grey JPEG of its first DC scan only, at 1 bit per block: the one Huffman code
// (1 bit, "0") means a DC difference of 0, so every block is mid-grey (128).
std::vector<std::byte> dc_only_jpeg(int width, int height, std::size_t scan_bytes) {
    std::vector<std::uint8_t> j = {0xFF, 0xD8, 0xFF, 0xDB, 0x00, 0x43, 0x00};
    j.insert(j.end(), 64, 1);  // quantisation table 0, all 1
    const std::vector<std::uint8_t> frame = {0xFF,
                                             0xC2,
                                             0x00,
                                             0x0B,
                                             8,
                                             std::uint8_t(height >> 8),
                                             std::uint8_t(height),
                                             std::uint8_t(width >> 8),
                                             std::uint8_t(width),
                                             1,
                                             1,
                                             0x11,
                                             0};
    j.insert(j.end(), frame.begin(), frame.end());
    const std::vector<std::uint8_t> table = {0xFF, 0xC4, 0x00, 0x14, 0x00, 1, 0, 0, 0, 0, 0,
                                             0,    0,    0,    0,    0,    0, 0, 0, 0, 0, 0};
    j.insert(j.end(), table.begin(), table.end());
    const std::vector<std::uint8_t> scan = {0xFF, 0xDA, 0x00, 0x08, 1, 1, 0x00, 0, 0, 0};
    j.insert(j.end(), scan.begin(), scan.end());
    j.insert(j.end(), scan_bytes, 0);
    j.push_back(0xFF);
    j.push_back(0xD9);
    std::vector<std::byte> bytes(j.size());
    std::memcpy(bytes.data(), j.data(), j.size());
    return bytes;
}

TEST(ImageIo, JpegAtOneBitPerBlockLoadsAndAByteLessIsRefused) {
    // 1024x512 grey: 128 x 64 = 8192 blocks, 1024 bytes of scan at the minimum.
    const std::vector<std::byte> at_minimum = dc_only_jpeg(1024, 512, 1024);
    const LoadedImage loaded = load_image_memory(at_minimum, "grey.jpg");
    ASSERT_EQ(loaded.image.width, 1024);
    EXPECT_NEAR(loaded.image.rgb(0).g, srgb_decode(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(loaded.image.rgb(1024 * 512 - 1).r, srgb_decode(128.0f / 255.0f), 1e-6f);
    const std::vector<std::byte> short_one = dc_only_jpeg(1024, 512, 1023);
    expect_error([&] { load_image_memory(short_one, "short.jpg"); }, ErrorKind::InvalidInput,
                 claim_refusal("short.jpg", 1024, 512, short_one.size()) +
                     "Huffman coding needs at least 1 bit per 8x8 block: 1024 bytes of scan data "
                     "for 8192 blocks; the file has 1023)",
                 "one byte under the minimum");
}

TEST(ImageIo, ConstantPngIsNearItsDeflateMinimumAndLoads) {
    // zlib's deflate of a constant image (at OpenImageIO's default level) comes within a factor
    // 1.5 of its 1032:1 limit: the minimum is not far below what real files reach.
    TempDir dir;
    HdrImage image(2048, 1024);
    std::fill(image.pixels.begin(), image.pixels.end(), 0.5f);
    const std::string path = dir.file("flat.png");
    write_image_file(image, path);
    const std::vector<std::byte> bytes = read_bytes(path);
    const std::size_t minimum = ceil_div(1024 * (1 + 2048 * 3), 1032);
    EXPECT_GT(bytes.size(), minimum);
    EXPECT_LT(bytes.size(), minimum * 3 / 2) << "zlib got nowhere near 1032:1";
    EXPECT_EQ(load_image_memory(bytes, "flat.png").image.width, 2048);
}

TEST(ImageIo, ProbeChecksLikeALoadWithoutReadingPixels) {
    TempDir dir;
    const std::string path = dir.file("map.exr");
    write_image_file(noise_image(300, 200, 11), path);
    const std::vector<std::byte> bytes = read_bytes(path);
    const ImageHeader header = probe_image_memory(bytes, "map.exr");
    EXPECT_EQ(header.format, "openexr");
    EXPECT_EQ(header.width, 300);
    EXPECT_EQ(header.height, 200);
    EXPECT_EQ(header.channels, 3);
    EXPECT_GE(header.decode_bytes, 300u * 200u * 12u);
    ImageLimits limits;
    limits.max_pixels = 50000;
    expect_error([&] { probe_image_memory(bytes, "map.exr", limits); }, ErrorKind::LimitExceeded,
                 "map.exr: image is 300x200 = 60000 pixels, over the limit of 50000",
                 "probe over the limit");
    // Short of the chunk offset table's 13 entries: refused without reading pixels.
    const std::span<const std::byte> no_table(bytes.data(), exr_header_end(bytes) + 50);
    expect_error([&] { probe_image_memory(no_table, "no-table.exr"); }, ErrorKind::InvalidInput,
                 claim_refusal("no-table.exr", 300, 200, no_table.size()) +
                     "a chunk offset table of 13 entries",
                 "probe without the chunk table");
    // Half the file holds more than the minimum: only reading the pixels finds it truncated.
    const std::span<const std::byte> half(bytes.data(), bytes.size() / 2);
    EXPECT_EQ(probe_image_memory(half, "half.exr").width, 300);
    EXPECT_THROW(load_image_memory(half, "half.exr"), Error);
}

// Peak resident growth of loading bytes, KiB (the pages a load touches; new ones, as freed
// memory is handed back to the system first).
long load_growth_kib(const std::vector<std::byte>& bytes, const std::string& name) {
    malloc_trim(0);
    oer::testing::reset_peak_resident();
    const long before = oer::testing::resident_kib();
    const LoadedImage loaded = load_image_memory(bytes, name);
    EXPECT_GT(loaded.image.width, 0);
    return oer::testing::peak_resident_kib() - before;
}

TEST(ImageIo, ProbePredictsTheMemoryOfALoad) {
    if (!have_oiiotool()) {
        GTEST_SKIP() << "*** oiiotool not found (package openimageio-tools): the probe's memory "
                        "figure is NOT tested on RGBA and tiled maps ***";
    }
    if (!oer::testing::reset_peak_resident()) {
        GTEST_SKIP() << "*** /proc/self/clear_refs is not writable: the peak resident memory "
                        "of a load cannot be measured ***";
    }
    // Maps of 2048x1024 in each format and layout the loader reads differently: the growth of
    // resident memory while loading is the prediction, within the pages the readers' row
    // buffers, the libraries' tables and the allocator add.
    TempDir dir;
    std::string command = "oiiotool";
    const std::vector<std::pair<std::string, std::string>> made = {
        {"rgba_half.exr", "--pattern noise 2048x1024 4 -d half"},
        {"tiled.exr", "--pattern noise 2048x1024 3 -d float --tile 64 64"},
        {"rgb8.png", "--pattern noise 2048x1024 3 -d uint8"},
        {"rgba16.png", "--pattern noise 2048x1024 4 -d uint16"},
        {"progressive.jpg", "--pattern noise 2048x1024 3 -d uint8 --attrib jpeg:progressive 1"},
    };
    for (const auto& [file, pattern] : made) {
        command += " " + pattern + " -o " + dir.file(file);
    }
    run(command);
    const HdrImage noise = noise_image(2048, 1024, 12);
    for (const std::string file : {"rgb.hdr", "rgb.exr"}) {
        write_image_file(noise, dir.file(file));
    }
    for (const std::string file : {"rgb.hdr", "rgb.exr", "rgba_half.exr", "tiled.exr", "rgb8.png",
                                   "rgba16.png", "progressive.jpg"}) {
        const std::vector<std::byte> bytes = read_bytes(dir.file(file));
        const ImageHeader header = probe_image_memory(bytes, file);
        const long predicted_kib = long(header.decode_bytes / 1024);
        const long measured_kib = load_growth_kib(bytes, file);
        std::cout << "[          ] " << file << ": predicted " << predicted_kib
                  << " KiB, resident growth " << measured_kib << " KiB\n";
        if (oer::testing::kResidentMemoryIsTheProgramsOwn) {
            EXPECT_LE(measured_kib, predicted_kib * 21 / 20 + 4096) << file;
            EXPECT_GE(measured_kib, predicted_kib * 3 / 4) << file;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Writing

TEST(ImageIo, WriteErrorsNameThePath) {
    TempDir dir;
    const HdrImage image = noise_image(4, 2, 8);
    const std::string unsupported = dir.file("map.xyz");
    expect_error([&] { write_image_file(image, unsupported); }, ErrorKind::Unsupported, unsupported,
                 "unknown extension");
    const std::string nowhere = dir.file("no/such/dir/map.exr");
    expect_error([&] { write_image_file(image, nowhere); }, ErrorKind::Io, nowhere,
                 "missing directory");
    HdrImage broken(4, 2);
    broken.pixels.resize(5);
    const std::string path = dir.file("broken.exr");
    expect_error([&] { write_image_file(broken, path); }, ErrorKind::InvalidInput, path,
                 "inconsistent image");
}

// ---------------------------------------------------------------------------------------------
// Real data (docs/design.md section 5)

TEST(ImageIo, LoadsBlenderStudioWorlds) {
    const fs::path folder = "/usr/share/blender/datafiles/studiolights/world";
    std::vector<fs::path> files;
    if (fs::is_directory(folder)) {
        for (const auto& entry : fs::directory_iterator(folder)) {
            if (entry.path().extension() == ".exr") {
                files.push_back(entry.path());
            }
        }
    }
    if (files.empty()) {
        GTEST_SKIP() << "*** blender-data is not installed: no real HDR worlds under " << folder
                     << "; real-data loading is NOT tested ***";
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
        const LoadedImage loaded = load_image_file(file.string());
        // Real maps pass the checks of their claims against their bytes, and the probe says
        // what the load found.
        const ImageHeader header = probe_image_memory(read_bytes(file.string()), file.string());
        EXPECT_EQ(header.width, loaded.image.width) << file;
        EXPECT_EQ(header.height, loaded.image.height) << file;
        EXPECT_GE(header.decode_bytes, loaded.image.pixels.size() * sizeof(float)) << file;
        EXPECT_GT(loaded.image.width, 0) << file;
        EXPECT_GT(loaded.image.height, 0) << file;
        ASSERT_EQ(loaded.image.pixels.size(), loaded.image.pixel_count() * 3) << file;
        double total = 0.0;
        for (float v : loaded.image.pixels) {
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << file << ": " << v;
            total += v;
        }
        EXPECT_GT(total, 0.0) << file;
        std::cout << "[          ] " << file.filename().string() << ": " << loaded.image.width
                  << "x" << loaded.image.height << ", repaired nan=" << loaded.repaired.nan
                  << " inf=" << loaded.repaired.inf << " negative=" << loaded.repaired.negative
                  << "\n";
    }
}
