// The wire encoders: JPEG (quality, chroma subsampling, round-trip error), PNG (exact with
// alpha), EXR (exact floats, read back by the image loader), and decoding's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"

using namespace oer;

namespace {

// A smooth image: horizontal red ramp, vertical green ramp, a slow diagonal blue wave; alpha
// a ramp too (JPEG ignores it).
Rgba8Image smooth_image(int width, int height) {
    Rgba8Image image{width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 4)};
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = &image.pixels[(std::size_t(y) * width + x) * 4];
            const double u = (x + 0.5) / width, v = (y + 0.5) / height;
            p[0] = std::uint8_t(std::lround(255.0 * u));
            p[1] = std::uint8_t(std::lround(255.0 * v));
            p[2] = std::uint8_t(std::lround(127.5 + 100.0 * std::sin(3.0 * (u + v))));
            p[3] = std::uint8_t(std::lround(255.0 * (1.0 - u)));
        }
    }
    return image;
}

struct Difference {
    int max = 0;
    double mean = 0;
};

// Over R, G and B only.
Difference rgb_difference(const Rgba8Image& a, const Rgba8Image& b) {
    Difference d;
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
        for (std::size_t c = 0; c < 3; ++c) {
            const int e = std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c]));
            d.max = std::max(d.max, e);
            sum += e;
            ++count;
        }
    }
    d.mean = sum / double(count);
    return d;
}

// The sampling factors (h << 4 | v) of the JPEG's first component, from its SOF0 frame
// header: 0x22 for 4:2:0 luma, 0x11 for 4:4:4.
int luma_sampling(const std::vector<std::uint8_t>& jpeg) {
    for (std::size_t i = 2; i + 12 < jpeg.size(); ++i) {
        if (jpeg[i] == 0xff && jpeg[i + 1] == 0xc0) {
            // FFC0, length(2), precision(1), height(2), width(2), components(1), id, sampling
            return jpeg[i + 11];
        }
    }
    return -1;
}

ErrorKind kind_of(const std::function<void()>& action, std::string* message = nullptr) {
    try {
        action();
    } catch (const Error& error) {
        if (message != nullptr) {
            *message = error.what();
        }
        return error.kind();
    }
    ADD_FAILURE() << "no oer::Error thrown";
    return ErrorKind::Internal;
}

}  // namespace

TEST(ImageEncoding, JpegRoundTripOfASmoothImageAtQuality95) {
    const Rgba8Image image = smooth_image(256, 192);
    const std::vector<std::uint8_t> jpeg = encode_jpeg(image, 95);
    ASSERT_GE(jpeg.size(), 4u);
    EXPECT_EQ(jpeg[0], 0xff);
    EXPECT_EQ(jpeg[1], 0xd8);
    EXPECT_EQ(jpeg[jpeg.size() - 2], 0xff);
    EXPECT_EQ(jpeg[jpeg.size() - 1], 0xd9);
    EXPECT_EQ(luma_sampling(jpeg), 0x11);  // 4:4:4 from quality 90

    const Rgba8Image decoded = decode_8bit(jpeg);
    ASSERT_EQ(decoded.width, 256);
    ASSERT_EQ(decoded.height, 192);
    ASSERT_EQ(decoded.pixels.size(), image.pixels.size());
    const Difference d = rgb_difference(image, decoded);
    std::cout << "[ JPEG q95 ] " << jpeg.size() << " bytes, max error " << d.max << "/255, mean "
              << d.mean << std::endl;
    EXPECT_LE(d.max, 4);     // of 255, on any channel of any pixel
    EXPECT_LE(d.mean, 0.8);  // of 255
    for (std::size_t i = 3; i < decoded.pixels.size(); i += 4) {
        ASSERT_EQ(decoded.pixels[i], 255);  // JPEG has no alpha: opaque
    }
}

TEST(ImageEncoding, JpegQualityTradesSizeForError) {
    const Rgba8Image image = smooth_image(256, 256);
    const std::vector<std::uint8_t> low = encode_jpeg(image, 10);
    const std::vector<std::uint8_t> middle = encode_jpeg(image, 85);
    const std::vector<std::uint8_t> high = encode_jpeg(image, 95);
    EXPECT_LT(low.size(), middle.size());
    EXPECT_LT(middle.size(), high.size());
    EXPECT_EQ(luma_sampling(middle), 0x22);  // 4:2:0 below quality 90
    EXPECT_EQ(luma_sampling(low), 0x22);
    EXPECT_GT(rgb_difference(image, decode_8bit(low)).mean,
              rgb_difference(image, decode_8bit(high)).mean);
    // The extremes are valid.
    EXPECT_NO_THROW(encode_jpeg(image, 1));
    EXPECT_NO_THROW(encode_jpeg(image, 100));
}

