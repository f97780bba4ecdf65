#include "oer/lighting/sh_rotation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "oer/core/error.hpp"

namespace oer {
namespace {

using std::numbers::pi;

// n-point (n >= 1) Gauss-Legendre rule on [-1, 1] (exact for polynomials of degree 2n - 1), by
// Newton's method on P_n from the initial guesses of Numerical Recipes' gauleg (Press et al.,
// "Numerical Recipes", 3rd ed., 2007, section 4.6).
void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(n, 0.0);
    weights.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(pi * (i + 0.75) / (n + 0.5));
        double derivative = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = z;  // P_0, P_1
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            // p1 = P_n(z), p0 = P_{n-1}(z) (n >= 1)
            derivative = n * (z * p1 - p0) / (z * z - 1.0);
            const double step = p1 / derivative;
            z -= step;
            if (std::abs(step) < 1e-16) {
                break;
            }
        }
        nodes[i] = z;
        weights[i] = 2.0 / ((1.0 - z * z) * derivative * derivative);
    }
}

void check_orthogonal(const glm::dmat3& q) {
    const glm::dmat3 product = glm::transpose(q) * q;
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) {
            const double expected = c == r ? 1.0 : 0.0;
            const double error = std::abs(product[c][r] - expected);
            worst = std::isfinite(error) ? std::max(worst, error) : HUGE_VAL;
        }
    }
    if (worst > 1e-9) {
        throw Error(ErrorKind::InvalidInput,
                    "SH rotation: the matrix is not orthogonal (|q^T q - I| = " +
                        std::to_string(worst) + ")");
    }
}

}  // namespace

std::vector<double> sh_band_transform(int l, const glm::dmat3& q) {
    if (l < 0 || l >= kMaxShOrder) {
        throw Error(ErrorKind::InvalidInput, "SH rotation: band " + std::to_string(l) +
                                                 " outside [0, " + std::to_string(kMaxShOrder) +
                                                 ")");
    }
    check_orthogonal(q);
    // Integrating over phi leaves a polynomial of degree <= 2l in z = cos(theta) (exact with
    // l + 1 Gauss points), whose phi frequencies are <= 2l (exact with any uniform rule of more
    // than 2l points).
    const int order = l + 1;
    const int n_z = l + 2;
    const int n_phi = 2 * l + 3;
    std::vector<double> nodes, weights;
    gauss_legendre(n_z, nodes, weights);
    const int size = 2 * l + 1;
    std::vector<double> matrix(std::size_t(size) * size, 0.0);
    std::array<double, sh_count(kMaxShOrder)> y{}, y_turned{};
    for (int i = 0; i < n_z; ++i) {
        const double z = nodes[i];
        const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double weight = weights[i] * 2.0 * pi / n_phi;
        for (int j = 0; j < n_phi; ++j) {
            const double phi = 2.0 * pi * (j + 0.5) / n_phi;
            const glm::dvec3 v(s * std::cos(phi), s * std::sin(phi), z);
            sh_evaluate(order, v, y);
            sh_evaluate(order, q * v, y_turned);
            for (int m = -l; m <= l; ++m) {
                const double a = y[sh_index(l, m)] * weight;
                for (int m2 = -l; m2 <= l; ++m2) {
                    matrix[std::size_t(m + l) * size + (m2 + l)] += a * y_turned[sh_index(l, m2)];
                }
            }
        }
    }
    return matrix;
}

ShRgb rotate_sh(const ShRgb& sh, const glm::dmat3& rotation) {
    // g(d) = f(R^T d) = sum c_lm' Y_lm'(R^T d): the basis Y(Q v) with Q = R^T.
    const glm::dmat3 q = glm::transpose(rotation);
    ShRgb rotated(sh.order);
    for (int l = 0; l < sh.order; ++l) {
        const std::vector<double> band = sh_band_transform(l, q);
        const int size = 2 * l + 1;
        for (int m = -l; m <= l; ++m) {
            glm::dvec3 sum(0.0);
            for (int m2 = -l; m2 <= l; ++m2) {
                sum += band[std::size_t(m + l) * size + (m2 + l)] *
                       sh.coefficients[std::size_t(sh_index(l, m2))];
            }
            rotated.coefficients[std::size_t(sh_index(l, m))] = sum;
        }
    }
    return rotated;
}

}  // namespace oer
