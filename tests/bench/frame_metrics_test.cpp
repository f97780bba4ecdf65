// bench/support/frame_metrics: the frame-error figures of the frame sweep, on images whose
// answer is known by hand.
#include "frame_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "oer/core/error.hpp"

namespace {

using oer::bench::fidelity_db;
using oer::bench::relative_noise;
using oer::bench::relative_rms_error;

oer::Rgba8Image flat(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    oer::Rgba8Image image{width, height, {}};
    for (int i = 0; i < width * height; ++i) {
        image.pixels.insert(image.pixels.end(), {r, g, b, 255});
    }
    return image;
}

TEST(FrameMetrics, RelativeRmsIsTheReferenceNoiseMeasureOverTheMaskOnly) {
    const std::vector<double> reference{1.0, 2.0, 100.0};
    const std::vector<double> frame{1.5, 2.0, -7.0};
    const std::vector<std::uint8_t> mask{1, 1, 0};
    // sqrt((0.5^2 + 0) / (1 + 4)): the third pixel, outside the mask, counts for nothing.
    EXPECT_NEAR(relative_rms_error(frame, reference, mask), std::sqrt(0.25 / 5.0), 1e-15);
    EXPECT_EQ(relative_rms_error(reference, reference, mask), 0.0);
    EXPECT_THROW(relative_rms_error(frame, reference, std::vector<std::uint8_t>{0, 0, 0}),
                 oer::Error);
    EXPECT_THROW(relative_rms_error(frame, std::vector<double>{0.0, 0.0, 1.0}, mask), oer::Error);
    EXPECT_THROW(relative_rms_error(frame, reference, std::vector<std::uint8_t>{1, 1}), oer::Error);
}

TEST(FrameMetrics, RelativeNoiseIsThePerPixelNoiseOverTheMaskOnly) {
    const std::vector<double> reference{1.0, 2.0, 100.0};
    const std::vector<double> noise{0.3, 0.4, 50.0};
    const std::vector<std::uint8_t> mask{1, 1, 0};
    // sqrt((0.3^2 + 0.4^2) / (1 + 4)): the third pixel, outside the mask, counts for nothing.
    EXPECT_NEAR(relative_noise(noise, reference, mask), std::sqrt(0.25 / 5.0), 1e-15);
    EXPECT_EQ(relative_noise(noise, reference, std::vector<std::uint8_t>{0, 0, 0}), 0.0);
    EXPECT_THROW(relative_noise(noise, reference, std::vector<std::uint8_t>{1, 1}), oer::Error);
}

TEST(FrameMetrics, BlocksTileFromTheTopLeftAndLeaveOutPartialOnes) {
    // 5 x 3 pixels in blocks of 2: two whole blocks (columns 0-1 and 2-3 of rows 0-1); the fifth
    // column and the third row are partial blocks, left out.
    const oer::bench::BlockGrid grid{5, 3, 2};
    const std::vector<double> values{1,  2,  10, 20, 99,  //
                                     3,  4,  30, 40, 99,  //
                                     99, 99, 99, 99, 99};
    EXPECT_EQ(oer::bench::block_means(values, grid), (std::vector<double>{2.5, 25.0}));
    std::vector<std::uint8_t> mask(15, 1);
    mask[8] = 0;  // (3, 1): the second block is no longer whole
    mask[4] = 0;  // (4, 0): a partial block's pixel changes nothing
    EXPECT_EQ(oer::bench::whole_blocks(mask, grid), (std::vector<std::uint8_t>{1, 0}));
    // A block's mean of 4 independent pixels: sqrt(sum sigma^2) / 4.
    const std::vector<double> noise{0.4, 0.4, 0.0, 0.0, 9.0,  //
                                    0.4, 0.4, 0.0, 0.8, 9.0,  //
                                    9.0, 9.0, 9.0, 9.0, 9.0};
    const std::vector<double> block_noise = oer::bench::block_noise(noise, grid);
    ASSERT_EQ(block_noise.size(), 2u);
    EXPECT_NEAR(block_noise[0], 0.2, 1e-15);
    EXPECT_NEAR(block_noise[1], 0.2, 1e-15);
    EXPECT_THROW(oer::bench::block_means(std::vector<double>(14), grid), oer::Error);
    EXPECT_THROW(oer::bench::whole_blocks(mask, oer::bench::BlockGrid{5, 3, 0}), oer::Error);
}

TEST(FrameMetrics, LeastSquaresScaleUndoesAnExposure) {
    const std::vector<double> reference{0.2, 0.9, 4.0};
    const std::vector<double> frame{0.8, 3.6, 16.0};  // 4x the reference
    EXPECT_NEAR(
        oer::bench::least_squares_scale(frame, reference, std::vector<std::uint8_t>{1, 1, 1}), 0.25,
        1e-15);
    EXPECT_THROW(oer::bench::least_squares_scale(std::vector<double>{0.0, 0.0, 0.0}, reference,
                                                 std::vector<std::uint8_t>{1, 1, 1}),
                 oer::Error);
}

TEST(FrameMetrics, YiqDeltaOfBlackAgainstWhiteIsPixelmatchsLuminanceTerm) {
    const std::uint8_t black[4] = {0, 0, 0, 255}, white[4] = {255, 255, 255, 255};
    // Y of white is 255 (the weights sum to 1), I and Q are 0: 0.5053 * 255^2.
    EXPECT_NEAR(oer::bench::yiq_delta(black, white), 0.5053 * 255.0 * 255.0, 1e-3);
    EXPECT_EQ(oer::bench::yiq_delta(white, white), 0.0);
    // A transparent pixel is blended over white, as pixelmatch does.
    const std::uint8_t clear_black[4] = {0, 0, 0, 0};
    EXPECT_EQ(oer::bench::yiq_delta(clear_black, white), 0.0);
    // Pure red against black: the chroma terms count too.
    const std::uint8_t red[4] = {255, 0, 0, 255};
    const double y = 255 * 0.29889531, i = 255 * 0.59597799, q = 255 * 0.21147017;
    EXPECT_NEAR(oer::bench::yiq_delta(red, black), 0.5053 * y * y + 0.299 * i * i + 0.1957 * q * q,
                1e-6);
}

TEST(FrameMetrics, FidelityDbIsModelViewersRmsRatioInDecibels) {
    const oer::Rgba8Image black = flat(4, 2, 0, 0, 0), white = flat(4, 2, 255, 255, 255);
    std::vector<std::uint8_t> mask(8, 1);
    EXPECT_NEAR(fidelity_db(black, white, mask),
                10.0 * std::log10(0.5053 * 255.0 * 255.0 / oer::bench::kMaxYiqDelta),
                1e-6);  // the Y weights sum to 1 + 1e-8
    EXPECT_EQ(fidelity_db(white, white, mask), -INFINITY);
    // Half the pixels differ: the RMS of delta falls by sqrt(2), 1.5 dB.
    oer::Rgba8Image half = white;
    for (int i = 0; i < 4; ++i) {
        half.pixels[4 * i] = half.pixels[4 * i + 1] = half.pixels[4 * i + 2] = 0;
    }
    EXPECT_NEAR(fidelity_db(half, white, mask) - fidelity_db(black, white, mask),
                10.0 * std::log10(std::sqrt(0.5)), 1e-9);
    // Only the masked pixels count.
    std::fill(mask.begin(), mask.begin() + 4, 0);
    EXPECT_EQ(fidelity_db(half, white, mask), -INFINITY);
    EXPECT_THROW(fidelity_db(half, white, std::vector<std::uint8_t>(8, 0)), oer::Error);
}

TEST(FrameMetrics, DisplayImageAppliesScaleExposureAndTheTransferFunction) {
    // 0.25 x 2 (scale) x 2 (1 EV) = 1 linear: white without tone mapping; alpha kept.
    const std::vector<float> rgba{0.25f, 0.0f, 0.125f, 0.5f};
    const oer::Rgba8Image image =
        oer::bench::display_image(rgba, 1, 1, 2.0, 1.0, oer::ToneMapper::None);
    EXPECT_EQ(image.pixels[0], 255);
    EXPECT_EQ(image.pixels[1], 0);
    EXPECT_EQ(image.pixels[2], std::uint8_t(std::lround(255.0f * oer::srgb_encode(0.5f))));
    EXPECT_EQ(image.pixels[3], 128);
}

TEST(FrameMetrics, ErrorMapIsRedWhereBrighterBlueWhereDarkerWhiteWhereEqual) {
    const std::vector<double> reference{1.0, 1.0, 1.0, 1.0};
    const std::vector<double> frame{1.0, 1.25, 0.5, 9.0};
    const std::vector<std::uint8_t> mask{1, 1, 1, 0};
    const oer::Rgba8Image map = oer::bench::error_map(frame, reference, mask, 4, 1, 0.5);
    const auto pixel = [&](int i) {
        return std::vector<int>{map.pixels[4 * i], map.pixels[4 * i + 1], map.pixels[4 * i + 2]};
    };
    EXPECT_EQ(pixel(0), (std::vector<int>{255, 255, 255}));
    EXPECT_EQ(pixel(1), (std::vector<int>{255, 128, 128}));  // +25 % of a 50 % full scale
    EXPECT_EQ(pixel(2), (std::vector<int>{0, 0, 255}));      // -50 %: saturated
    EXPECT_EQ(pixel(3), (std::vector<int>{128, 128, 128}));  // outside the mask
}

// PSNR of luma: a uniform difference of 10 (grey 100 against 110) is 10 log10(255^2 / 100);
// equal images are +infinity; pixels outside the mask do not count.
TEST(FrameMetrics, PsnrIsTheLumasPeakSignalToNoiseOverTheMask) {
    const oer::Rgba8Image grey = flat(8, 8, 100, 100, 100), lighter = flat(8, 8, 110, 110, 110);
    const std::vector<std::uint8_t> all(64, 1);
    EXPECT_NEAR(oer::bench::psnr_db(lighter, grey, all), 10.0 * std::log10(255.0 * 255.0 / 100.0),
                1e-9);
    EXPECT_EQ(oer::bench::psnr_db(grey, grey, all), INFINITY);
    oer::Rgba8Image one_off = grey;
    one_off.pixels[0] = 0;  // pixel 0's red: luma 100 - 0.299 x 100
    std::vector<std::uint8_t> but_the_first = all;
    but_the_first[0] = 0;
    EXPECT_EQ(oer::bench::psnr_db(one_off, grey, but_the_first), INFINITY);
    EXPECT_NEAR(oer::bench::psnr_db(one_off, grey, all),
                10.0 * std::log10(255.0 * 255.0 / (29.9 * 29.9 / 64.0)), 1e-9);
    EXPECT_THROW(oer::bench::psnr_db(grey, grey, std::vector<std::uint8_t>(64, 0)), oer::Error);
}

// SSIM: 1 for equal images; a uniform offset leaves only the luminance term,
// (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1); a checkerboard against its inverse (the same
// means and contrasts, the structure reversed) is below 0.
TEST(FrameMetrics, SsimIsWangEtAlsStructuralSimilarity) {
    const oer::Rgba8Image grey = flat(16, 16, 100, 100, 100), lighter = flat(16, 16, 110, 110, 110);
    const std::vector<std::uint8_t> all(256, 1);
    const double c1 = (0.01 * 255.0) * (0.01 * 255.0);
    EXPECT_NEAR(oer::bench::ssim(grey, grey, all), 1.0, 1e-12);
    EXPECT_NEAR(oer::bench::ssim(lighter, grey, all),
                (2.0 * 100.0 * 110.0 + c1) / (100.0 * 100.0 + 110.0 * 110.0 + c1), 1e-9);
    oer::Rgba8Image checker = grey, inverse = grey;
    for (int i = 0; i < 256; ++i) {
        const bool odd = ((i % 16) + (i / 16)) % 2 == 1;
        for (int c = 0; c < 3; ++c) {
            checker.pixels[4 * i + c] = odd ? 200 : 50;
            inverse.pixels[4 * i + c] = odd ? 50 : 200;
        }
    }
    EXPECT_LT(oer::bench::ssim(checker, inverse, all), 0.0);
    EXPECT_NEAR(oer::bench::ssim(checker, checker, all), 1.0, 1e-12);
}

}  // namespace
