#include "oer/lighting/sh.hpp"

#include <string>

#include "oer/core/error.hpp"
#include "sh_legendre.hpp"

namespace oer {
namespace {

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
