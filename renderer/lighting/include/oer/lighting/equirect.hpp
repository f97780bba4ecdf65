#pragma once
// The equirectangular mapping of docs/design.md section 3, shared by every module:
//   theta = pi (y + 0.5) / H   (polar angle from +Y)
//   phi   = 2 pi (x + 0.5) / W - pi
//   dir   = (sin theta cos phi, cos theta, sin theta sin phi)
// and the exact solid angle of a pixel in row y (docs/design.md section 3), the integral of
// sin(theta) dtheta dphi over the pixel, phi across 2 pi / W and theta from pi y / H to
// pi (y + 1) / H:
//   dOmega(y) = (2 pi / W) (cos(pi y / H) - cos(pi (y + 1) / H))
// The rows telescope to 2 pi (cos 0 - cos pi) / W per column, so a map sums to exactly 4 pi;
// the midpoint form sin(theta_y) (pi / H) (2 pi / W) does not.
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace oer::equirect {

// Direction of a continuous image position (u, v) in pixel units; pixel (x, y) has its
// centre at (x + 0.5, y + 0.5).
glm::dvec3 direction_at(double u, double v, int width, int height);

// Direction through the centre of pixel (x, y).
glm::dvec3 pixel_direction(int x, int y, int width, int height);

// Continuous image position (u, v) in pixel units of a unit direction; u in [0, W), v in [0, H].
glm::dvec2 position_of(const glm::dvec3& direction, int width, int height);

// Exact solid angle of one pixel of row y.
double pixel_solid_angle(int y, int width, int height);

// Per-row and per-column tables of one image size, so that loops over millions of pixels
// evaluate no trigonometry.
struct Grid {
    int width = 0;
    int height = 0;
    std::vector<double> row_solid_angle;  // dOmega(y)
    std::vector<double> row_cos_theta;
    std::vector<double> row_sin_theta;
    std::vector<double> column_cos_phi;
    std::vector<double> column_sin_phi;

    Grid(int width, int height);
    glm::dvec3 direction(int x, int y) const {
        return {row_sin_theta[y] * column_cos_phi[x], row_cos_theta[y],
                row_sin_theta[y] * column_sin_phi[x]};
    }
    glm::dvec3 direction(std::size_t index) const {
        return direction(int(index % std::size_t(width)), int(index / std::size_t(width)));
    }
};

// Rotation of a direction about +Y by yaw degrees (docs/design.md section 3), positive yaw
// turning +X towards -Z (counter-clockwise seen from above).
glm::dvec3 rotate_yaw(const glm::dvec3& direction, double yaw_degrees);

}  // namespace oer::equirect
