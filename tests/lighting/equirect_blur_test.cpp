#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/core/image.hpp"
#include "oer/lighting/light_location.hpp"

using namespace oer;

namespace {

double row_sum(const std::vector<float>& values, int width, int y) {
    double sum = 0.0;
    for (int x = 0; x < width; ++x) {
        sum += values[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
    return sum;
}

}  // namespace

TEST(EquirectBlur, ImpulseAtTheLeftEdgeSpreadsAcrossTheSeam) {
    const int w = 64, h = 16;
    std::vector<float> values(std::size_t(w) * h, 0.0f);
    values[std::size_t(8) * w + 0] = 1.0f;
    const std::vector<float> blurred = blur_equirect_channel(values, w, h, 4.0);
    const float* row = &blurred[std::size_t(8) * w];
    EXPECT_GT(row[w - 1], 0.01f);
    EXPECT_GT(row[w - 4], 0.0f);
    // Symmetric about x = 0 across the seam: x = -k is x = w - k.
    for (int k = 1; k <= 4; ++k) {
        EXPECT_FLOAT_EQ(row[w - k], row[k]) << k;
    }
    EXPECT_EQ(row[w / 2], 0.0f);  // beyond the kernel's reach
}

TEST(EquirectBlur, GaussianHasSigmaHalfTheRadius) {
    const int w = 101, h = 1;
    std::vector<float> values(w, 0.0f);
    values[50] = 1.0f;
    const std::vector<float> blurred = blur_equirect_channel(values, w, h, 4.0);
    // sigma = 2: exp(-k^2 / 8) relative to the centre.
    for (int k = 1; k <= 4; ++k) {
        EXPECT_NEAR(blurred[50 + k] / blurred[50], std::exp(-k * k / 8.0), 1e-6) << k;
    }
    EXPECT_EQ(blurred[55], 0.0f);  // half-width ceil(4) = 4
}

TEST(EquirectBlur, ConstantImageStaysExactlyConstant) {
    HdrImage image(37, 19);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, {0.7f, 1.3f, 2.9f});
    }
    const HdrImage blurred = blur_equirect(image, 4.0);
    ASSERT_EQ(blurred.width, 37);
    ASSERT_EQ(blurred.height, 19);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        for (int c = 0; c < 3; ++c) {
            // Every pixel adds the same taps in the same order: bit-identical everywhere.
            ASSERT_EQ(blurred.pixels[i * 3 + c], blurred.pixels[c]) << i;
        }
    }
    EXPECT_NEAR(blurred.pixels[0], 0.7f, 1e-6);
    EXPECT_NEAR(blurred.pixels[1], 1.3f, 1e-6);
    EXPECT_NEAR(blurred.pixels[2], 2.9f, 1e-6);
}

TEST(EquirectBlur, HorizontalPassConservesRowSums) {
    // Rows that are all the same make the vertical pass an identity, so each row's sum shows
    // the horizontal pass alone: a wrapped, normalised kernel loses nothing at the seam.
    const int w = 50, h = 6;
    std::vector<float> row(w);
    for (int x = 0; x < w; ++x) {
        row[x] = float((x * 37) % 11) + (x < 3 || x > w - 3 ? 40.0f : 0.0f);
    }
    std::vector<float> values;
    for (int y = 0; y < h; ++y) {
        values.insert(values.end(), row.begin(), row.end());
    }
    const double before = row_sum(values, w, 0);
    for (double radius : {1.0, 2.5, 4.0, 30.0, 100.0}) {
        const std::vector<float> blurred = blur_equirect_channel(values, w, h, radius);
        for (int y = 0; y < h; ++y) {
            EXPECT_NEAR(row_sum(blurred, w, y), before, 1e-5 * before) << radius << " " << y;
        }
    }
}

TEST(EquirectBlur, RadiusZeroCopies) {
    HdrImage image(5, 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = float(i) * 0.25f;
    }
    EXPECT_EQ(blur_equirect(image, 0.0).pixels, image.pixels);
}

TEST(EquirectBlur, TinyImagesAndKernelsWiderThanTheImage) {
    // 1x1: the only pixel keeps its value.
    EXPECT_NEAR(blur_equirect_channel({3.0f}, 1, 1, 4.0)[0], 3.0f, 1e-6);
    // 2x1: the kernel wraps around the row several times; the row sum is kept and the dark
    // pixel receives light from both sides.
    const std::vector<float> two = blur_equirect_channel({1.0f, 0.0f}, 2, 1, 4.0);
    EXPECT_NEAR(two[0] + two[1], 1.0f, 1e-6);
    EXPECT_GT(two[1], 0.3f);
    EXPECT_GT(two[0], two[1]);
    // 1x4096: horizontal wrap onto itself is an identity; the vertical pass spreads.
    std::vector<float> column(4096, 0.0f);
    column[2000] = 1.0f;
    const std::vector<float> blurred = blur_equirect_channel(column, 1, 4096, 4.0);
    EXPECT_GT(blurred[1996], 0.0f);
    EXPECT_EQ(blurred[1995], 0.0f);
    EXPECT_NEAR(std::accumulate(blurred.begin(), blurred.end(), 0.0), 1.0, 1e-6);
    // Clamped at the poles: an impulse in the first row keeps the taps that fall above it.
    std::vector<float> top(64, 0.0f);
    top[0] = 1.0f;
    const std::vector<float> clamped = blur_equirect_channel(top, 1, 64, 4.0);
    EXPECT_GT(clamped[0], clamped[1]);
    EXPECT_GT(clamped[0], 0.5f);
}

TEST(EquirectBlur, RgbBlurIsTheChannelBlurPerChannel) {
    const int w = 23, h = 11;
    HdrImage image(w, h);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = float((i * 7919) % 101) * 0.1f;
    }
    const HdrImage blurred = blur_equirect(image, 3.0);
    for (int c = 0; c < 3; ++c) {
        std::vector<float> channel(image.pixel_count());
        for (std::size_t i = 0; i < channel.size(); ++i) {
            channel[i] = image.pixels[i * 3 + c];
        }
        const std::vector<float> expected = blur_equirect_channel(channel, w, h, 3.0);
        for (std::size_t i = 0; i < channel.size(); ++i) {
            ASSERT_EQ(blurred.pixels[i * 3 + c], expected[i]) << c << " " << i;
        }
    }
}

TEST(EquirectBlur, RejectsInvalidRadiusAndImages) {
    const HdrImage image(4, 2);
    for (double radius : {-1.0, std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::infinity(), 1025.0}) {
        try {
            blur_equirect(image, radius);
            ADD_FAILURE() << "no error for radius " << radius;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput) << radius;
        }
    }
    EXPECT_THROW(blur_equirect(HdrImage(), 4.0), Error);
    EXPECT_THROW(blur_equirect_channel({1.0f, 2.0f}, 3, 1, 4.0), Error);
}
