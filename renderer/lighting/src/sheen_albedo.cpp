// The sheen BRDF's directional albedo (sheen_albedo.hpp). Each entry integrates over half vectors
// drawn with pdf D(h) n.h, which the Charlie distribution normalises exactly
// (the integral of (2 + 1/a) sin^(1/a) cos sin dtheta is 1): sin(theta_h) = u^(a / (2 a + 1)).
// The light l = reflect(-v, h) then has pdf D n.h / (4 v.h), so each sample weighs
// D V n.l / pdf = 4 V n.l v.h / n.h. The samples are a Hammersley set, the same for every entry.
#include "oer/lighting/sheen_albedo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/sampling.hpp"
#include "table_lookup.hpp"

namespace oer {

namespace {

// The extension's roughness floor: a = r^2 at least 1e-7, so that 1 / a stays finite (the Khronos
// glTF-Sample-Viewer clamps r to 1e-6 likewise before squaring it).
double sheen_alpha(double roughness) {
    return std::max(roughness * roughness, 1e-7);
}

// Estevez and Kulla's fit of the sheen's lambda, as the extension gives it: L(x) = a / (1 + b
// x^c) + d x + e, its coefficients interpolated in (1 - alpha)^2 between their two fits.
double lambda_fit(double x, double alpha) {
    const double t = (1.0 - alpha) * (1.0 - alpha);
    const auto mix = [t](double from, double to) { return from + (to - from) * t; };
    const double a = mix(21.5473, 25.3245);
    const double b = mix(3.82987, 3.32435);
    const double c = mix(0.19823, 0.16801);
    const double d = mix(-1.97760, -1.27393);
    const double e = mix(-4.32054, -4.85967);
    return a / (1.0 + b * std::pow(x, c)) + d * x + e;
}

// Lambda(cos theta): exp(L(cos theta)) below 0.5, mirrored above it for smoothness (the
// extension's "Sheen visibility").
double sheen_lambda(double cos_theta, double alpha) {
    return cos_theta < 0.5
               ? std::exp(lambda_fit(cos_theta, alpha))
               : std::exp(2.0 * lambda_fit(0.5, alpha) - lambda_fit(1.0 - cos_theta, alpha));
}

double sheen_visibility(double n_dot_v, double n_dot_l, double alpha) {
    return 1.0 / ((1.0 + sheen_lambda(n_dot_v, alpha) + sheen_lambda(n_dot_l, alpha)) * 4.0 *
                  n_dot_v * n_dot_l);
}

double integrate_sheen(double n_dot_v, double roughness, int samples) {
    const double alpha = sheen_alpha(roughness);
    const glm::dvec3 v(std::sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    double sum = 0.0;
    for (int i = 0; i < samples; ++i) {
        const double phi = 2.0 * std::numbers::pi * (double(i) + 0.5) / double(samples);
        const double u = sampling::radical_inverse(std::uint32_t(i));
        const double sin_theta = std::pow(u, alpha / (2.0 * alpha + 1.0));
        const double cos_theta = std::sqrt(std::max(0.0, 1.0 - sin_theta * sin_theta));
        const glm::dvec3 h(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
        const double v_dot_h = glm::dot(v, h);
        const glm::dvec3 l = 2.0 * v_dot_h * h - v;
        if (l.z <= 0.0 || v_dot_h <= 0.0 || cos_theta <= 0.0) {
            continue;
        }
        sum += 4.0 * sheen_visibility(n_dot_v, l.z, alpha) * l.z * v_dot_h / cos_theta;
    }
    return sum / double(samples);
}

}  // namespace

double sample_sheen_albedo(const SheenAlbedoTable& table, double n_dot_v, double roughness) {
    return detail::bilinear_lookup(table.size, n_dot_v, roughness, [&](int column, int row) {
        return double(
            table.albedo[std::size_t(row) * std::size_t(table.size) + std::size_t(column)]);
    });
}

SheenAlbedoTable sheen_albedo_table(int size, int samples) {
    if (size < 2 || size > 256) {
        throw Error(ErrorKind::InvalidInput,
                    "sheen_albedo_table: size must be in [2, 256], got " + std::to_string(size));
    }
    if (samples < 1 || samples > 65536) {
        throw Error(
            ErrorKind::InvalidInput,
            "sheen_albedo_table: samples must be in [1, 65536], got " + std::to_string(samples));
    }
    SheenAlbedoTable table;
    table.size = size;
    table.albedo.resize(std::size_t(size) * std::size_t(size));
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            // The fitted visibility lets the lobe reflect more than arrives at grazing view and
            // low roughness (3.2 at n.v and roughness 1/64, 1.08 at n.v 1/64 and roughness
            // 0.2): at most 1, so that the albedo scaling beneath never turns negative and a
            // white sheen over a white base never brightens a furnace.
            table.albedo[std::size_t(j) * std::size_t(size) + std::size_t(i)] =
                float(std::min(1.0, integrate_sheen((i + 0.5) / size, (j + 0.5) / size, samples)));
        }
    }
    return table;
}

}  // namespace oer
