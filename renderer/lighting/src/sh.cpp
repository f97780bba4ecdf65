#include "oer/lighting/sh.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "oer/core/error.hpp"

namespace oer {
namespace {

// Coefficients of the recurrence of sh.hpp, computed once.
struct LegendreTables {
    std::array<double, kMaxShOrder> diagonal{};                    // N_m^m / (s N_{m-1}^{m-1})
    std::array<double, kMaxShOrder> subdiagonal{};                 // N_{m+1}^m / (z N_m^m)
    std::array<std::array<double, kMaxShOrder>, kMaxShOrder> a{};  // a_lm, [l][m]
    std::array<std::array<double, kMaxShOrder>, kMaxShOrder> b{};  // b_lm, [l][m]

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

void require_order(int order, const char* what) {
    if (order < 1 || order > kMaxShOrder) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": SH order " +
                                                 std::to_string(order) + " is not in [1, " +
                                                 std::to_string(kMaxShOrder) + "]");
    }
}

void require_same_order(const ShRgb& a, const ShRgb& b, const char* what) {
    if (a.order != b.order || a.coefficients.size() != b.coefficients.size()) {
        throw Error(ErrorKind::InvalidInput, std::string(what) + ": SH orders differ (" +
                                                 std::to_string(a.order) + " and " +
                                                 std::to_string(b.order) + ")");
    }
}

}  // namespace

namespace detail {

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

}  // namespace detail

void sh_evaluate(int order, const glm::dvec3& d, std::span<double> out) {
    require_order(order, "sh_evaluate");
    if (out.size() < std::size_t(sh_count(order))) {
        throw Error(ErrorKind::InvalidInput, "sh_evaluate: output span holds " +
                                                 std::to_string(out.size()) + " values, order " +
                                                 std::to_string(order) + " needs " +
                                                 std::to_string(sh_count(order)));
    }
    double legendre[detail::legendre_count(kMaxShOrder)];
    detail::sh_legendre(order, d.z, 1.0, legendre);
    // Re and Im of (x + i y)^m: sin^m(theta) cos(m phi) and sin^m(theta) sin(m phi) without
    // any angle, so the poles need no special case.
    double c = 1.0, s = 0.0;
    for (int m = 0; m < order; ++m) {
        if (m > 0) {
            const double c_next = d.x * c - d.y * s;
            s = d.x * s + d.y * c;
            c = c_next;
        }
        for (int l = m; l < order; ++l) {
            const double p = legendre[detail::legendre_index(l, m)];
            if (m == 0) {
                out[sh_index(l, 0)] = p;
            } else {
                out[sh_index(l, m)] = p * c;
                out[sh_index(l, -m)] = p * s;
            }
        }
    }
}

double lambertian_band_factor(int l) {
    if (l < 0) {
        throw Error(ErrorKind::InvalidInput,
                    "lambertian_band_factor: band " + std::to_string(l) + " is negative");
    }
    if (l == 1) {
        return 2.0 * std::numbers::pi / 3.0;
    }
    if (l % 2 == 1) {
        return 0.0;
    }
    // l! / (2^l ((l/2)!)^2) = prod over i = 1 .. l/2 of (2i - 1) / (2i)
    double central = 1.0;
    for (int i = 1; i <= l / 2; ++i) {
        central *= (2.0 * i - 1.0) / (2.0 * i);
    }
    const double sign = (l / 2) % 2 == 1 ? 1.0 : -1.0;  // (-1)^(l/2 - 1)
    return 2.0 * std::numbers::pi * sign / ((l + 2.0) * (l - 1.0)) * central;
}

glm::dvec3 ShRgb::evaluate(const glm::dvec3& d) const {
    require_order(order, "ShRgb::evaluate");
    if (coefficients.size() != std::size_t(sh_count(order))) {
        throw Error(ErrorKind::InvalidInput,
                    "ShRgb::evaluate: " + std::to_string(coefficients.size()) +
                        " coefficients for order " + std::to_string(order));
    }
    double basis[sh_count(kMaxShOrder)];
    sh_evaluate(order, d, basis);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < sh_count(order); ++i) {
        sum += coefficients[i] * basis[i];
    }
    return sum;
}

ShRgb ShRgb::truncated(int order_) const {
    if (order_ < 1 || order_ > order) {
        throw Error(ErrorKind::InvalidInput, "ShRgb::truncated: order " + std::to_string(order_) +
                                                 " is not in [1, " + std::to_string(order) + "]");
    }
    ShRgb result(order_);
    for (int i = 0; i < sh_count(order_); ++i) {
        result.coefficients[i] = coefficients[i];
    }
    return result;
}

ShRgb& ShRgb::operator+=(const ShRgb& other) {
    require_same_order(*this, other, "ShRgb::operator+=");
    for (std::size_t i = 0; i < coefficients.size(); ++i) {
        coefficients[i] += other.coefficients[i];
    }
    return *this;
}

ShRgb& ShRgb::operator-=(const ShRgb& other) {
    require_same_order(*this, other, "ShRgb::operator-=");
    for (std::size_t i = 0; i < coefficients.size(); ++i) {
        coefficients[i] -= other.coefficients[i];
    }
    return *this;
}

ShRgb& ShRgb::operator*=(double factor) {
    for (glm::dvec3& c : coefficients) {
        c *= factor;
    }
    return *this;
}

}  // namespace oer
