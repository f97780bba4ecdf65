#include "bench_support.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/lighting/equirect.hpp"

namespace oer::bench {

using std::numbers::pi;

glm::dvec3 disc_centre(const Disc& disc) {
    const double phi = disc.azimuth_degrees * pi / 180.0;
    const double elevation = disc.elevation_degrees * pi / 180.0;
    return {std::cos(elevation) * std::cos(phi), std::sin(elevation),
            std::cos(elevation) * std::sin(phi)};
}

HdrImage make_synthetic_map(int width, int height, int lights) {
    const equirect::Grid grid(width, height);
    std::vector<glm::dvec3> centres;
    std::vector<double> cos_radii;
    for (int k = 0; k < lights; ++k) {
        centres.push_back(disc_centre(kDiscs[k]));
        cos_radii.push_back(std::cos(kDiscs[k].radius_degrees * pi / 180.0));
    }
    HdrImage image(width, height);
    const glm::vec3 zenith(0.08f, 0.12f, 0.25f), horizon(0.30f, 0.32f, 0.35f),
        ground(0.06f, 0.05f, 0.04f);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d = grid.direction(x, y);
            glm::vec3 value = d.y >= 0.0 ? horizon + (zenith - horizon) * float(std::sqrt(d.y))
                                         : ground * float(1.0 + 0.5 * d.y);
            value *= float(1.0 + 0.5 * d.x);
            for (int k = 0; k < lights; ++k) {
                if (glm::dot(d, centres[k]) >= cos_radii[k]) {
                    value = kDiscs[k].radiance;
                }
            }
            image.set(std::size_t(y) * std::size_t(width) + std::size_t(x), value);
        }
    }
    return image;
}

}  // namespace oer::bench
