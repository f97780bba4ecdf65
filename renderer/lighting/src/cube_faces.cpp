// The OpenGL cube-map table from a face position to a direction, and a texel's solid angle
// (see cube_faces.hpp; the other way, cube_lookup, is inline there).
#include "cube_faces.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace oer::detail {

glm::dvec3 cube_direction(int face, double s, double t) {
    const double sc = 2.0 * s - 1.0, tc = 2.0 * t - 1.0;
    glm::dvec3 d;
    switch (face) {
        case 0:
            d = {1.0, -tc, -sc};
            break;
        case 1:
            d = {-1.0, -tc, sc};
            break;
        case 2:
            d = {sc, 1.0, tc};
            break;
        case 3:
            d = {sc, -1.0, -tc};
            break;
        case 4:
            d = {sc, -tc, 1.0};
            break;
        default:
            d = {-sc, -tc, -1.0};
            break;
    }
    return glm::normalize(d);
}

std::vector<double> cube_face_solid_angles(int n) {
    const std::size_t corners = std::size_t(n) + 1;
    std::vector<double> f(corners * corners);
    for (std::size_t j = 0; j < corners; ++j) {
        const double y = 2.0 * double(j) / n - 1.0;
        for (std::size_t i = 0; i < corners; ++i) {
            const double x = 2.0 * double(i) / n - 1.0;
            f[j * corners + i] = std::atan2(x * y, std::sqrt(x * x + y * y + 1.0));
        }
    }
    std::vector<double> solid_angles(std::size_t(n) * n);
    for (std::size_t j = 0; j < std::size_t(n); ++j) {
        for (std::size_t i = 0; i < std::size_t(n); ++i) {
            solid_angles[j * n + i] = f[(j + 1) * corners + i + 1] - f[j * corners + i + 1] -
                                      f[(j + 1) * corners + i] + f[j * corners + i];
        }
    }
    return solid_angles;
}

}  // namespace oer::detail
