#include "sh_legendre.hpp"

#include <array>
#include <cmath>
#include <numbers>

#include "oer/lighting/sh.hpp"

namespace oer::detail {
namespace {

// Recurrence coefficients, computed once.
struct LegendreTables {
    std::array<double, kMaxShOrder> diagonal{};                    // N_m^m / (s N_{m-1}^{m-1})
    std::array<double, kMaxShOrder> subdiagonal{};                 // N_{m+1}^m / (z N_m^m)
    std::array<std::array<double, kMaxShOrder>, kMaxShOrder> a{};  // [l][m]
    std::array<std::array<double, kMaxShOrder>, kMaxShOrder> b{};  // [l][m]

    LegendreTables() {
        for (int m = 1; m < kMaxShOrder; ++m) {
            // K_m^m (2m - 1)!! over K_{m-1}^{m-1} (2m - 3)!! is sqrt((2m + 1) / (2m)); the
            // factor sqrt(2) of the real basis enters once, at m = 1.
            diagonal[m] = std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * (m == 1 ? std::sqrt(2.0) : 1.0);
        }
        for (int m = 0; m < kMaxShOrder; ++m) {
            subdiagonal[m] = std::sqrt(2.0 * m + 3.0);
        }
        for (int l = 2; l < kMaxShOrder; ++l) {
            for (int m = 0; m <= l - 2; ++m) {
                const double l2 = double(l) * l, m2 = double(m) * m;
                a[l][m] = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
                b[l][m] = std::sqrt(((l - 1.0) * (l - 1.0) - m2) * (2.0 * l + 1.0) /
                                    ((2.0 * l - 3.0) * (l2 - m2)));
            }
        }
    }
};

const LegendreTables& tables() {
    static const LegendreTables instance;
    return instance;
}

}  // namespace

void sh_legendre(int order, double z, double s, double* out) {
    const LegendreTables& t = tables();
    double diagonal = 0.5 / std::sqrt(std::numbers::pi);  // N_0^0 = Y_0^0
    for (int m = 0; m < order; ++m) {
        if (m > 0) {
            diagonal *= t.diagonal[m] * s;
        }
        out[legendre_index(m, m)] = diagonal;
        if (m + 1 >= order) {
            continue;
        }
        double previous = diagonal;
        double current = t.subdiagonal[m] * z * diagonal;
        out[legendre_index(m + 1, m)] = current;
        for (int l = m + 2; l < order; ++l) {
            const double next = t.a[l][m] * z * current - t.b[l][m] * previous;
            out[legendre_index(l, m)] = next;
            previous = current;
            current = next;
        }
    }
}

}  // namespace oer::detail
