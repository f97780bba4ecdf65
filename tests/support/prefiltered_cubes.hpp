#pragma once
// Prefiltered specular cubes (oer/lighting/specular_environment.hpp) made by hand for the GL
// tests, exact by construction: a map of constant radiance L prefilters to L at every level
// and direction, whatever the filter, and a residual map that is black (every non-zero pixel
// the lights') to 0; and any map's level 0 (roughness 0, the map itself) from its radiance at
// each texel's direction. specular_of wraps a residual cube into what a frame reads, with a
// black cube for each of the rig's lights (tests that do not reflect them).
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <numeric>
#include <vector>

#include <glm/geometric.hpp>

#include <glm/gtc/packing.hpp>
#include <glm/vec3.hpp>

#include "oer/lighting/specular_environment.hpp"

namespace oer::testing {

inline PrefilteredCube constant_cube(glm::vec3 radiance, int face_size = 16, int levels = 5) {
    PrefilteredCube cube;
    cube.face_size = face_size;
    cube.levels = levels;
    const std::uint16_t rgb[3] = {glm::packHalf1x16(radiance.r), glm::packHalf1x16(radiance.g),
                                  glm::packHalf1x16(radiance.b)};
    for (int level = 0; level < levels; ++level) {
        const std::size_t side = std::size_t(face_size >> level);
        std::vector<std::uint16_t>& texels = cube.rgb_half.emplace_back();
        for (std::size_t i = 0; i < 6 * side * side; ++i) {
            texels.insert(texels.end(), rgb, rgb + 3);
        }
    }
    return cube;
}

// `residual` and, for each of the rig's `lights`, a black light cube of its levels (each its own
// floor layer).
inline std::shared_ptr<const SpecularEnvironment> specular_of(PrefilteredCube residual,
                                                              std::size_t lights = 0) {
    PrefilteredCube black = constant_cube(glm::vec3(0.0f), residual.face_size, residual.levels);
    black.layers = int(lights);
    for (std::vector<std::uint16_t>& level : black.rgb_half) {
        const std::vector<std::uint16_t> one = level;
        level.clear();
        for (std::size_t k = 0; k < lights; ++k) {
            level.insert(level.end(), one.begin(), one.end());
        }
    }
    std::vector<int> floor_layers(lights);
    std::iota(floor_layers.begin(), floor_layers.end(), 0);
    return std::make_shared<const SpecularEnvironment>(
        SpecularEnvironment{std::move(residual), std::move(black), std::move(floor_layers)});
}

// The direction of texel (i, j) of face `face` of an n x n face, rows from t = 0: the OpenGL
// cube-map table (OpenGL 4.5 core, table 8.19) inverted, s = (sc / |ma| + 1) / 2 and
// t = (tc / |ma| + 1) / 2.
inline glm::dvec3 cube_texel_direction(int face, int i, int j, int n) {
    const double a = 2.0 * (i + 0.5) / n - 1.0, b = 2.0 * (j + 0.5) / n - 1.0;
    const glm::dvec3 faces[6] = {{1.0, -b, -a}, {-1.0, -b, a}, {a, 1.0, b},
                                 {a, -1.0, -b}, {a, -b, 1.0},  {-a, -b, -1.0}};
    return glm::normalize(faces[face]);
}

// Every level's texels at radiance(direction): level 0 is then exact for that map; the levels
// above are what a mirror would see at their resolution, not the map prefiltered, so tests
// read them only at roughness 0 or for maps that prefiltering leaves unchanged.
inline PrefilteredCube cube_of(const std::function<glm::vec3(const glm::dvec3&)>& radiance,
                               int face_size = 64, int levels = 5) {
    PrefilteredCube cube;
    cube.face_size = face_size;
    cube.levels = levels;
    for (int level = 0; level < levels; ++level) {
        const int side = face_size >> level;
        std::vector<std::uint16_t>& texels = cube.rgb_half.emplace_back();
        for (int face = 0; face < 6; ++face) {
            for (int j = 0; j < side; ++j) {
                for (int i = 0; i < side; ++i) {
                    const glm::vec3 value = radiance(cube_texel_direction(face, i, j, side));
                    texels.insert(texels.end(),
                                  {glm::packHalf1x16(value.r), glm::packHalf1x16(value.g),
                                   glm::packHalf1x16(value.b)});
                }
            }
        }
    }
    return cube;
}

}  // namespace oer::testing