TEST(ImageEncoding, JpegRejectsAQualityOutside1To100) {
    const Rgba8Image image = smooth_image(8, 8);
    for (const int quality : {0, 101, -5, 1000}) {
        std::string message;
        EXPECT_EQ(kind_of([&] { encode_jpeg(image, quality); }, &message), ErrorKind::InvalidInput);
        EXPECT_NE(message.find(std::to_string(quality)), std::string::npos) << message;
        EXPECT_NE(message.find("1..100"), std::string::npos) << message;
    }
}

TEST(ImageEncoding, EncodersValidateSizes) {
    Rgba8Image empty{0, 4, {}};
    std::string message;
    EXPECT_EQ(kind_of([&] { encode_jpeg(empty, 80); }, &message), ErrorKind::InvalidInput);
    EXPECT_NE(message.find("0x4"), std::string::npos) << message;
    EXPECT_EQ(kind_of([&] { encode_png(empty); }), ErrorKind::InvalidInput);
    EXPECT_EQ(kind_of([&] { encode_exr(4, -1, {}); }), ErrorKind::InvalidInput);

    Rgba8Image short_buffer = smooth_image(5, 3);
    short_buffer.pixels.pop_back();
    EXPECT_EQ(kind_of([&] { encode_png(short_buffer); }, &message), ErrorKind::InvalidInput);
    EXPECT_NE(message.find("5x3"), std::string::npos) << message;
    EXPECT_NE(message.find("60"), std::string::npos) << message;  // values needed
    EXPECT_NE(message.find("59"), std::string::npos) << message;  // values given
    EXPECT_EQ(kind_of([&] { encode_jpeg(short_buffer, 90); }), ErrorKind::InvalidInput);
    EXPECT_EQ(kind_of([&] { encode_exr(5, 3, std::vector<float>(5 * 3 * 3)); }),
              ErrorKind::InvalidInput);  // RGB is not RGBA

    Rgba8Image too_wide{70000, 1, std::vector<std::uint8_t>(70000 * 4)};
    EXPECT_EQ(kind_of([&] { encode_jpeg(too_wide, 80); }), ErrorKind::LimitExceeded);
}

TEST(ImageEncoding, PngRoundTripIsExactIncludingAlpha) {
    Rgba8Image image = smooth_image(97, 61);  // odd sizes: no row padding assumed
    // Every value in every channel, and color under alpha 0 (straight alpha keeps it).
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        if (i < 256 * 4) {
            image.pixels[i] = std::uint8_t((i / 4 + i % 4 * 67) & 0xff);
        }
    }
    image.pixels[3] = 0;
    image.pixels[0] = 200;
    const std::vector<std::uint8_t> png = encode_png(image);
    ASSERT_GE(png.size(), 8u);
    EXPECT_EQ(std::memcmp(png.data(), "\x89PNG\r\n\x1a\n", 8), 0);
    const Rgba8Image decoded = decode_8bit(png);
    ASSERT_EQ(decoded.width, image.width);
    ASSERT_EQ(decoded.height, image.height);
    ASSERT_EQ(decoded.pixels.size(), image.pixels.size());
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        ASSERT_EQ(decoded.pixels[i], image.pixels[i]) << "value " << i;
    }
}

TEST(ImageEncoding, ExrRoundTripIsExact) {
    const int width = 33, height = 17;
    std::vector<float> rgba(std::size_t(width) * height * 4);
    for (std::size_t i = 0; i < rgba.size(); ++i) {
        // Linear radiance well beyond 1, tiny values, and values no half float holds.
        rgba[i] = float(i % 7) * 1234.5678f + float(i) * 1e-5f + (i % 4 == 3 ? 0.5f : 0.0f);
    }
    const std::vector<std::uint8_t> exr = encode_exr(width, height, rgba);
    ASSERT_GE(exr.size(), 4u);
    EXPECT_EQ(exr[0], 0x76);  // OpenEXR's magic number
    EXPECT_EQ(exr[1], 0x2f);
    EXPECT_EQ(exr[2], 0x31);
    EXPECT_EQ(exr[3], 0x01);

    std::vector<std::byte> bytes(exr.size());
    std::memcpy(bytes.data(), exr.data(), exr.size());
    const LoadedImage loaded = load_image_memory(bytes, "frame.exr");
    ASSERT_EQ(loaded.image.width, width);
    ASSERT_EQ(loaded.image.height, height);
    for (std::size_t p = 0; p < loaded.image.pixel_count(); ++p) {
        for (std::size_t c = 0; c < 3; ++c) {
            ASSERT_EQ(loaded.image.pixels[p * 3 + c], rgba[p * 4 + c])
                << "pixel " << p << " channel " << c;
        }
    }
    // Compressed: a smooth image takes less than its 16 bytes per pixel.
    std::vector<float> flat(std::size_t(256) * 256 * 4, 0.5f);
    EXPECT_LT(encode_exr(256, 256, flat).size(), flat.size() * sizeof(float) / 4);
}

