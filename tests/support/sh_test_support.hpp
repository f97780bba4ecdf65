#pragma once
// Helpers for the SH tests, written independently of the code under test: Legendre polynomials,
// a Gauss-Legendre rule, a naive per-pixel SH projection and synthetic maps.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "oer/core/image.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/sh.hpp"

namespace oer::test {

// Legendre polynomial P_l(t) by Bonnet's recurrence.
inline double legendre_p(int l, double t) {
    double p0 = 1.0, p1 = t;
    if (l == 0) {
        return p0;
    }
    for (int k = 2; k <= l; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    return p1;
}

// n-point Gauss-Legendre rule on [-1, 1], exact for polynomials of degree 2n - 1.
struct GaussLegendre {
    std::vector<double> nodes, weights;
    explicit GaussLegendre(int n) {
        for (int i = 0; i < n; ++i) {
            double t = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
            double dp = 1.0;
            for (int it = 0; it < 100; ++it) {
                const double p = legendre_p(n, t);
                dp = n * (t * p - legendre_p(n - 1, t)) / (t * t - 1.0);
                const double dt = p / dp;
                t -= dt;
                if (std::abs(dt) < 1e-15) {
                    break;
                }
            }
            nodes.push_back(t);
            weights.push_back(2.0 / ((1.0 - t * t) * dp * dp));
        }
    }
};

// L_lm = sum over pixels L Y_lm(dir) dOmega, one pixel at a time (all pixels, or only those
// listed).
inline ShRgb naive_projection(const HdrImage& image, int order,
                              const std::vector<std::uint32_t>* only = nullptr) {
    ShRgb result(order);
    std::vector<double> basis(sh_count(order));
    const auto add = [&](std::size_t index) {
        const int x = int(index % std::size_t(image.width));
        const int y = int(index / std::size_t(image.width));
        sh_evaluate(order, equirect::pixel_direction(x, y, image.width, image.height), basis);
        const glm::dvec3 radiance(image.rgb(index));
        const double d_omega = equirect::pixel_solid_angle(y, image.width, image.height);
        for (int i = 0; i < sh_count(order); ++i) {
            result.coefficients[i] += radiance * (basis[i] * d_omega);
        }
    };
    if (only != nullptr) {
        for (const std::uint32_t index : *only) {
            add(index);
        }
    } else {
        for (std::size_t index = 0; index < image.pixel_count(); ++index) {
            add(index);
        }
    }
    return result;
}

inline HdrImage random_map(int width, int height, std::uint32_t seed) {
    HdrImage image(width, height);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 2.0f);
    for (float& value : image.pixels) {
        value = uniform(rng);
    }
    return image;
}

inline HdrImage constant_map(int width, int height, glm::vec3 radiance) {
    HdrImage image(width, height);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        image.set(i, radiance);
    }
    return image;
}

// Largest absolute coefficient (over all channels) of an expansion: the scale for relative
// comparisons of coefficient sets.
inline double max_abs(const ShRgb& sh) {
    double result = 0.0;
    for (const glm::dvec3& c : sh.coefficients) {
        result = std::max({result, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
    }
    return result;
}

inline double max_abs_difference(const ShRgb& a, const ShRgb& b) {
    double result = 0.0;
    for (std::size_t i = 0; i < a.coefficients.size() && i < b.coefficients.size(); ++i) {
        const glm::dvec3 d = a.coefficients[i] - b.coefficients[i];
        result = std::max({result, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    }
    return a.coefficients.size() == b.coefficients.size() ? result : HUGE_VAL;
}

}  // namespace oer::test
