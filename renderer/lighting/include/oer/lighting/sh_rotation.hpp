#pragma once
// Rotation of SH coefficients, for any order (object transforms and the environment's
// yaw turn the lighting into a transfer's frame). Rotations keep each band l to itself, so a
// rotation is one (2l + 1) x (2l + 1) matrix per band,
//   D_l[m][m'] = integral over the sphere of Y_lm(v) Y_lm'(Q v) dv,
// which converts coefficients c' in the basis Y_lm(Q v) into the basis Y_lm: c_lm =
// sum over m' of D_l[m][m'] c'_lm'. Y_lm(v) Y_lm'(Q v) is a polynomial of degree 2l in
// (x, y, z), so a product of an (l + 2)-point Gauss-Legendre rule in z and a uniform rule of
// 2l + 3 points in phi integrates it exactly (in double: to about 1e-15); this is the
// projection form of the rotation, simpler to trust than the recurrences of Ivanic and
// Ruedenberg (J. Phys. Chem. 1996) and fast enough here (order 9: under a millisecond).
#include <vector>

#include <glm/mat3x3.hpp>

#include "oer/lighting/sh.hpp"

namespace oer {

// D_l of the orthogonal matrix q (a rotation, or a reflection such as an axis swap), row-major,
// index [(m + l) * (2l + 1) + (m' + l)]. Throws oer::Error (InvalidInput) for l outside
// [0, kMaxShOrder) or a q that is not orthogonal (|q^T q - I| above 1e-9).
std::vector<double> sh_band_transform(int l, const glm::dmat3& q);

// The coefficients of the function turned by `rotation`: g(d) = f(rotation^T d), where f is
// the expansion `sh`. Same order; throws oer::Error (InvalidInput) as above.
ShRgb rotate_sh(const ShRgb& sh, const glm::dmat3& rotation);

}  // namespace oer
