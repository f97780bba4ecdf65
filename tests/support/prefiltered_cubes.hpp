#pragma once
// Prefiltered specular cubes (oer/lighting/specular_environment.hpp) made by hand for the GL
// tests, exact by construction: a map of constant radiance L prefilters to L at every level
// and direction, whatever the filter, and a residual map that is black (every non-zero pixel
// the lights') to 0.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/gtc/packing.hpp>
#include <glm/vec3.hpp>

#include "oer/lighting/specular_environment.hpp"

namespace oer::testing {

inline std::shared_ptr<const PrefilteredCube> constant_cube(glm::vec3 radiance, int face_size = 16,
                                                            int levels = 5) {
    auto cube = std::make_shared<PrefilteredCube>();
    cube->face_size = face_size;
    cube->levels = levels;
    const std::uint16_t rgb[3] = {glm::packHalf1x16(radiance.r), glm::packHalf1x16(radiance.g),
                                  glm::packHalf1x16(radiance.b)};
    for (int level = 0; level < levels; ++level) {
        const std::size_t side = std::size_t(face_size >> level);
        std::vector<std::uint16_t>& texels = cube->rgb_half.emplace_back();
        for (std::size_t i = 0; i < 6 * side * side; ++i) {
            texels.insert(texels.end(), rgb, rgb + 3);
        }
    }
    return cube;
}

}  // namespace oer::testing
