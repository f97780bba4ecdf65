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
