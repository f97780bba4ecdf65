#include "literal_thesis.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <random>

#include "oer/lighting/equirect.hpp"

namespace oer::bench {

using std::numbers::pi;

namespace {

// Normalised gaussian weights w[i + radius], i in [-radius, radius], sigma = radius / 2.
std::vector<double> gaussian_kernel(int radius) {
    std::vector<double> weights(std::size_t(2 * radius + 1), 1.0);
    if (radius <= 0) {
        return weights;
    }
    const double sigma = radius / 2.0;
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        weights[std::size_t(i + radius)] = std::exp(-(i * i) / (2.0 * sigma * sigma));
        sum += weights[std::size_t(i + radius)];
    }
    for (double& w : weights) {
        w /= sum;
    }
    return weights;
}

// 2-D separable gaussian blur of the RGB map, clamping at every border.
HdrImage blur_clamped(const HdrImage& image, int radius) {
    radius = std::max(radius, 0);
    const std::vector<double> kernel = gaussian_kernel(radius);
    const int w = image.width, h = image.height;
    HdrImage horizontal(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            double sum[3] = {0.0, 0.0, 0.0};
            for (int i = -radius; i <= radius; ++i) {
                const int sx = std::clamp(x + i, 0, w - 1);
                const float* p = image.at(sx, y);
                const double weight = kernel[std::size_t(i + radius)];
                for (int c = 0; c < 3; ++c) {
                    sum[c] += weight * p[c];
                }
            }
            float* out = horizontal.at(x, y);
            for (int c = 0; c < 3; ++c) {
                out[c] = float(sum[c]);
            }
        }
    }
    HdrImage blurred(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            double sum[3] = {0.0, 0.0, 0.0};
            for (int i = -radius; i <= radius; ++i) {
                const int sy = std::clamp(y + i, 0, h - 1);
                const float* p = horizontal.at(x, sy);
                const double weight = kernel[std::size_t(i + radius)];
                for (int c = 0; c < 3; ++c) {
                    sum[c] += weight * p[c];
                }
            }
            float* out = blurred.at(x, y);
            for (int c = 0; c < 3; ++c) {
                out[c] = float(sum[c]);
            }
        }
    }
    return blurred;
}

// The value at fraction p of sorted values.
double percentile_of_sorted(const std::vector<double>& sorted, double p) {
    const double position = p * double(sorted.size() - 1);
    return sorted[std::min(sorted.size() - 1, std::size_t(position))];
}

struct Point {
    double x = 0.0;
    double y = 0.0;
};

// Lloyd's k-means in 2-D with centres drawn at random from the points; labels[i] in [0, k).
std::vector<Point> kmeans(const std::vector<Point>& points, int k, int max_iterations,
                          std::mt19937& random, std::vector<int>& labels) {
    // k distinct points as initial centres.
    std::vector<std::size_t> chosen;
    std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
    while (chosen.size() < std::size_t(k)) {
        const std::size_t candidate = pick(random);
        if (std::find(chosen.begin(), chosen.end(), candidate) == chosen.end()) {
            chosen.push_back(candidate);
        }
    }
    std::vector<Point> centres;
    for (const std::size_t i : chosen) {
        centres.push_back(points[i]);
    }
    labels.assign(points.size(), -1);
    for (int iteration = 0; iteration < max_iterations; ++iteration) {
        bool changed = false;
        for (std::size_t i = 0; i < points.size(); ++i) {
            int best = 0;
            double best_distance = std::numeric_limits<double>::max();
            for (int c = 0; c < k; ++c) {
                const double dx = points[i].x - centres[c].x;
                const double dy = points[i].y - centres[c].y;
                const double distance = dx * dx + dy * dy;
                if (distance < best_distance) {
                    best_distance = distance;
                    best = c;
                }
            }
            if (labels[i] != best) {
                labels[i] = best;
                changed = true;
            }
        }
        if (!changed) {
            break;
        }
        std::vector<Point> sums(static_cast<std::size_t>(k));
        std::vector<std::size_t> counts(std::size_t(k), 0);
        for (std::size_t i = 0; i < points.size(); ++i) {
            sums[labels[i]].x += points[i].x;
            sums[labels[i]].y += points[i].y;
            ++counts[labels[i]];
        }
        for (int c = 0; c < k; ++c) {
            if (counts[c] > 0) {  // an empty cluster keeps its centre
                centres[c] = {sums[c].x / double(counts[c]), sums[c].y / double(counts[c])};
            }
        }
    }
    return centres;
}

}  // namespace

