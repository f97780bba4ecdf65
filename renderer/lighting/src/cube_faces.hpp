#pragma once
// Internal to the lighting library: the OpenGL cube-map table (OpenGL 4.6 core specification,
// section 8.13, table 8.19) both ways, for the cube layouts resampled to equirect
// (environment_layouts.cpp) and the prefiltered specular cube (specular_environment.cpp).
// Face order +X, -X, +Y, -Y, +Z, -Z (GL_TEXTURE_CUBE_MAP_POSITIVE_X + face); for major axis ma:
//   +X: sc = -z, tc = -y   -X: sc = +z, tc = -y
//   +Y: sc = +x, tc = +z   -Y: sc = +x, tc = -z
//   +Z: sc = +x, tc = -y   -Z: sc = -x, tc = -y
//   s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2, with t = 0 at a face's first row.
#include <cmath>
#include <vector>

#include <glm/vec3.hpp>

namespace oer::detail {

template <typename Real>
struct CubeFaceCoordinates {
    int face;
    Real s, t;  // in [0, 1]
};

// The face a direction (any length but zero) points into and its (s, t) there. In the
// header, in double and in float (the prefilter's inner loop), so that it inlines.
template <typename Real>
inline CubeFaceCoordinates<Real> cube_lookup(const glm::vec<3, Real>& d) {
    const Real ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    int face;
    Real sc, tc, ma;
    if (ax >= ay && ax >= az) {
        ma = ax;
        face = d.x >= Real(0) ? 0 : 1;
        sc = d.x >= Real(0) ? -d.z : d.z;
        tc = -d.y;
    } else if (ay >= az) {
        ma = ay;
        face = d.y >= Real(0) ? 2 : 3;
        sc = d.x;
        tc = d.y >= Real(0) ? d.z : -d.z;
    } else {
        ma = az;
        face = d.z >= Real(0) ? 4 : 5;
        sc = d.z >= Real(0) ? d.x : -d.x;
        tc = -d.y;
    }
    const Real half_over_ma = Real(0.5) / ma;
    return {face, sc * half_over_ma + Real(0.5), tc * half_over_ma + Real(0.5)};
}

// The inverse: the unit direction through (s, t) of `face` (the direction of texel (i, j) of
// an n x n face is that of s = (i + 0.5) / n, t = (j + 0.5) / n).
glm::dvec3 cube_direction(int face, double s, double t);

// Exact solid angles of the texels of an n x n face, row-major (j * n + i), the same on every
// face: the integral of the cube's Jacobian (1 + sc^2 + tc^2)^(-3/2) dsc dtc over texel (i, j),
// F(x1, y1) - F(x0, y1) - F(x1, y0) + F(x0, y0) with F(x, y) = atan2(x y, sqrt(x^2 + y^2 + 1))
// at its corners in [-1, 1]^2 (they sum to 4 pi / 6).
std::vector<double> cube_face_solid_angles(int n);

}  // namespace oer::detail
