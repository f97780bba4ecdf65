#include "oer/lighting/microfacet.hpp"

#include <cmath>

namespace oer {

double smith_visibility(double n_dot_v, double n_dot_l, double alpha) {
    const double a2 = alpha * alpha;
    const double view = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    const double light = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (view + light);
}

double smith_masking(double n_dot_w, double alpha) {
    const double a2 = alpha * alpha;
    return 2.0 * n_dot_w / (n_dot_w + std::sqrt(a2 + (1.0 - a2) * n_dot_w * n_dot_w));
}

}  // namespace oer
