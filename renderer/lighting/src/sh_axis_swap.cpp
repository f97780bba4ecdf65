#include "sh_axis_swap.hpp"

#include <array>
#include <mutex>
#include <string>

#include <glm/mat3x3.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/lighting/sh_rotation.hpp"

namespace oer::detail {

const std::vector<double>& axis_swap_matrix(int l) {
    if (l < 0 || l >= kMaxShOrder) {
        throw Error(ErrorKind::Internal,
                    "axis_swap_matrix: band " + std::to_string(l) + " out of range");
    }
    static std::array<std::once_flag, kMaxShOrder> once;
    static std::array<std::vector<double>, kMaxShOrder> matrices;
    // The swap of y and z: Y'_lm(v) = Y_lm(v.x, v.z, v.y), an orthogonal (reflecting) q.
    const glm::dmat3 swap(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0);
    std::call_once(once[l], [l, &swap] { matrices[l] = sh_band_transform(l, swap); });
    return matrices[l];
}

}  // namespace oer::detail
