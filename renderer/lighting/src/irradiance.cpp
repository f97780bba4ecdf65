#include "oer/lighting/irradiance.hpp"

#include "oer/core/enum_names.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/lighting/reference_irradiance.hpp"

namespace oer {
namespace {

using std::numbers::pi;

void require_valid(const ShRgb& sh, const char* what) {
    if (sh.order < 1 || sh.order > kMaxShOrder ||
        sh.coefficients.size() != std::size_t(sh_count(sh.order))) {
        throw Error(ErrorKind::InvalidInput,
                    std::string(what) + ": " + std::to_string(sh.coefficients.size()) +
                        " coefficients for SH order " + std::to_string(sh.order));
    }
}

// Normals on which deringing checks the irradiance (a fixed set, so results are reproducible).
constexpr int kCheckNormals = 2048;
// Irradiance down to -kNegativeTolerance times the largest counts as non-negative (rounding).
constexpr double kNegativeTolerance = 1e-9;

// Per-band irradiance A_l sum_m L_lm Y_lm(n) of the whole map and of each light, on the check
// normals, so that any window is a weighted sum over bands.
struct BandIrradiance {
    int order = 0;
    std::size_t sets = 0;  // 1 + number of lights; set 0 is the whole map
    std::size_t normals = 0;
    std::vector<glm::dvec3> values;  // [(set * normals + normal) * order + l]

    explicit BandIrradiance(const ShProjection& projection) {
        require_valid(projection.all, "deringing");
        order = projection.all.order;
        for (const ShRgb& light : projection.per_light) {
            require_valid(light, "deringing");
            if (light.order != order) {
                throw Error(ErrorKind::InvalidInput,
                            "deringing: a light's SH order differs from the map's");
            }
        }
        sets = 1 + projection.per_light.size();
        const std::vector<glm::dvec3> directions = fibonacci_sphere(kCheckNormals);
        normals = directions.size();
        values.assign(sets * normals * std::size_t(order), glm::dvec3(0.0));
        double basis[sh_count(kMaxShOrder)];
        for (std::size_t n = 0; n < normals; ++n) {
            sh_evaluate(order, directions[n], basis);
            for (std::size_t set = 0; set < sets; ++set) {
                const ShRgb& sh = set == 0 ? projection.all : projection.per_light[set - 1];
                glm::dvec3* out = &values[(set * normals + n) * std::size_t(order)];
                for (int l = 0; l < order; ++l) {
                    glm::dvec3 sum(0.0);
                    for (int m = -l; m <= l; ++m) {
                        sum += sh.coefficients[sh_index(l, m)] * basis[sh_index(l, m)];
                    }
                    out[l] = lambertian_band_factor(l) * sum;
                }
            }
        }
    }

