#pragma once
// Turns what a user brings (an equirect map, a cube map as six faces or one cross, a
// mirror-ball probe, or nothing: the built-in studio) into one equirect map, with the repair
// counts of its pixels.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "oer/image/image_io.hpp"

namespace oer {

enum class EnvironmentLayout { Equirect, Cross, MirrorBall, CubeFaces };
std::string to_string(EnvironmentLayout layout);
EnvironmentLayout environment_layout_from_string(const std::string& name);  // throws oer::Error

struct EncodedImage {
    std::string name;  // for messages
    std::span<const std::byte> bytes;
};

// images: one encoded image, or six for CubeFaces (+X, -X, +Y, -Y, +Z, -Z). The resampled
// layouts produce an equirect map four face widths (cube) or two ball diameters wide.
LoadedImage decode_environment(std::span<const EncodedImage> images, EnvironmentLayout layout,
                               const ImageLimits& limits);

}  // namespace oer
