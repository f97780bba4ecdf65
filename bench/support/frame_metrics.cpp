#include "frame_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/vec3.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/light_location.hpp"

namespace oer::bench {
namespace {

void check_sizes(std::size_t a, std::size_t b, std::size_t mask, const char* what) {
    if (a != b || a != mask) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": sizes differ (" +
                                                 std::to_string(a) + ", " + std::to_string(b) +
                                                 ", mask " + std::to_string(mask) + ")");
    }
}

double yiq_y(double r, double g, double b) {
    return r * 0.29889531 + g * 0.58662247 + b * 0.11448223;
}
double yiq_i(double r, double g, double b) {
    return r * 0.59597799 - g * 0.27417610 - b * 0.32180189;
}
double yiq_q(double r, double g, double b) {
    return r * 0.21147017 - g * 0.52261711 + b * 0.31114694;
}
// pixelmatch blends a translucent pixel over white.
double over_white(std::uint8_t channel, double alpha) {
    return 255.0 + (double(channel) - 255.0) * alpha;
}

}  // namespace

std::vector<double> frame_luminance(std::span<const float> rgba) {
    std::vector<double> out(rgba.size() / 4);
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = luminance(glm::dvec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]));
    }
    return out;
}

double masked_mean(std::span<const double> values, std::span<const std::uint8_t> mask) {
    check_sizes(values.size(), values.size(), mask.size(), "masked_mean");
    double sum = 0.0;
    std::size_t selected = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) {
            sum += values[i];
            ++selected;
        }
    }
    return selected > 0 ? sum / double(selected) : 0.0;
}

double relative_rms_error(std::span<const double> luminance, std::span<const double> reference,
                          std::span<const std::uint8_t> mask) {
    check_sizes(luminance.size(), reference.size(), mask.size(), "relative_rms_error");
    double difference = 0.0, truth = 0.0;
    std::size_t selected = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) {
            difference += (luminance[i] - reference[i]) * (luminance[i] - reference[i]);
            truth += reference[i] * reference[i];
            ++selected;
        }
    }
    if (selected == 0 || !(truth > 0.0)) {
        throw Error(ErrorKind::InvalidInput,
                    "relative_rms_error: " + std::string(selected == 0 ? "no pixel selected"
                                                                       : "the reference is black"));
    }
    return std::sqrt(difference / truth);
}

double relative_noise(std::span<const double> noise, std::span<const double> reference,
                      std::span<const std::uint8_t> mask) {
    check_sizes(noise.size(), reference.size(), mask.size(), "relative_noise");
    double squared_noise = 0.0, truth = 0.0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) {
            squared_noise += noise[i] * noise[i];
            truth += reference[i] * reference[i];
        }
    }
    return truth > 0.0 ? std::sqrt(squared_noise / truth) : 0.0;
}

namespace {

void check_grid(std::size_t size, const BlockGrid& grid, const char* what) {
    if (grid.width <= 0 || grid.height <= 0 || grid.block <= 0 ||
        size != std::size_t(grid.width) * std::size_t(grid.height)) {
        throw Error(ErrorKind::InvalidInput,
                    std::string(what) + ": " + std::to_string(size) + " values for " +
                        std::to_string(grid.width) + "x" + std::to_string(grid.height) +
                        " pixels in blocks of " + std::to_string(grid.block));
    }
}

// Calls `visit(block index, pixel index)` for every pixel of every whole block.
template <typename Visit>
void for_each_block_pixel(const BlockGrid& grid, Visit&& visit) {
    for (std::size_t row = 0; row < grid.rows(); ++row) {
        for (std::size_t column = 0; column < grid.columns(); ++column) {
            const std::size_t block_index = row * grid.columns() + column;
            for (int dy = 0; dy < grid.block; ++dy) {
                for (int dx = 0; dx < grid.block; ++dx) {
                    const std::size_t y = row * std::size_t(grid.block) + std::size_t(dy);
                    const std::size_t x = column * std::size_t(grid.block) + std::size_t(dx);
                    visit(block_index, y * std::size_t(grid.width) + x);
                }
            }
        }
    }
}

}  // namespace

std::vector<double> block_means(std::span<const double> values, const BlockGrid& grid) {
    check_grid(values.size(), grid, "block_means");
    std::vector<double> means(grid.columns() * grid.rows(), 0.0);
    for_each_block_pixel(
        grid, [&](std::size_t block, std::size_t pixel) { means[block] += values[pixel]; });
    const double pixels = double(grid.block) * double(grid.block);
    for (double& mean : means) {
        mean /= pixels;
    }
    return means;
}

