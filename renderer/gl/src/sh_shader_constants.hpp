#pragma once
// Constants the shaders' SH basis needs (sh_basis in renderer/gl/shaders/sh_lighting.glsl): the
// normalisation K_l^|m| = sqrt((2l + 1) / (4 pi) (l - |m|)! / (l + |m|)!), times sqrt 2 for
// m != 0, at index l (l + 1) + m; computed in double once per order.
#include <vector>

namespace oer {

const std::vector<float>& sh_shader_scales(int order);

}  // namespace oer
