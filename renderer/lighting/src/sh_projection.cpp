#include "oer/lighting/sh_projection.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "sh_axis_swap.hpp"
#include "sh_row_harmonics.hpp"
#include "two_thread_split.hpp"

namespace oer {
namespace {

// Separable projection (docs/design.md section 3 conventions). In the basis with polar axis +Y,
// Y'_lm(v) = Y_lm(v.x, v.z, v.y) = N_l^|m|(cos theta) sin^|m|(theta) (cos m phi | sin |m| phi)
// with the equirect angles themselves, so
//   c'_lm = sum over rows y of dOmega(y) N_l^|m|(cos theta_y) sin^|m|(theta_y) S_m(y),
// S_m(y) the azimuthal Fourier sums of row y. c' converts to our basis band by band.

using Coefficients = std::vector<glm::dvec3>;  // order^2, in the primed basis until converted

// Below this many pixels a second thread costs more than it saves.
constexpr std::size_t kMinPixelsPerThread = std::size_t(1) << 15;

struct RowWeights {
    int order;
    double legendre[detail::legendre_count(kMaxShOrder)];

    // sums: 3 (2 order - 1) values as written by row_harmonic_sums.
    void add_row(const equirect::Grid& grid, int y, const double* sums, Coefficients& out) {
        detail::sh_legendre(order, grid.row_cos_theta[y], grid.row_sin_theta[y], legendre);
        const double solid_angle = grid.row_solid_angle[y];
        const auto term = [sums](int k) {
            return glm::dvec3(sums[3 * k], sums[3 * k + 1], sums[3 * k + 2]);
        };
        for (int l = 0; l < order; ++l) {
            out[sh_index(l, 0)] += (legendre[detail::legendre_index(l, 0)] * solid_angle) * term(0);
            for (int m = 1; m <= l; ++m) {
                const double w = legendre[detail::legendre_index(l, m)] * solid_angle;
                out[sh_index(l, m)] += w * term(2 * m - 1);
                out[sh_index(l, -m)] += w * term(2 * m);
            }
        }
    }
};

struct Partial {
    Coefficients all;
    std::vector<Coefficients> lights;
};

// Rows [y_begin, y_end) of the map, and every light pixel in those rows.
void project_rows(const HdrImage& image, const equirect::Grid& grid,
                  const detail::AzimuthTable& table,
                  std::span<const std::vector<std::uint32_t>> light_pixels, int order, int y_begin,
                  int y_end, Partial& out) {
    const int terms = table.terms();
    std::vector<double> scratch(3 * table.stride());
    std::vector<double> sums(3 * std::size_t(terms));
    RowWeights weights{order, {}};
    for (int y = y_begin; y < y_end; ++y) {
        detail::row_harmonic_sums(table, image.at(0, y), scratch.data(), sums.data());
        weights.add_row(grid, y, sums.data(), out.all);
    }

    // Light pixels: runs of indices in one row share that row's weights. Lists need not be
    // sorted for correctness (sorted lists make the fewest runs).
    const std::size_t width = std::size_t(image.width);
    const std::size_t begin = std::size_t(y_begin) * width, end = std::size_t(y_end) * width;
    for (std::size_t k = 0; k < light_pixels.size(); ++k) {
        int run_row = -1;
        std::fill(sums.begin(), sums.end(), 0.0);
        for (const std::uint32_t index : light_pixels[k]) {
            if (index < begin || index >= end) {
                continue;
            }
            const int y = int(index / width);
            const int x = int(index % width);
            if (y != run_row) {
                if (run_row >= 0) {
                    weights.add_row(grid, run_row, sums.data(), out.lights[k]);
                    std::fill(sums.begin(), sums.end(), 0.0);
                }
                run_row = y;
            }
            const float* p = image.at(x, y);
            const double r = p[0], g = p[1], b = p[2];
            for (int t = 0; t < terms; ++t) {
                const double value = table.at(t, x);
                sums[3 * t] += value * r;
                sums[3 * t + 1] += value * g;
                sums[3 * t + 2] += value * b;
            }
        }
        if (run_row >= 0) {
            weights.add_row(grid, run_row, sums.data(), out.lights[k]);
        }
    }
}

ShRgb to_our_basis(const Coefficients& primed, int order) {
    ShRgb result(order);
    for (int l = 0; l < order; ++l) {
        const std::vector<double>& d = detail::axis_swap_matrix(l);
        const int size = 2 * l + 1;
        for (int m = -l; m <= l; ++m) {
            glm::dvec3 sum(0.0);
            for (int m2 = -l; m2 <= l; ++m2) {
                sum += d[std::size_t(m + l) * size + (m2 + l)] * primed[sh_index(l, m2)];
            }
            result.coefficients[sh_index(l, m)] = sum;
        }
    }
    return result;
}

void validate(const HdrImage& image, std::span<const std::vector<std::uint32_t>> light_pixels,
              int order) {
    if (order < 1 || order > kMaxShOrder) {
        throw Error(ErrorKind::InvalidInput, "project_environment: SH order " +
                                                 std::to_string(order) + " is not in [1, " +
                                                 std::to_string(kMaxShOrder) + "]");
    }
    if (image.width <= 0 || image.height <= 0 || image.pixels.size() != image.pixel_count() * 3) {
        throw Error(ErrorKind::InvalidInput,
                    "project_environment: image of " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + " with " +
                        std::to_string(image.pixels.size()) + " floats is not a valid RGB map");
    }
    const std::size_t count = image.pixel_count();
    for (std::size_t k = 0; k < light_pixels.size(); ++k) {
        for (const std::uint32_t index : light_pixels[k]) {
            if (index >= count) {
                throw Error(ErrorKind::InvalidInput, "project_environment: light " +
                                                         std::to_string(k) + " has pixel index " +
                                                         std::to_string(index) + ", the map has " +
                                                         std::to_string(count) + " pixels");
            }
        }
    }
}

}  // namespace

ShProjection project_environment(const HdrImage& image,
                                 std::span<const std::vector<std::uint32_t>> light_pixels,
                                 int order) {
    validate(image, light_pixels, order);
    const equirect::Grid grid(image.width, image.height);
    const detail::AzimuthTable table(image.width, order);
    for (int l = 0; l < order; ++l) {
        detail::axis_swap_matrix(l);  // computed (once) before the threads start
    }

    const auto make_partial = [&] {
        Partial partial;
        partial.all.assign(sh_count(order), glm::dvec3(0.0));
        partial.lights.assign(light_pixels.size(), partial.all);
        return partial;
    };
    // The split depends on the image size only, and the halves are summed in a fixed order, so
    // the result is deterministic.
    // The halves split at the horizon, so that the first is the map above it.
    const bool two_threads = image.pixel_count() >= 2 * kMinPixelsPerThread && image.height >= 2;
    const int split = image.height / 2;
    Partial first = make_partial();
    Partial second = make_partial();
    if (two_threads) {
        detail::split_on_two_threads(image.height, split, [&](int begin, int end) {
            project_rows(image, grid, table, light_pixels, order, begin, end,
                         begin == 0 ? first : second);
        });
    } else {
        project_rows(image, grid, table, light_pixels, order, 0, split, first);
        project_rows(image, grid, table, light_pixels, order, split, image.height, second);
    }

    const auto combine = [&](Coefficients& a, const Coefficients& b) {
        for (std::size_t i = 0; i < a.size(); ++i) {
            a[i] += b[i];
        }
        return to_our_basis(a, order);
    };
    ShProjection result;
    result.all_above_horizon = to_our_basis(first.all, order);
    for (const Coefficients& light : first.lights) {
        result.per_light_above_horizon.push_back(to_our_basis(light, order));
    }
    result.all = combine(first.all, second.all);
    result.per_light.reserve(light_pixels.size());
    for (std::size_t k = 0; k < light_pixels.size(); ++k) {
        result.per_light.push_back(combine(first.lights[k], second.lights[k]));
    }
    return result;
}

ShRgb residual_above_horizon(const ShProjection& projection, int order) {
    if (projection.all_above_horizon.order < order ||
        projection.per_light_above_horizon.size() != projection.per_light.size()) {
        throw Error(ErrorKind::InvalidInput,
                    "residual_above_horizon: the projection has no above-horizon part at order " +
                        std::to_string(order));
    }
    ShRgb residual = projection.all_above_horizon.truncated(order);
    for (const ShRgb& light : projection.per_light_above_horizon) {
        residual -= light.truncated(order);
    }
    return residual;
}

ShRgb subset_coefficients(const ShProjection& projection, std::span<const bool> on) {
    if (on.size() != projection.per_light.size()) {
        throw Error(ErrorKind::InvalidInput,
                    "subset_coefficients: " + std::to_string(on.size()) + " on/off flags for " +
                        std::to_string(projection.per_light.size()) + " lights");
    }
    ShRgb result = projection.all;
    for (std::size_t k = 0; k < on.size(); ++k) {
        if (!on[k]) {
            result -= projection.per_light[k];
        }
    }
    return result;
}

ShRgb visibility_coefficients(const ShProjection& projection, std::span<const double> visibility) {
    if (visibility.size() != projection.per_light.size()) {
        throw Error(ErrorKind::InvalidInput,
                    "visibility_coefficients: " + std::to_string(visibility.size()) +
                        " visibilities for " + std::to_string(projection.per_light.size()) +
                        " lights");
    }
    ShRgb result = projection.all;
    for (std::size_t k = 0; k < visibility.size(); ++k) {
        const double v = visibility[k];
        if (!(v >= 0.0 && v <= 1.0)) {
            throw Error(ErrorKind::InvalidInput, "visibility_coefficients: visibility " +
                                                     std::to_string(v) + " of light " +
                                                     std::to_string(k) + " is not in [0, 1]");
        }
        if (v == 1.0) {
            continue;
        }
        ShRgb off = projection.per_light[k];
        off *= 1.0 - v;
        result -= off;
    }
    return result;
}

}  // namespace oer
