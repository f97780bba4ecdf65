#include "sh_shader_constants.hpp"

#include <array>
#include <cmath>
#include <mutex>
#include <numbers>

#include "oer/core/error.hpp"
#include "oer/lighting/sh.hpp"

namespace oer {

const std::vector<float>& sh_shader_scales(int order) {
    if (order < 1 || order > kMaxShOrder) {
        throw Error(ErrorKind::InvalidInput, "sh_shader_scales: order " + std::to_string(order) +
                                                 " is outside 1.." + std::to_string(kMaxShOrder));
    }
    static std::array<std::vector<float>, kMaxShOrder + 1> tables;
    static std::once_flag once[kMaxShOrder + 1];
    std::call_once(once[order], [order] {
        std::vector<float>& table = tables[order];
        table.resize(std::size_t(order * order));
        for (int l = 0; l < order; ++l) {
            for (int m = 0; m <= l; ++m) {
                double ratio = 1.0;  // (l - m)! / (l + m)!
                for (int j = l - m + 1; j <= l + m; ++j) {
                    ratio /= j;
                }
                const double k = std::sqrt((2.0 * l + 1.0) / (4.0 * std::numbers::pi) * ratio);
                if (m == 0) {
                    table[sh_index(l, 0)] = float(k);
                } else {
                    table[sh_index(l, m)] = table[sh_index(l, -m)] = float(std::sqrt(2.0) * k);
                }
            }
        }
    });
    return tables[order];
}

}  // namespace oer
