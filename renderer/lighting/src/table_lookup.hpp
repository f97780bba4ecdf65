#pragma once
// A square table of texel-centred values read bilinearly with clamping, as a GL_LINEAR,
// CLAMP_TO_EDGE texture is: the CPU's reading of the tables the shaders sample at (n.v,
// roughness) (split_sum.hpp's DFG table, sheen_albedo.hpp's albedo).
#include <algorithm>
#include <cstddef>

#include <glm/common.hpp>

namespace oer::detail {

// at(column, row): the table's value there; u along columns, v along rows, each in [0, 1].
template <typename At>
auto bilinear_lookup(int size, double u, double v, At at) {
    const auto coordinate = [size](double t, int& low, double& fraction) {
        const double x = std::clamp(t * size - 0.5, 0.0, double(size - 1));
        low = std::min(int(x), size - 2);
        fraction = x - low;
    };
    int i = 0, j = 0;
    double fx = 0.0, fy = 0.0;
    coordinate(u, i, fx);
    coordinate(v, j, fy);
    const auto bottom = glm::mix(at(i, j), at(i + 1, j), fx);
    const auto top = glm::mix(at(i, j + 1), at(i + 1, j + 1), fx);
    return glm::mix(bottom, top, fy);
}

}  // namespace oer::detail