std::vector<std::uint8_t> whole_blocks(std::span<const std::uint8_t> mask, const BlockGrid& grid) {
    check_grid(mask.size(), grid, "whole_blocks");
    std::vector<std::uint8_t> whole(grid.columns() * grid.rows(), 1);
    for_each_block_pixel(grid, [&](std::size_t block, std::size_t pixel) {
        whole[block] = whole[block] != 0 && mask[pixel] != 0 ? 1 : 0;
    });
    return whole;
}

std::vector<double> block_noise(std::span<const double> noise, const BlockGrid& grid) {
    check_grid(noise.size(), grid, "block_noise");
    std::vector<double> squares(grid.columns() * grid.rows(), 0.0);
    for_each_block_pixel(grid, [&](std::size_t block, std::size_t pixel) {
        squares[block] += noise[pixel] * noise[pixel];
    });
    const double pixels = double(grid.block) * double(grid.block);
    for (double& square : squares) {
        square = std::sqrt(square) / pixels;
    }
    return squares;
}

double least_squares_scale(std::span<const double> luminance, std::span<const double> reference,
                           std::span<const std::uint8_t> mask) {
    check_sizes(luminance.size(), reference.size(), mask.size(), "least_squares_scale");
    double cross = 0.0, square = 0.0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) {
            cross += luminance[i] * reference[i];
            square += luminance[i] * luminance[i];
        }
    }
    if (!(square > 0.0)) {
        throw Error(ErrorKind::InvalidInput, "least_squares_scale: the frame is black there");
    }
    return cross / square;
}

double yiq_delta(const std::uint8_t* a, const std::uint8_t* b) {
    const double alpha_a = a[3] / 255.0, alpha_b = b[3] / 255.0;
    const double r1 = over_white(a[0], alpha_a), g1 = over_white(a[1], alpha_a),
                 b1 = over_white(a[2], alpha_a);
    const double r2 = over_white(b[0], alpha_b), g2 = over_white(b[1], alpha_b),
                 b2 = over_white(b[2], alpha_b);
    const double y = yiq_y(r1, g1, b1) - yiq_y(r2, g2, b2);
    const double i = yiq_i(r1, g1, b1) - yiq_i(r2, g2, b2);
    const double q = yiq_q(r1, g1, b1) - yiq_q(r2, g2, b2);
    return 0.5053 * y * y + 0.299 * i * i + 0.1957 * q * q;
}

double fidelity_db(const Rgba8Image& image, const Rgba8Image& reference,
                   std::span<const std::uint8_t> mask) {
    check_sizes(image.pixels.size() / 4, reference.pixels.size() / 4, mask.size(), "fidelity_db");
    double square_sum = 0.0;
    std::size_t selected = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) {
            const double delta = yiq_delta(&image.pixels[4 * i], &reference.pixels[4 * i]);
            square_sum += delta * delta;
            ++selected;
        }
    }
    if (selected == 0) {
        throw Error(ErrorKind::InvalidInput, "fidelity_db: no pixel selected");
    }
    const double ratio = std::sqrt(square_sum / double(selected)) / kMaxYiqDelta;
    return ratio > 0.0 ? 10.0 * std::log10(ratio) : -std::numeric_limits<double>::infinity();
}

namespace {

// The luma of each pixel of an 8-bit sRGB image (psnr_db, ssim).
std::vector<double> luma(const Rgba8Image& image) {
    std::vector<double> out(image.pixels.size() / 4);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const std::uint8_t* p = &image.pixels[4 * i];
        out[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
    }
    return out;
}

void check_images(const Rgba8Image& image, const Rgba8Image& reference,
                  std::span<const std::uint8_t> mask, const char* what) {
    if (image.width != reference.width || image.height != reference.height) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": images of different sizes");
    }
    check_sizes(image.pixels.size() / 4, reference.pixels.size() / 4, mask.size(), what);
    if (std::none_of(mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; })) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": no pixel selected");
    }
}

}  // namespace

double psnr_db(const Rgba8Image& image, const Rgba8Image& reference,
               std::span<const std::uint8_t> mask) {
    check_images(image, reference, mask, "psnr_db");
    const std::vector<double> a = luma(image), b = luma(reference);
    double square_sum = 0.0;
    std::size_t selected = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) {
            square_sum += (a[i] - b[i]) * (a[i] - b[i]);
            ++selected;
        }
    }
    const double mean_square = square_sum / double(selected);
    return mean_square > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mean_square)
                             : std::numeric_limits<double>::infinity();
}

