#pragma once
// Internal to the SH projection (sh_projection.cpp), its only user; the basis itself is
// oer/lighting/sh.hpp. The change of basis between the SH basis with polar axis world +Y (the
// equirect polar axis, used by the separable projection) and our basis with polar axis world z
// (docs/design.md section 3). With Y'_lm(v) = Y_lm(v.x, v.z, v.y), each band transforms by the
// fixed orthogonal matrix
//   D_l[m][m'] = integral of Y_lm(v) Y'_lm'(v) over the sphere,
// so that coefficients convert as c_lm = sum over m' of D_l[m][m'] c'_lm'.
#include <vector>

namespace oer::detail {

// D_l, row-major, (2l + 1) x (2l + 1), index [(m + l) * (2l + 1) + (m' + l)], for
// 0 <= l < kMaxShOrder. Computed once per band by an exact quadrature; thread-safe.
const std::vector<double>& axis_swap_matrix(int l);

}  // namespace oer::detail