    // See min_relative_irradiance. The subset with the least irradiance in a channel at a
    // normal switches off exactly the lights whose own irradiance there is positive, so the
    // minimum over all 2^n subsets is E_all - sum_k max(0, E_k), per normal and channel.
    double min_relative(const ShWindow& window) const {
        std::vector<double> w(order);
        for (int l = 0; l < order; ++l) {
            w[l] = window.factor(l);
        }
        const auto irradiance = [&](std::size_t set, std::size_t n) {
            const glm::dvec3* bands = &values[(set * normals + n) * std::size_t(order)];
            glm::dvec3 sum(0.0);
            for (int l = 0; l < order; ++l) {
                sum += w[l] * bands[l];
            }
            return sum;
        };
        glm::dvec3 lowest(std::numeric_limits<double>::infinity());
        glm::dvec3 highest(-std::numeric_limits<double>::infinity());
        for (std::size_t n = 0; n < normals; ++n) {
            const glm::dvec3 all = irradiance(0, n);
            glm::dvec3 least = all;
            for (std::size_t set = 1; set < sets; ++set) {
                least -= glm::max(irradiance(set, n), glm::dvec3(0.0));
            }
            lowest = glm::min(lowest, least);
            highest = glm::max(highest, all);
        }
        double result = 0.0;
        for (int c = 0; c < 3; ++c) {
            if (highest[c] > 0.0) {
                result = std::min(result, lowest[c] / highest[c]);
            }
        }
        return result;
    }
};

}  // namespace

double ShWindow::factor(int l) const {
    if (kind == WindowKind::None) {
        return 1.0;
    }
    if (!(cutoff > 0.0) || !std::isfinite(cutoff)) {
        throw Error(ErrorKind::InvalidInput, "ShWindow: cutoff " + std::to_string(cutoff) +
                                                 " of a " + to_string(kind) +
                                                 " window is not a positive number");
    }
    if (l < 0) {
        throw Error(ErrorKind::InvalidInput,
                    "ShWindow::factor: band " + std::to_string(l) + " is negative");
    }
    if (l >= cutoff) {
        return 0.0;
    }
    const double x = pi * l / cutoff;
    switch (kind) {
        case WindowKind::Hanning:
            return 0.5 * (1.0 + std::cos(x));
        case WindowKind::Lanczos:
            return l == 0 ? 1.0 : std::sin(x) / x;
        case WindowKind::None:
            break;
    }
    return 1.0;
}

namespace {
constexpr EnumNames<WindowKind, 3> kWindowNames = {{{WindowKind::None, "none"},
                                                    {WindowKind::Hanning, "hanning"},
                                                    {WindowKind::Lanczos, "lanczos"}}};
}  // namespace

std::string to_string(WindowKind kind) {
    return name_of(kind, kWindowNames);
}

WindowKind window_kind_from_string(const std::string& name) {
    return value_named(name, kWindowNames, "SH window");
}

ShRgb irradiance_coefficients(const ShRgb& radiance, const ShWindow& window) {
    require_valid(radiance, "irradiance_coefficients");
    ShRgb result(radiance.order);
    for (int l = 0; l < radiance.order; ++l) {
        const double factor = lambertian_band_factor(l) * window.factor(l);
        for (int m = -l; m <= l; ++m) {
            result.coefficients[sh_index(l, m)] = factor * radiance.coefficients[sh_index(l, m)];
        }
    }
    return result;
}

std::array<glm::dmat4, 3> irradiance_matrices(const ShRgb& radiance) {
    require_valid(radiance, "irradiance_matrices");
    if (radiance.order < 3) {
        throw Error(ErrorKind::InvalidInput, "irradiance_matrices: needs SH order >= 3, got " +
                                                 std::to_string(radiance.order));
    }
    // The matrix form of Ramamoorthi and Hanrahan, "An Efficient Representation for Irradiance
    // Environment Maps", SIGGRAPH 2001, eq. 12: c1 = A_2 times Y_22's constant 0.546274
    // = 0.429043, ..., c5 = A_2 times Y_20's 0.315392 = 0.247708 (their basis ordering is ours).
    constexpr double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    std::array<glm::dmat4, 3> result;
    for (int c = 0; c < 3; ++c) {
        const auto L = [&](int l, int m) { return radiance.coefficients[sh_index(l, m)][c]; };
        const double rows[4][4] = {
            {c1 * L(2, 2), c1 * L(2, -2), c1 * L(2, 1), c2 * L(1, 1)},
            {c1 * L(2, -2), -c1 * L(2, 2), c1 * L(2, -1), c2 * L(1, -1)},
            {c1 * L(2, 1), c1 * L(2, -1), c3 * L(2, 0), c2 * L(1, 0)},
            {c2 * L(1, 1), c2 * L(1, -1), c2 * L(1, 0), c4 * L(0, 0) - c5 * L(2, 0)},
        };
        glm::dmat4 m(0.0);
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) {
                m[j][i] = rows[i][j];  // glm is column-major; the matrix is symmetric anyway
            }
        }
        result[c] = m;
    }
    return result;
}

double min_relative_irradiance(const ShProjection& projection, const ShWindow& window) {
    return BandIrradiance(projection).min_relative(window);
}

ShWindow choose_deringing_window(const ShProjection& projection, WindowKind kind) {
    const BandIrradiance bands(projection);
    const auto feasible = [&](const ShWindow& window) {
        return bands.min_relative(window) >= -kNegativeTolerance;
    };
    if (kind == WindowKind::None || feasible(ShWindow{})) {
        return ShWindow{};
    }
    // Upper end of the search: a cutoff that still rings (windows tend to 1 as it grows).
    double high = 4.0 * bands.order;
    while (feasible({kind, high}) && high < 1024.0 * bands.order) {
        high *= 2.0;
    }
    if (feasible({kind, high})) {
        return {kind, high};
    }
    // A coarse scan from the top finds the largest feasible grid cutoff (the feasible set need
    // not be an interval), then bisection sharpens the boundary above it.
    constexpr int kScanSteps = 64;
    int step = kScanSteps - 1;
    while (step >= 1 && !feasible({kind, high * step / kScanSteps})) {
        --step;
    }
    if (step < 1) {
        // Even the strongest window rings: the map's own average is negative somewhere
        // (negative radiance); return the strongest window tried.
        return {kind, high / kScanSteps};
    }
    double lo = high * step / kScanSteps;
    double hi = high * (step + 1) / kScanSteps;
    for (int iteration = 0; iteration < 60 && hi - lo > 1e-12 * hi; ++iteration) {
        const double mid = 0.5 * (lo + hi);
        if (feasible({kind, mid})) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return {kind, lo};
}

}  // namespace oer