double ssim(const Rgba8Image& image, const Rgba8Image& reference,
            std::span<const std::uint8_t> mask) {
    check_images(image, reference, mask, "ssim");
    const std::vector<double> a = luma(image), b = luma(reference);
    constexpr int kRadius = 5;
    constexpr double kSigma = 1.5;
    const double c1 = (0.01 * 255.0) * (0.01 * 255.0), c2 = (0.03 * 255.0) * (0.03 * 255.0);
    double weights[2 * kRadius + 1];
    for (int k = -kRadius; k <= kRadius; ++k) {
        weights[k + kRadius] = std::exp(-0.5 * k * k / (kSigma * kSigma));
    }
    const int width = image.width, height = image.height;
    double sum = 0.0;
    std::size_t selected = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
            if (mask[i] == 0) {
                continue;
            }
            double w_sum = 0.0, mean_a = 0.0, mean_b = 0.0;
            double square_a = 0.0, square_b = 0.0, product = 0.0;
            for (int dy = -kRadius; dy <= kRadius; ++dy) {
                const int wy = y + dy;
                if (wy < 0 || wy >= height) {
                    continue;
                }
                for (int dx = -kRadius; dx <= kRadius; ++dx) {
                    const int wx = x + dx;
                    if (wx < 0 || wx >= width) {
                        continue;
                    }
                    const double w = weights[dy + kRadius] * weights[dx + kRadius];
                    const std::size_t j = std::size_t(wy) * std::size_t(width) + std::size_t(wx);
                    w_sum += w;
                    mean_a += w * a[j];
                    mean_b += w * b[j];
                    square_a += w * a[j] * a[j];
                    square_b += w * b[j] * b[j];
                    product += w * a[j] * b[j];
                }
            }
            mean_a /= w_sum;
            mean_b /= w_sum;
            const double variance_a = square_a / w_sum - mean_a * mean_a;
            const double variance_b = square_b / w_sum - mean_b * mean_b;
            const double covariance = product / w_sum - mean_a * mean_b;
            sum += (2.0 * mean_a * mean_b + c1) * (2.0 * covariance + c2) /
                   ((mean_a * mean_a + mean_b * mean_b + c1) * (variance_a + variance_b + c2));
            ++selected;
        }
    }
    return sum / double(selected);
}

Rgba8Image display_image(std::span<const float> rgba, int width, int height, double scale,
                         double exposure, ToneMapper mapper) {
    HdrImage linear(width, height);
    for (std::size_t i = 0; i < linear.pixel_count(); ++i) {
        linear.set(i, glm::vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]) * float(scale));
    }
    const HdrImage display = to_display(linear, exposure, mapper);
    Rgba8Image out{width, height, std::vector<std::uint8_t>(linear.pixel_count() * 4)};
    for (std::size_t i = 0; i < linear.pixel_count(); ++i) {
        const glm::vec3 rgb = display.rgb(i);
        for (int c = 0; c < 3; ++c) {
            out.pixels[4 * i + c] =
                std::uint8_t(std::lround(255.0f * std::clamp(rgb[c], 0.0f, 1.0f)));
        }
        out.pixels[4 * i + 3] =
            std::uint8_t(std::lround(255.0f * std::clamp(rgba[4 * i + 3], 0.0f, 1.0f)));
    }
    return out;
}

Rgba8Image error_map(std::span<const double> luminance, std::span<const double> reference,
                     std::span<const std::uint8_t> mask, int width, int height, double full_scale) {
    check_sizes(luminance.size(), reference.size(), mask.size(), "error_map");
    const double mean = masked_mean(reference, mask);
    Rgba8Image out{width, height, std::vector<std::uint8_t>(mask.size() * 4, 255)};
    for (std::size_t i = 0; i < mask.size(); ++i) {
        std::uint8_t* pixel = &out.pixels[4 * i];
        if (mask[i] == 0 || !(mean > 0.0)) {
            pixel[0] = pixel[1] = pixel[2] = 128;
            continue;
        }
        const double relative =
            std::clamp((luminance[i] - reference[i]) / (mean * full_scale), -1.0, 1.0);
        // White at 0, towards red (brighter) or blue (darker): the other channels fall.
        const auto fall = std::uint8_t(std::lround(255.0 * (1.0 - std::abs(relative))));
        if (relative >= 0.0) {
            pixel[1] = pixel[2] = fall;
        } else {
            pixel[0] = pixel[1] = fall;
        }
    }
    return out;
}

}  // namespace oer::bench