TEST(ImageEncoding, DecodingGarbageOrTruncatedBytesIsInvalidInput) {
    std::string message;
    EXPECT_EQ(kind_of([] { decode_8bit({}); }), ErrorKind::InvalidInput);
    EXPECT_EQ(kind_of(
                  [] {
                      decode_8bit({'h', 'e', 'l', 'l', 'o'});
                  },
                  &message),
              ErrorKind::InvalidInput);
    EXPECT_NE(message.find("not a JPEG or PNG"), std::string::npos) << message;

    const Rgba8Image image = smooth_image(64, 64);
    std::vector<std::uint8_t> jpeg = encode_jpeg(image, 80);
    jpeg.resize(jpeg.size() / 2);
    EXPECT_EQ(kind_of([&] { decode_8bit(jpeg); }, &message), ErrorKind::InvalidInput);
    std::cout << "[ message  ] " << message << std::endl;
    std::vector<std::uint8_t> header_only = {0xff, 0xd8, 0xff, 0xe0, 0x00};
    EXPECT_EQ(kind_of([&] { decode_8bit(header_only); }), ErrorKind::InvalidInput);

    const std::vector<std::uint8_t> png = encode_png(image);
    std::vector<std::uint8_t> truncated(png.begin(), png.begin() + std::ptrdiff_t(png.size() / 2));
    EXPECT_EQ(kind_of([&] { decode_8bit(truncated); }, &message), ErrorKind::InvalidInput);
    std::cout << "[ message  ] " << message << std::endl;
    EXPECT_NE(message.find("truncated PNG"), std::string::npos) << message;
    // Without its last chunk (IEND: 12 bytes).
    truncated.assign(png.begin(), png.end() - 12);
    EXPECT_EQ(kind_of([&] { decode_8bit(truncated); }, &message), ErrorKind::InvalidInput);
    EXPECT_NE(message.find("IEND"), std::string::npos) << message;

    // Chunks intact, pixel data damaged: libpng's CRC check or zlib catches it.
    std::vector<std::uint8_t> corrupt = png;
    const std::size_t idat = std::string(png.begin(), png.end()).find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    const std::size_t idat_size = std::size_t(png[idat - 2]) << 8 | png[idat - 1];
    ASSERT_GT(idat_size, 16u);
    for (std::size_t i = idat + 4 + 2; i < idat + 4 + idat_size; i += 5) {
        corrupt[i] ^= 0x5a;
    }
    EXPECT_EQ(kind_of([&] { decode_8bit(corrupt); }, &message), ErrorKind::InvalidInput);
    std::cout << "[ message  ] " << message << std::endl;
    // Chunk structure broken.
    corrupt = png;
    corrupt[12] = '1';  // IHDR's type
    EXPECT_EQ(kind_of([&] { decode_8bit(corrupt); }, &message), ErrorKind::InvalidInput);
    EXPECT_NE(message.find("byte 12"), std::string::npos) << message;
}

// Not a benchmark, a record: the time and size of a typical preview frame's encoding.
TEST(ImageEncoding, JpegOf512SquareAtQuality85) {
    const Rgba8Image image = smooth_image(512, 512);
    std::vector<std::uint8_t> jpeg = encode_jpeg(image, 85);  // warm the thread's encoder
    const int runs = 20;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < runs; ++i) {
        jpeg = encode_jpeg(image, 85);
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count() /
        runs;
    const auto png_start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> png = encode_png(image);
    const double png_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - png_start)
            .count();
    std::cout << "[ timing   ] 512x512 JPEG q85: " << ms << " ms, " << jpeg.size()
              << " bytes; PNG: " << png_ms << " ms, " << png.size() << " bytes" << std::endl;
    EXPECT_LT(jpeg.size(), 512u * 512u * 3u / 10u);  // a smooth image compresses > 10:1
    EXPECT_LT(rgb_difference(image, decode_8bit(jpeg)).max, 16);
}
