#include <gtest/gtest.h>

#include <cmath>

#include "oer/core/error.hpp"
#include "oer/lighting/tonemap.hpp"

using namespace oer;

TEST(Tonemap, SrgbTransferFunctionRoundTripsAndHitsKnownPoints) {
    EXPECT_NEAR(srgb_encode(0.5f), 0.735357f, 1e-5);
    EXPECT_NEAR(srgb_encode(0.002f), 0.002f * 12.92f, 1e-7);
    EXPECT_FLOAT_EQ(srgb_encode(1.0f), 1.0f);
    for (float v = 0.0f; v <= 1.0f; v += 0.01f) {
        EXPECT_NEAR(srgb_decode(srgb_encode(v)), v, 1e-5);
    }
}

TEST(Tonemap, NeutralLeavesMidtonesAlmostLinear) {
    // Khronos PBR Neutral: below the compression start only the 0.04 toe offset applies.
    const glm::vec3 mapped = tone_map(glm::vec3(0.5f), ToneMapper::Neutral);
    EXPECT_NEAR(mapped.r, 0.46f, 1e-6);
    // Above it, highlights are compressed into [0, 1] and stay ordered.
    float previous = 0.0f;
    for (float v = 0.8f; v < 100.0f; v *= 1.5f) {
        const float m = tone_map(glm::vec3(v), ToneMapper::Neutral).r;
        EXPECT_GT(m, previous);
        EXPECT_LE(m, 1.0f);
        previous = m;
    }
}

TEST(Tonemap, AcesIsMonotoneAndBounded) {
    float previous = -1.0f;
    for (float v = 0.0f; v < 50.0f; v += 0.25f) {
        const float m = tone_map(glm::vec3(v), ToneMapper::Aces).g;
        EXPECT_GE(m, previous);
        EXPECT_LE(m, 1.0f);
        previous = m;
    }
    EXPECT_NEAR(tone_map(glm::vec3(0.0f), ToneMapper::Aces).r, 0.0f, 1e-3);
}

TEST(Tonemap, AcesMatchesHillsPublishedFitAtKnownPoints) {
    // Stephen Hill's fit of the ACES RRT + ODT (BakingLab, ACES.hlsl, 2016: input matrix,
    // RRTAndODTFit, output matrix), evaluated in double outside this code base (Python) at a
    // few inputs, then clamped to [0, 1]. A plain clamp would give the input back; Narkowicz's
    // 2015 curve gives 0.267 at 0.18; the matrices move energy between channels, as only this
    // fit does for a saturated red.
    struct Point {
        glm::vec3 input;
        glm::vec3 expected;
    };
    const Point points[] = {
        {glm::vec3(0.18f), {0.105591f, 0.105591f, 0.105590f}},
        {glm::vec3(1.0f), {0.619115f, 0.619115f, 0.619109f}},
        {glm::vec3(4.0f), {0.909014f, 0.909014f, 0.909005f}},
        {{1.0f, 0.0f, 0.0f}, {0.688028f, 0.0f, 0.002639f}},
        {{0.2f, 0.1f, 0.05f}, {0.112009f, 0.043360f, 0.016843f}},
    };
    for (const Point& point : points) {
        const glm::vec3 mapped = tone_map(point.input, ToneMapper::Aces);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(mapped[c], point.expected[c], 2e-6)
                << "channel " << c << " of (" << point.input.r << ", " << point.input.g << ", "
                << point.input.b << ")";
        }
    }
}

TEST(Tonemap, NoneClampsOnly) {
    const glm::vec3 mapped = tone_map({0.25f, 2.0f, -1.0f}, ToneMapper::None);
    EXPECT_FLOAT_EQ(mapped.r, 0.25f);
    EXPECT_FLOAT_EQ(mapped.g, 1.0f);
    EXPECT_FLOAT_EQ(mapped.b, 0.0f);
}

TEST(Tonemap, NamesRoundTripAndUnknownIsAnError) {
    for (const ToneMapper mapper : {ToneMapper::Neutral, ToneMapper::Aces, ToneMapper::None}) {
        EXPECT_EQ(tone_mapper_from_string(to_string(mapper)), mapper);
    }
    EXPECT_THROW(tone_mapper_from_string("filmic"), Error);
}

TEST(Tonemap, ToDisplayAppliesExposureInStops) {
    HdrImage image(1, 1);
    image.set(0, glm::vec3(0.125f));
    const HdrImage display = to_display(image, 2.0, ToneMapper::None);
    EXPECT_NEAR(display.rgb(0).r, srgb_encode(0.5f), 1e-6);
}

TEST(Tonemap, ThesisToneMapNormalisesToOneAndKeepsOrder) {
    HdrImage image(4, 1);
    image.set(0, glm::vec3(0.0f));
    image.set(1, glm::vec3(0.1f));
    image.set(2, glm::vec3(1.0f));
    image.set(3, glm::vec3(1000.0f, 500.0f, 10.0f));
    const HdrImage mapped = thesis_tone_map(image);
    EXPECT_FLOAT_EQ(mapped.rgb(3).r, 1.0f);
    EXPECT_FLOAT_EQ(mapped.rgb(0).g, 0.0f);
    EXPECT_LT(mapped.rgb(1).g, mapped.rgb(2).g);
    EXPECT_LT(mapped.rgb(2).g, mapped.rgb(3).g);
    const HdrImage black = thesis_tone_map(HdrImage(3, 2));
    for (float v : black.pixels) {
        EXPECT_EQ(v, 0.0f);
    }
}

TEST(Tonemap, ThesisToneMapUsesKeyPoint18OverTheLogAverageLuminance) {
    // Three pixels whose luminances without the 179 (0.265 R + 0.670 G + 0.065 B, the thesis's
    // eq. 3.1) are 0.5, 2 and 1: the log-average is (0.5 * 2 * 1)^(1/3) = 1 (the arithmetic
    // mean would be 7/6), so Reinhard's scale is 0.18 / 1 and L / (1 + L) gives, per channel,
    //   grey 0.5: 0.09 / 1.09,   grey 2: 0.36 / 1.36,   red: (0.18 / 0.265) / (1 + 0.18 / 0.265),
    // and the red pixel's 0.404494 is the largest, by which everything is divided.
    HdrImage image(3, 1);
    image.set(0, glm::vec3(0.5f));
    image.set(1, glm::vec3(2.0f));
    image.set(2, glm::vec3(1.0f / 0.265f, 0.0f, 0.0f));
    const HdrImage mapped = thesis_tone_map(image);
    const double red = (0.18 / 0.265) / (1.0 + 0.18 / 0.265);
    // The 1e-6 that keeps log() away from 0 moves the log-average by about 1e-6.
    constexpr double tolerance = 1e-5;
    EXPECT_NEAR(mapped.rgb(0).g, (0.09 / 1.09) / red, tolerance);  // 0.204128
    EXPECT_NEAR(mapped.rgb(1).g, (0.36 / 1.36) / red, tolerance);  // 0.654412
    EXPECT_NEAR(mapped.rgb(2).r, 1.0, tolerance);
    EXPECT_NEAR(mapped.rgb(2).g, 0.0, tolerance);
    // Brighter by a factor 10: the same image (the key over the log-average is scale-free, up to
    // the 1e-6).
    HdrImage brighter = image;
    for (float& value : brighter.pixels) {
        value *= 10.0f;
    }
    const HdrImage mapped_brighter = thesis_tone_map(brighter);
    for (std::size_t i = 0; i < mapped.pixels.size(); ++i) {
        EXPECT_NEAR(mapped_brighter.pixels[i], mapped.pixels[i], tolerance) << i;
    }
}
