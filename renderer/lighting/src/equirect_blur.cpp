#include "equirect_blur.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "large_buffer.hpp"
#include "oer/core/error.hpp"
#include "oer/core/image.hpp"
#include "oer/lighting/light_location.hpp"

namespace oer {
namespace detail {

std::vector<float> gaussian_kernel(double radius) {
    if (!std::isfinite(radius) || radius < 0.0 || radius > max_blur_radius) {
        std::ostringstream message;
        message << "blur radius " << radius << " is outside [0, " << max_blur_radius << "] pixels";
        throw Error(ErrorKind::InvalidInput, message.str());
    }
    const int half = int(std::ceil(radius));
    if (half == 0) {
        return {1.0f};
    }
    const double sigma = radius / 2.0;
    std::vector<double> taps(std::size_t(2 * half + 1));
    double sum = 0.0;
    for (int k = -half; k <= half; ++k) {
        const double w = std::exp(-double(k) * k / (2.0 * sigma * sigma));
        taps[std::size_t(k + half)] = w;
        sum += w;
    }
    std::vector<float> kernel(taps.size());
    for (std::size_t i = 0; i < taps.size(); ++i) {
        kernel[i] = float(taps[i] / sum);
    }
    return kernel;
}

namespace {

// out[x] = sum over t of weights[t] * sources[t][x], for x in [0, n). Blocks of 16 outputs
// accumulate in registers over all taps (one load per tap and output, one store per output);
// every output adds its taps in the same order, so a constant image stays exactly constant.
void weighted_sum(const float* const* sources, const float* weights, std::size_t taps,
                  float* __restrict out, std::size_t n) {
    constexpr std::size_t block = 16;
    std::size_t x = 0;
    for (; x + block <= n; x += block) {
        float acc[block];
        const float w0 = weights[0];
        const float* __restrict s0 = sources[0] + x;
        for (std::size_t j = 0; j < block; ++j) {
            acc[j] = w0 * s0[j];
        }
        for (std::size_t t = 1; t < taps; ++t) {
            const float w = weights[t];
            const float* __restrict s = sources[t] + x;
            for (std::size_t j = 0; j < block; ++j) {
                acc[j] += w * s[j];
            }
        }
        for (std::size_t j = 0; j < block; ++j) {
            out[x + j] = acc[j];
        }
    }
    for (; x < n; ++x) {
        float acc = weights[0] * sources[0][x];
        for (std::size_t t = 1; t < taps; ++t) {
            acc += weights[t] * sources[t][x];
        }
        out[x] = acc;
    }
}

}  // namespace

void blur_equirect_in_place(float* values, int width, int height, double radius, float* scratch) {
    const std::vector<float> kernel = gaussian_kernel(radius);
    const std::size_t w = std::size_t(std::max(width, 0));
    const std::size_t h = std::size_t(std::max(height, 0));
    if (kernel.size() == 1 || w == 0 || h == 0) {
        return;
    }
    const std::size_t taps = kernel.size();
    const std::size_t half = taps / 2;
    std::vector<const float*> sources(taps);

    // Horizontal: each row is copied into a padded row that wraps around (x modulo width, so
    // that kernels wider than the row work too), then convolved into scratch.
    std::vector<float> padded(w + taps - 1);
    for (std::size_t t = 0; t < taps; ++t) {
        sources[t] = padded.data() + t;
    }
    for (std::size_t y = 0; y < h; ++y) {
        const float* row = values + y * w;
        std::size_t source = (w - half % w) % w;  // (-half) modulo w
        for (float& p : padded) {
            p = row[source];
            if (++source == w) {
                source = 0;
            }
        }
        weighted_sum(sources.data(), kernel.data(), taps, scratch + y * w, w);
    }

    // Vertical: rows beyond the poles clamp to the first and last row.
    for (std::size_t y = 0; y < h; ++y) {
        for (std::size_t t = 0; t < taps; ++t) {
            const std::size_t row = std::min(h - 1, (y + t >= half) ? y + t - half : 0);
            sources[t] = scratch + row * w;
        }
        weighted_sum(sources.data(), kernel.data(), taps, values + y * w, w);
    }
}

}  // namespace detail

HdrImage blur_equirect(const HdrImage& image, double radius) {
    if (image.width <= 0 || image.height <= 0 || image.pixels.size() != image.pixel_count() * 3) {
        throw Error(ErrorKind::InvalidInput,
                    "blur_equirect: image is empty or its pixel buffer does not match its size");
    }
    const std::size_t n = image.pixel_count();
    detail::gaussian_kernel(radius);  // validates before anything is allocated
    HdrImage result(image.width, image.height);
    detail::LargeBuffer<float> channel(n), scratch(n);
    for (int c = 0; c < 3; ++c) {
        for (std::size_t i = 0; i < n; ++i) {
            channel[i] = image.pixels[i * 3 + std::size_t(c)];
        }
        detail::blur_equirect_in_place(channel.data(), image.width, image.height, radius,
                                       scratch.data());
        for (std::size_t i = 0; i < n; ++i) {
            result.pixels[i * 3 + std::size_t(c)] = channel[i];
        }
    }
    return result;
}

std::vector<float> blur_equirect_channel(const std::vector<float>& values, int width, int height,
                                         double radius) {
    if (width <= 0 || height <= 0 || values.size() != std::size_t(width) * std::size_t(height)) {
        throw Error(ErrorKind::InvalidInput,
                    "blur_equirect_channel: image is empty or its buffer does not match its size");
    }
    detail::gaussian_kernel(radius);  // validates before anything is allocated
    std::vector<float> result = values;
    detail::LargeBuffer<float> scratch(values.size());
    detail::blur_equirect_in_place(result.data(), width, height, radius, scratch.data());
    return result;
}

}  // namespace oer