std::vector<double> literal_luminance(const HdrImage& image, int blur_radius) {
    const HdrImage blurred = blur_clamped(image, blur_radius);
    std::vector<double> luminance(image.pixel_count());
    for (std::size_t i = 0; i < luminance.size(); ++i) {
        const float* p = &blurred.pixels[i * 3];
        luminance[i] = 179.0 * (0.265 * p[0] + 0.670 * p[1] + 0.065 * p[2]);
    }
    return luminance;
}

std::vector<LiteralLight> literal_locate_lights(const HdrImage& image,
                                                const LiteralOptions& options) {
    std::vector<LiteralLight> lights;
    if (image.pixel_count() == 0 || options.light_count <= 0) {
        return lights;
    }
    const int w = image.width, h = image.height;
    const std::vector<double> luminance = literal_luminance(image, options.blur_radius);
    // Both thresholds from one full sort of a copy of every luminance value.
    std::vector<double> sorted = luminance;
    std::sort(sorted.begin(), sorted.end());
    const double light_threshold = percentile_of_sorted(sorted, options.light_percentile);
    const double halo_threshold = percentile_of_sorted(sorted, options.halo_percentile);
    sorted = {};
    double total_luminance = 0.0;
    for (const double l : luminance) {
        total_luminance += l;
    }

    // The bright set and the halo set, as pixel indices; removed pixels leave both.
    std::vector<std::uint32_t> bright, halo;
    for (std::size_t i = 0; i < luminance.size(); ++i) {
        if (luminance[i] >= light_threshold) {
            bright.push_back(std::uint32_t(i));
        }
        if (luminance[i] >= halo_threshold) {
            halo.push_back(std::uint32_t(i));
        }
    }
    std::vector<bool> removed(image.pixel_count(), false);

    std::mt19937 random(options.seed);
    int clusters = options.cluster_count;
    while (int(lights.size()) < options.light_count) {
        std::vector<std::uint32_t> remaining;
        std::vector<Point> points;
        for (const std::uint32_t i : bright) {
            if (!removed[i]) {
                remaining.push_back(i);
                points.push_back({double(i % std::uint32_t(w)), double(i / std::uint32_t(w))});
            }
        }
        if (points.empty()) {
            break;  // no bright pixel left: fewer lights than asked
        }
        const int k = std::max(1, std::min(clusters, int(points.size())));
        std::vector<int> labels;
        const std::vector<Point> centres =
            kmeans(points, k, options.max_iterations, random, labels);

        // The cluster of greatest mean luminance.
        std::vector<double> luminance_sum(std::size_t(k), 0.0);
        std::vector<std::size_t> counts(std::size_t(k), 0);
        for (std::size_t i = 0; i < points.size(); ++i) {
            luminance_sum[labels[i]] += luminance[remaining[i]];
            ++counts[labels[i]];
        }
        int best = -1;
        double best_mean = -std::numeric_limits<double>::max();
        for (int c = 0; c < k; ++c) {
            if (counts[c] > 0 && luminance_sum[c] / double(counts[c]) > best_mean) {
                best_mean = luminance_sum[c] / double(counts[c]);
                best = c;
            }
        }

        // Its spread, and the halo pixels within 3 max(sigma) of its centre.
        double variance_x = 0.0, variance_y = 0.0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (labels[i] == best) {
                variance_x += (points[i].x - centres[best].x) * (points[i].x - centres[best].x);
                variance_y += (points[i].y - centres[best].y) * (points[i].y - centres[best].y);
            }
        }
        variance_x /= double(counts[best]);
        variance_y /= double(counts[best]);
        LiteralLight light;
        light.centre_x = centres[best].x;
        light.centre_y = centres[best].y;
        light.radius = 3.0 * std::max(std::sqrt(variance_x), std::sqrt(variance_y));
        glm::dvec3 direction_sum(0.0);
        double light_luminance = 0.0;
        for (const std::uint32_t i : halo) {
            if (removed[i]) {
                continue;
            }
            const int x = int(i % std::uint32_t(w)), y = int(i / std::uint32_t(w));
            const double dx = x - light.centre_x, dy = y - light.centre_y;
            if (dx * dx + dy * dy <= light.radius * light.radius) {
                removed[i] = true;
                light.pixels.push_back(i);
                direction_sum += equirect::pixel_direction(x, y, w, h);
                light_luminance += luminance[i];
            }
        }
        const double length =
            std::sqrt(direction_sum.x * direction_sum.x + direction_sum.y * direction_sum.y +
                      direction_sum.z * direction_sum.z);
        if (length > 0.0) {
            light.direction = direction_sum / length;
        }
        light.luminance_loss = total_luminance > 0.0 ? light_luminance / total_luminance : 0.0;
        lights.push_back(std::move(light));
        --clusters;
    }
    return lights;
}

