#pragma once
// How far a rendered frame is from the reference renderer's (the frame sweep): the
// relative RMS of luminance and the render-fidelity metric of model-viewer and the Khronos
// glTF Render Fidelity project, each over a set of pixels (the product's, or the ground's),
// and the images the report shows (display-referred frames and a signed error map).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "oer/core/image.hpp"
#include "oer/lighting/tonemap.hpp"

namespace oer::bench {

// Luminance (docs/design.md section 2's, light_location.hpp's luminance, as the reference
// renderer's noise estimate uses) of each pixel of an RGBA linear frame (Frame::linear's layout).
std::vector<double> frame_luminance(std::span<const float> rgba);

// The mean of the values whose mask entry is set; 0 when none is (sizes must match, else
// oer::Error InvalidInput).
double masked_mean(std::span<const double> values, std::span<const std::uint8_t> mask);

// sqrt(sum (Y - Y_ref)^2 / sum Y_ref^2) over the pixels whose mask entry is set: the reference
// renderer's noise measure (ReferenceNoise), so that noise and error compare directly. Sizes
// must match, at least one pixel must be selected and the reference must not be black there
// (else oer::Error InvalidInput).
double relative_rms_error(std::span<const double> luminance, std::span<const double> reference,
                          std::span<const std::uint8_t> mask);

// sqrt(sum noise^2 / sum Y_ref^2) over the pixels whose mask entry is set: the reference
// renderer's relative noise (ReferenceNoise) over any set of pixels, from its per-pixel noise
// (ReferenceFrame::luminance_noise). 0 when no pixel is selected or the reference is black
// there; sizes must match (else oer::Error InvalidInput).
double relative_noise(std::span<const double> noise, std::span<const double> reference,
                      std::span<const std::uint8_t> mask);

// The frame sweep compares lighting over square blocks of pixels, not pixel by pixel: inside
// a product, thin geometry (the engine's fins) makes edges whose pixels measure how a renderer
// integrates the pixel (ours its supersamples, the reference random points), not its light,
// and a block's mean has a block-th of a pixel's Monte Carlo noise (the reference's pixels are
// independent). Lighting error is of low frequency: a block's mean keeps it. The blocks tile
// the image from its top-left corner; a partial block at the right or bottom edge is left out.
struct BlockGrid {
    int width = 0, height = 0;  // the image's, in pixels
    int block = 1;              // a block's side, in pixels
    std::size_t columns() const { return std::size_t(width / block); }
    std::size_t rows() const { return std::size_t(height / block); }
};

// Per block, the mean of its pixels' values (row-major, grid.columns() x grid.rows()).
std::vector<double> block_means(std::span<const double> values, const BlockGrid& grid);

// Per block, 1 where every pixel of the block is selected by `mask`, else 0.
std::vector<std::uint8_t> whole_blocks(std::span<const std::uint8_t> mask, const BlockGrid& grid);

// Per block, the standard deviation of its mean from the pixels' independent ones:
// sqrt(sum noise^2) / block^2.
std::vector<double> block_noise(std::span<const double> noise, const BlockGrid& grid);

// The factor s minimising sum (s Y - Y_ref)^2 over the mask: s = sum Y Y_ref / sum Y^2. For a
// frame with no absolute scale (the thesis model's display-referred lighting). oer::Error
// (InvalidInput) when the frame is black over the mask.
double least_squares_scale(std::span<const double> luminance, std::span<const double> reference,
                           std::span<const std::uint8_t> mask);

// The colour difference of pixelmatch (Y. Kotsarenko, F. Ramos, "Measuring perceived color
// difference using YIQ NTSC transmission color space in mobile applications", 2010), as
// model-viewer's render-fidelity tools use it (packages/render-fidelity-tools, common.ts and
// third_party/pixelmatch/color-delta.ts): per pixel of two 8-bit sRGB images, alpha-blended
// over white, delta = 0.5053 dY^2 + 0.299 dI^2 + 0.1957 dQ^2; then sqrt(mean delta^2) over
// the pixels, divided by the largest possible delta (35215, black against white), in decibels
// (10 log10). model-viewer's fidelity test fails a renderer above -22 dB. -infinity for equal
// images. Sizes must match and a pixel must be selected (else oer::Error InvalidInput).
inline constexpr double kMaxYiqDelta = 35215.0;
inline constexpr double kFidelityFailDb = -22.0;
double yiq_delta(const std::uint8_t* a, const std::uint8_t* b);  // RGBA, 4 bytes each
double fidelity_db(const Rgba8Image& image, const Rgba8Image& reference,
                   std::span<const std::uint8_t> mask);

// The Khronos 3D Commerce certification's measures of a render against a reference, on the
// 8-bit sRGB images' luma (Y' = 0.299 R' + 0.587 G' + 0.114 B', of 0 to 255):
// PSNR, 10 log10(255^2 / mean squared difference) over the masked pixels, in dB (+infinity for
// equal images); and SSIM (Z. Wang, A. C. Bovik, H. R. Sheikh and E. P. Simoncelli, "Image
// Quality Assessment: From Error Visibility to Structural Similarity", IEEE TIP 2004): the
// mean over the masked pixels of
//   (2 mu_a mu_b + C1)(2 sigma_ab + C2) / ((mu_a^2 + mu_b^2 + C1)(sigma_a^2 + sigma_b^2 + C2))
// in an 11 x 11 Gaussian window of sigma 1.5 about the pixel (clipped at the image's edges,
// renormalised), C1 = (0.01 255)^2, C2 = (0.03 255)^2: 1 for equal images. Sizes must match and
// a pixel must be selected (else oer::Error InvalidInput).
double psnr_db(const Rgba8Image& image, const Rgba8Image& reference,
               std::span<const std::uint8_t> mask);
double ssim(const Rgba8Image& image, const Rgba8Image& reference,
            std::span<const std::uint8_t> mask);

// An RGBA linear frame (alpha the coverage) to 8-bit sRGB through the service's display
// transform (exposure, tone mapper, sRGB), each pixel's radiance first multiplied by `scale`.
Rgba8Image display_image(std::span<const float> rgba, int width, int height, double scale,
                         double exposure, ToneMapper mapper);

// The signed luminance error of the masked pixels as colour: (Y - Y_ref) / mean Y_ref over the
// mask, blue where the frame is darker than the reference, red where brighter, white where
// equal, saturated at +-full_scale; pixels outside the mask mid grey.
Rgba8Image error_map(std::span<const double> luminance, std::span<const double> reference,
                     std::span<const std::uint8_t> mask, int width, int height, double full_scale);

}  // namespace oer::bench
