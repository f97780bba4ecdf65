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
// block x block blocks of pixels whose centres the reference all sees as `surface`: a block's
// mean of kBlock^2 pixels has a kBlock-th of a pixel's Monte Carlo noise (the reference's pixels
// are independent), so the reference is brute force at a tolerable number of samples. A block
// of 1 compares pixels, for what lies within one (a mirror's image of a small light).
inline constexpr int kBlock = 4;
inline double block_relative_rms(const std::vector<float>& ours, const ReferenceFrame& truth,
                                 ReferenceSurface surface, int block = kBlock) {
    double error = 0.0, total = 0.0;
    for (int by = 0; by + block <= truth.height; by += block) {
        for (int bx = 0; bx + block <= truth.width; bx += block) {
            double expected = 0.0, got = 0.0;
            bool whole = true;
            for (int y = by; y < by + block; ++y) {
                for (int x = bx; x < bx + block; ++x) {
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
