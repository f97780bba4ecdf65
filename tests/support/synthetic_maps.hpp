#pragma once
// Synthetic environment maps with known content, shared by the tests.
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/core/image.hpp"
#include "oer/lighting/equirect.hpp"

namespace oer::testing {

inline HdrImage constant_map(int width, int height, glm::vec3 radiance) {
    HdrImage image(width, height);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, radiance);
    }
    return image;
}

struct DiscLight {
    glm::dvec3 direction;
    double angular_radius;  // radians
    glm::vec3 radiance;
};

// A background of constant radiance plus discs of constant radiance (every pixel whose centre
// lies within the disc's angular radius takes the disc's radiance).
inline HdrImage disc_map(int width, int height, glm::vec3 background,
                         const std::vector<DiscLight>& discs) {
    HdrImage image = constant_map(width, height, background);
    const equirect::Grid grid(width, height);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        const glm::dvec3 d = grid.direction(i);
        for (const DiscLight& disc : discs) {
            if (glm::dot(d, glm::normalize(disc.direction)) >= std::cos(disc.angular_radius)) {
                image.set(i, disc.radiance);
            }
        }
    }
    return image;
}

}  // namespace oer::testing
