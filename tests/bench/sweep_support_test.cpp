// The sweeps' helpers (bench/support/sweep_support.hpp): a wrong truth, a downsampling that
// loses energy or a light mask lost in downsampling would print wrong accuracy figures.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/reference_irradiance.hpp"
#include "sweep_support.hpp"

using namespace oer;

namespace {

// sum(L dOmega) over the map, per channel.
glm::dvec3 radiant_sum(const HdrImage& image) {
    const equirect::Grid grid(image.width, image.height);
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        sum += glm::dvec3(image.rgb(i)) * grid.row_solid_angle[i / std::size_t(image.width)];
    }
    return sum;
}

bench::DiscMap two_lamps(int width, int height) {
    const bench::Disc discs[] = {{30.0, 40.0, 6.0, glm::vec3(50.0f, 40.0f, 30.0f)},
                                 {-100.0, 10.0, 1.2, glm::vec3(5000.0f)}};
    return bench::make_disc_map(width, height, glm::vec3(0.5f, 0.6f, 0.7f), discs);
}

}  // namespace

TEST(SweepSupport, PixelsIrradianceOfEveryPixelIsTheReference) {
    const bench::DiscMap map = two_lamps(64, 32);
    std::vector<std::uint32_t> every(map.image.pixel_count());
    std::iota(every.begin(), every.end(), 0u);
    const std::vector<glm::dvec3> normals = fibonacci_sphere(40);
    const std::vector<glm::dvec3> ours = bench::pixels_irradiance(map.image, every, normals);
    const std::vector<glm::dvec3> reference = ReferenceIrradiance(map.image).at(normals);
    for (std::size_t i = 0; i < normals.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(ours[i][c], reference[i][c], 1e-9 * std::abs(reference[i][c]));
        }
    }
    EXPECT_THROW(
        bench::pixels_irradiance(map.image, std::vector<std::uint32_t>{64u * 32u}, normals), Error);
}

TEST(SweepSupport, DownsamplingKeepsEveryBlocksEnergy) {
    const bench::DiscMap map = two_lamps(128, 64);
    for (const int factor : {1, 2, 4, 8}) {
        const HdrImage reduced = bench::downsample_equirect(map.image, factor);
        EXPECT_EQ(reduced.width, 128 / factor);
        EXPECT_EQ(reduced.height, 64 / factor);
        const glm::dvec3 before = radiant_sum(map.image), after = radiant_sum(reduced);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(after[c], before[c], 1e-6 * before[c]) << "factor " << factor;
        }
    }
    // A uniform map stays uniform (plain means of the blocks would too; the energy check
    // above is what tells them apart).
    HdrImage uniform(16, 8);
    std::fill(uniform.pixels.begin(), uniform.pixels.end(), 2.0f);
    for (const float value : bench::downsample_equirect(uniform, 4).pixels) {
        EXPECT_FLOAT_EQ(value, 2.0f);
    }
    EXPECT_THROW(bench::downsample_equirect(map.image, 3), Error);
    EXPECT_THROW(bench::downsample_equirect(map.image, 0), Error);
}

TEST(SweepSupport, DownsampledMasksKeepEveryLightEvenASmallOne) {
    const bench::DiscMap map = two_lamps(256, 128);
    ASSERT_FALSE(map.disc_pixels[1].empty());
    const auto masks = bench::downsample_light_pixels(map.image, map.disc_pixels, 8);
    ASSERT_EQ(masks.size(), 2u);
    // The small lamp (a few pixels) keeps at least its one block; the big one about its area.
    EXPECT_GE(masks[1].size(), 1u);
    EXPECT_LE(masks[1].size(), 4u);
    EXPECT_GT(masks[0].size(), map.disc_pixels[0].size() / 64);
    // Sorted, inside the reduced map, disjoint, and every block of a small lamp's pixel is its.
    for (const auto& mask : masks) {
        EXPECT_TRUE(std::is_sorted(mask.begin(), mask.end()));
        for (const std::uint32_t block : mask) {
            EXPECT_LT(block, 32u * 16u);
        }
    }
    for (const std::uint32_t block : masks[0]) {
        EXPECT_FALSE(std::binary_search(masks[1].begin(), masks[1].end(), block));
    }
    for (const std::uint32_t pixel : map.disc_pixels[1]) {
        const std::uint32_t block = (pixel / 256 / 8) * 32 + (pixel % 256) / 8;
        EXPECT_TRUE(std::binary_search(masks[1].begin(), masks[1].end(), block));
    }
}

TEST(SweepSupport, IrradianceErrorFigures) {
    const std::vector<glm::dvec3> truth = {glm::dvec3(1.0), glm::dvec3(2.0),
                                           glm::dvec3(4.0, 4.0, 0.0)};
    const std::vector<glm::dvec3> approx = {glm::dvec3(1.0), glm::dvec3(2.0, 2.0, 1.0),
                                            glm::dvec3(4.0, 4.0, -0.5)};
    const bench::IrradianceError error = bench::irradiance_error(approx, truth);
    // Differences: 0, (0, 0, 1), (0, 0, 0.5); |truth|^2 = 3 + 12 + 32.
    EXPECT_NEAR(error.relative_rms, std::sqrt(1.25 / 47.0), 1e-12);
    EXPECT_NEAR(error.max_relative, 1.0 / std::sqrt(12.0), 1e-12);
    // Blue: smallest approximation -0.5, largest truth 2.
    EXPECT_NEAR(error.most_negative, -0.25, 1e-12);
    EXPECT_EQ(bench::irradiance_error(truth, truth).most_negative, 0.0);
    EXPECT_EQ(bench::irradiance_error(truth, truth).relative_rms, 0.0);
    EXPECT_THROW(bench::irradiance_error(approx, std::vector<glm::dvec3>(2)), Error);
}

TEST(SweepSupport, ParetoFrontKeepsOnlyTheUndominated) {
    const std::vector<double> time = {1.0, 2.0, 3.0, 0.5, 2.0, 4.0};
    const std::vector<double> error = {0.5, 0.2, 0.3, 0.9, 0.2, 0.1};
    // 2 is dominated by 1; 4 equals 1 (the first is kept); sorted by time.
    EXPECT_EQ(bench::pareto_front(time, error), (std::vector<std::size_t>{3, 0, 1, 5}));
    EXPECT_THROW(bench::pareto_front(time, std::vector<double>(2)), Error);
}

TEST(SweepSupport, CsvFieldsQuoteOnlyWhatNeedsIt) {
    EXPECT_EQ(bench::csv_field("city"), "city");
    EXPECT_EQ(bench::csv_field("a,b"), "\"a,b\"");
    EXPECT_EQ(bench::csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
}
