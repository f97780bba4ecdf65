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

// A rectangular soft box: a planar light seen from its centre, a rectangle in the gnomonic
// projection about `direction`, half_width radians either side horizontally (about the
// world's up) and half_height vertically.
struct SoftBoxLight {
    glm::dvec3 direction;
    double half_width;   // radians
    double half_height;  // radians
    glm::vec3 radiance;

    // The box's horizontal and vertical axes (unit, perpendicular to its direction).
    glm::dvec3 across() const {
        return glm::normalize(glm::cross(glm::dvec3(0.0, 1.0, 0.0), glm::normalize(direction)));
    }
    glm::dvec3 up() const { return glm::cross(glm::normalize(direction), across()); }
    bool contains(const glm::dvec3& d) const {
        const double forward = glm::dot(d, glm::normalize(direction));
        return forward > 0.0 &&
               std::abs(std::atan(glm::dot(d, across()) / forward)) <= half_width &&
               std::abs(std::atan(glm::dot(d, up()) / forward)) <= half_height;
    }
};

// The boxes' pixels (whose centres each box contains) set to its radiance, over `image`.
inline HdrImage with_soft_boxes(HdrImage image, const std::vector<SoftBoxLight>& boxes) {
    const equirect::Grid grid(image.width, image.height);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        for (const SoftBoxLight& box : boxes) {
            if (box.contains(grid.direction(i))) {
                image.set(i, box.radiance);
            }
        }
    }
    return image;
}

}  // namespace oer::testing
