#include "oer/lighting/equirect.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace oer::equirect {

using std::numbers::pi;

glm::dvec3 direction_at(double u, double v, int width, int height) {
    const double theta = pi * v / height;
    const double phi = 2.0 * pi * u / width - pi;
    return {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
}

glm::dvec3 pixel_direction(int x, int y, int width, int height) {
    return direction_at(x + 0.5, y + 0.5, width, height);
}

glm::dvec2 position_of(const glm::dvec3& direction, int width, int height) {
    const double length = std::sqrt(direction.x * direction.x + direction.y * direction.y +
                                    direction.z * direction.z);
    const double cos_theta = std::clamp(direction.y / length, -1.0, 1.0);
    const double theta = std::acos(cos_theta);
    double phi = std::atan2(direction.z, direction.x);  // in [-pi, pi]
    double u = (phi + pi) / (2.0 * pi) * width;
    if (u >= width) {
        u -= width;
    }
    return {u, theta / pi * height};
}

// Exact: the integral of sin(theta) dtheta dphi over the pixel (docs/design.md section 3).
double pixel_solid_angle(int y, int width, int height) {
    return (2.0 * pi / width) * (std::cos(pi * y / height) - std::cos(pi * (y + 1) / height));
}

Grid::Grid(int w, int h)
    : width(w),
      height(h),
      row_solid_angle(h),
      row_cos_theta(h),
      row_sin_theta(h),
      column_cos_phi(w),
      column_sin_phi(w) {
    for (int y = 0; y < h; ++y) {
        const double theta = pi * (y + 0.5) / h;
        row_solid_angle[y] = pixel_solid_angle(y, w, h);
        row_cos_theta[y] = std::cos(theta);
        row_sin_theta[y] = std::sin(theta);
    }
    for (int x = 0; x < w; ++x) {
        const double phi = 2.0 * pi * (x + 0.5) / w - pi;
        column_cos_phi[x] = std::cos(phi);
        column_sin_phi[x] = std::sin(phi);
    }
}

glm::dvec3 rotate_yaw(const glm::dvec3& d, double yaw_degrees) {
    // Rotation about +Y: x' = x cos a + z sin a, z' = -x sin a + z cos a turns +X to -Z
    // for positive a (right-handed, counter-clockwise seen from +Y).
    const double a = yaw_degrees * pi / 180.0;
    const double c = std::cos(a), s = std::sin(a);
    return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}

}  // namespace oer::equirect
