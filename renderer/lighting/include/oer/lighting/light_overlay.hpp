#pragma once
// A picture of where the lights are: each light's mask outlined in its own color and
// numbered (1-based, the order of the rig), drawn over a display-referred image of the map.
#include <vector>

#include "oer/core/image.hpp"
#include "oer/lighting/light_location.hpp"

namespace oer {

// display: an sRGB image in [0, 1] of the same size as the map the lights were found in.
HdrImage draw_light_overlay(const HdrImage& display, const std::vector<Light>& lights);

}  // namespace oer
