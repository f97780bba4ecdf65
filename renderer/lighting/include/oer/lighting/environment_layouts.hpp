#pragma once
// The two other environment layouts of the thesis, resampled to equirect (docs/design.md section 3
// mapping): cube maps (six faces, or one horizontal or vertical cross) with faces oriented as
// in the OpenGL cube-map table, and mirror-ball light probes.
//
// Every function returns an out_width x (out_width / 2) equirect map (out_width in
// [2, 32768]): each output pixel samples the source bilinearly at its own direction (cube
// faces clamp at their edges, no filtering across faces). Invalid sources or sizes throw
// oer::Error(ErrorKind::InvalidInput) saying what is wrong.
#include <array>

#include "oer/core/image.hpp"

namespace oer {

// Face order +X, -X, +Y, -Y, +Z, -Z (GL_TEXTURE_CUBE_MAP_POSITIVE_X + i). Faces are square
// and of one size. Per the OpenGL specification table (section 8.13), for major axis ma:
//   +X: sc = -z, tc = -y   -X: sc = +z, tc = -y
//   +Y: sc = +x, tc = +z   -Y: sc = +x, tc = -z
//   +Z: sc = +x, tc = -y   -Z: sc = -x, tc = -y
//   s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2, with t = 0 at the image's top row.
HdrImage equirect_from_cube_faces(const std::array<const HdrImage*, 6>& faces, int out_width);

enum class CrossLayout { Horizontal, Vertical };
// Horizontal cross: 4x3 face cells, row 1 = -X +Z +X -Z, +Y above +Z, -Y below +Z.
// Vertical cross: 3x4 cells, +Y top, row 1 = -X +Z +X, -Y below +Z, -Z at the bottom
// (stored rotated by 180 degrees, as is customary for vertical crosses).
// Detects the layout from the aspect ratio (4:3 or 3:4); throws oer::Error otherwise.
HdrImage equirect_from_cross(const HdrImage& cross, int out_width);

// Mirror ball photographed along -Z (the camera looks down -Z at a ball centred in a square
// image): the ball's image point at normalised (u, v) in [-1, 1]^2 (v up) reflects the
// direction r = 2 (n . e) n - e with e = (0, 0, 1) and n = (u, v, sqrt(1 - u^2 - v^2)).
// The disc touches the image's edges. Pixels outside it are only reached by the bilinear taps
// of rim points, i.e. of directions near -Z, which the ball squeezes into its rim (-Z itself
// is the whole rim and is read from one rim point).
HdrImage equirect_from_mirror_ball(const HdrImage& probe, int out_width);

}  // namespace oer
