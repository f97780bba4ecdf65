#pragma once
// Frames of the rasteriser against the reference renderer's (renderer/reference), by luminance.
#include <cmath>
#include <cstddef>
#include <vector>

#include "oer/reference/reference_renderer.hpp"

namespace oer::testing {

// Rec. 709 luminance of an RGBA pixel.
inline double luminance(const float* rgba) {
    return 0.2126 * rgba[0] + 0.7152 * rgba[1] + 0.0722 * rgba[2];
}

// Relative RMS of luminance, sqrt(sum (ours - truth)^2 / sum truth^2), over the means of the
// kBlock x kBlock blocks of pixels whose centres the reference all sees as `surface`: a block's
// mean has a kBlock-th of a pixel's Monte Carlo noise (the reference's pixels are independent),
// so the reference is brute force at a tolerable number of samples.
inline constexpr int kBlock = 4;
inline double block_relative_rms(const std::vector<float>& ours, const ReferenceFrame& truth,
                                 ReferenceSurface surface) {
    double error = 0.0, total = 0.0;
    for (int by = 0; by + kBlock <= truth.height; by += kBlock) {
        for (int bx = 0; bx + kBlock <= truth.width; bx += kBlock) {
            double expected = 0.0, got = 0.0;
            bool whole = true;
            for (int y = by; y < by + kBlock; ++y) {
                for (int x = bx; x < bx + kBlock; ++x) {
                    const std::size_t i =
                        std::size_t(y) * std::size_t(truth.width) + std::size_t(x);
                    whole = whole && truth.surfaces[i] == surface;
                    expected += luminance(&truth.linear[4 * i]);
                    got += luminance(&ours[4 * i]);
                }
            }
            if (whole) {
                error += (got - expected) * (got - expected);
                total += expected * expected;
            }
        }
    }
    return std::sqrt(error / total);
}

}  // namespace oer::testing
