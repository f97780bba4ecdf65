#include <gtest/gtest.h>

#include <span>
#include <string>
#include <vector>

#include "oer/api/frame_encoding.hpp"
#include "oer/core/error.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"

using namespace oer;

namespace {

// A 2x1 frame: a red opaque pixel and a half-transparent blue one, and the same in linear.
Frame two_pixel_frame() {
    Frame frame;
    frame.width = 2;
    frame.height = 1;
    frame.display.width = 2;
    frame.display.height = 1;
    frame.display.pixels = {255, 0, 0, 255, 0, 0, 255, 128};
    frame.linear = {4.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.5f, 0.5f};
    return frame;
}

std::string signature_of(const std::vector<std::uint8_t>& bytes, std::size_t count) {
    return std::string(bytes.begin(), bytes.begin() + std::ptrdiff_t(count));
}

}  // namespace

TEST(FrameEncoding, PngKeepsTheDisplayPixelsAndTheirAlpha) {
    const Frame frame = two_pixel_frame();
    const auto png = api::encode(frame, api::ImageFormat::Png, 85);
    EXPECT_EQ(signature_of(png, 4), "\x89PNG");
    EXPECT_EQ(decode_8bit(png).pixels, frame.display.pixels);
}

TEST(FrameEncoding, JpegEncodesTheDisplayPixelsAtTheGivenQuality) {
    const Frame frame = two_pixel_frame();
    const auto low = api::encode(frame, api::ImageFormat::Jpeg, 10);
    EXPECT_EQ(signature_of(low, 3), "\xFF\xD8\xFF");
    EXPECT_EQ(low, encode_jpeg(frame.display, 10));
    EXPECT_NE(low, api::encode(frame, api::ImageFormat::Jpeg, 95));
    EXPECT_THROW(api::encode(frame, api::ImageFormat::Jpeg, 0), Error);
}

TEST(FrameEncoding, ExrEncodesTheLinearPixels) {
    const Frame frame = two_pixel_frame();
    const auto exr = api::encode(frame, api::ImageFormat::Exr, 85);
    EXPECT_EQ(signature_of(exr, 4), "\x76\x2F\x31\x01");
    // Read back, not compared byte for byte: the header carries the second it was written.
    const LoadedImage read = load_image_memory(std::as_bytes(std::span(exr)), "frame.exr");
    ASSERT_EQ(read.image.width, 2);
    ASSERT_EQ(read.image.height, 1);
    EXPECT_EQ(read.image.pixels, (std::vector<float>{4.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.5f}));
}

TEST(FrameEncoding, ContentTypesNameEachFormat) {
    EXPECT_EQ(api::content_type_of(api::ImageFormat::Jpeg), "image/jpeg");
    EXPECT_EQ(api::content_type_of(api::ImageFormat::Png), "image/png");
    EXPECT_EQ(api::content_type_of(api::ImageFormat::Exr), "image/x-exr");
}