std::array<double, 9> literal_sh3_basis(const glm::dvec3& d) {
    // Ramamoorthi and Hanrahan 2001, eq. 3 (constants in closed form rather than to 6 digits,
    // so that the figures compare with the library's to rounding error).
    const double c0 = 0.5 * std::sqrt(1.0 / pi);    // 0.282095
    const double c1 = std::sqrt(3.0 / (4.0 * pi));  // 0.488603
    const double c2 = 0.5 * std::sqrt(15.0 / pi);   // 1.092548
    const double c3 = 0.25 * std::sqrt(5.0 / pi);   // 0.315392
    const double c4 = 0.25 * std::sqrt(15.0 / pi);  // 0.546274
    return {c0,
            c1 * d.y,
            c1 * d.z,
            c1 * d.x,
            c2 * d.x * d.y,
            c2 * d.y * d.z,
            c3 * (3.0 * d.z * d.z - 1.0),
            c2 * d.x * d.z,
            c4 * (d.x * d.x - d.y * d.y)};
}

LiteralSh3 literal_project_order3(const HdrImage& image) {
    const int w = image.width, h = image.height;
    LiteralSh3 coefficients;
    coefficients.fill(glm::dvec3(0.0));
    for (int y = 0; y < h; ++y) {
        const double solid_angle =
            (2.0 * pi / w) * (std::cos(pi * y / h) - std::cos(pi * (y + 1) / h));
        for (int x = 0; x < w; ++x) {
            const float* p = image.at(x, y);
            const glm::dvec3 radiance(p[0], p[1], p[2]);
            const glm::dvec3 direction = equirect::pixel_direction(x, y, w, h);
            const std::array<double, 9> basis = literal_sh3_basis(direction);
            for (int i = 0; i < 9; ++i) {
                coefficients[i] += radiance * (basis[i] * solid_angle);
            }
        }
    }
    return coefficients;
}

LiteralResult literal_thesis_preprocess(const HdrImage& image, const LiteralOptions& options) {
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point start) {
        return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    };
    LiteralResult result;
    auto start = Clock::now();
    result.lights = literal_locate_lights(image, options);
    result.locate_ms = since(start);
    start = Clock::now();
    const std::size_t n = result.lights.size();
    const std::size_t subsets = std::size_t(1) << n;
    result.oems.reserve(subsets);
    for (std::size_t s = 0; s < subsets; ++s) {
        HdrImage occluded = image;  // a full copy per OEM
        for (std::size_t k = 0; k < n; ++k) {
            if ((s >> k) & 1u) {
                continue;  // light k is on
            }
            for (const std::uint32_t i : result.lights[k].pixels) {
                occluded.set(i, glm::vec3(0.0f));
            }
        }
        result.oems.push_back(literal_project_order3(occluded));
    }
    result.oems_ms = since(start);
    return result;
}

}  // namespace oer::bench
