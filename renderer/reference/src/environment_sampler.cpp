#include "environment_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/light_location.hpp"

namespace oer::reference {

namespace {

constexpr double kPi = std::numbers::pi;

// The bin of `u` in a cumulative table cdf[0] = 0 .. cdf[n] = 1, and u's place within it.
std::pair<std::size_t, double> find_bin(const double* cdf, std::size_t n, double u) {
    const double* upper = std::upper_bound(cdf + 1, cdf + n, u);
    std::size_t bin = std::size_t(upper - cdf) - 1;
    // Skip bins of zero width, which upper_bound cannot land in but rounding could.
    while (bin + 1 < n && cdf[bin + 1] <= cdf[bin]) {
        ++bin;
    }
    const double width = cdf[bin + 1] - cdf[bin];
    const double within = width > 0.0 ? std::clamp((u - cdf[bin]) / width, 0.0, 1.0) : 0.5;
    return {bin, within};
}

}  // namespace

EnvironmentSampler::EnvironmentSampler(const HdrImage& map, const Rig& rig,
                                       const std::vector<float>& weights, double yaw_degrees)
    : width_(map.width), height_(map.height), yaw_degrees_(yaw_degrees) {
    if (map.width != rig.source_width || map.height != rig.source_height) {
        throw Error(ErrorKind::InvalidInput,
                    "reference: the map is " + std::to_string(map.width) + "x" +
                        std::to_string(map.height) + ", its rig was made from " +
                        std::to_string(rig.source_width) + "x" + std::to_string(rig.source_height));
    }
    if (!weights.empty() && weights.size() != rig.lights.size()) {
        throw Error(ErrorKind::InvalidInput, "reference: " + std::to_string(weights.size()) +
                                                 " light weights for " +
                                                 std::to_string(rig.lights.size()) + " lights");
    }
    const std::size_t count = map.pixel_count();
    radiance_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        radiance_[i] = glm::dvec3(map.rgb(i));
    }
    // Light k at weight w_k: its pixels (the rig's mask) scaled by w_k.
    for (std::size_t k = 0; k < weights.size(); ++k) {
        if (!(weights[k] >= 0.0f)) {
            throw Error(ErrorKind::InvalidInput,
                        "reference: light " + std::to_string(k) + " has a negative weight");
        }
        for (const std::uint32_t pixel : rig.lights[k].pixels) {
            radiance_[pixel] *= double(weights[k]);
        }
    }
    luminance_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        luminance_[i] = std::max(0.0, luminance(radiance_[i]));
    }
    row_cos_.resize(std::size_t(height_) + 1);
    for (int y = 0; y <= height_; ++y) {
        row_cos_[std::size_t(y)] = std::cos(kPi * y / height_);
    }
    const std::size_t columns = std::size_t(width_) + 1;
    column_cdf_.assign(columns * std::size_t(height_), 0.0);
    row_cdf_.assign(std::size_t(height_) + 1, 0.0);
    for (int y = 0; y < height_; ++y) {
        double* cdf = &column_cdf_[std::size_t(y) * columns];
        const double solid_angle = equirect::pixel_solid_angle(y, width_, height_);
        for (int x = 0; x < width_; ++x) {
            cdf[x + 1] = cdf[x] + luminance_[std::size_t(y) * std::size_t(width_) + x];
        }
        const double row_sum = cdf[width_];
        if (row_sum > 0.0) {
            for (int x = 1; x <= width_; ++x) {
                cdf[x] /= row_sum;
            }
            cdf[width_] = 1.0;
        }
        row_cdf_[std::size_t(y) + 1] = row_cdf_[std::size_t(y)] + row_sum * solid_angle;
    }
    total_weight_ = row_cdf_.back();
    if (total_weight_ > 0.0) {
        for (double& value : row_cdf_) {
            value /= total_weight_;
        }
        row_cdf_.back() = 1.0;
    }
}

EnvironmentSample EnvironmentSampler::sample(double u_row, double u_column, double u_within) const {
    const std::size_t y = find_bin(row_cdf_.data(), std::size_t(height_), u_row).first;
    const double* cdf = &column_cdf_[y * (std::size_t(width_) + 1)];
    const auto [x, u_within_column] = find_bin(cdf, std::size_t(width_), u_column);
    // Uniform in solid angle within pixel (x, y): phi uniform across the column, cos theta
    // uniform between the row's edges (the sphere's area element is dphi d(cos theta)).
    const double phi = 2.0 * kPi * (double(x) + u_within_column) / width_ - kPi;
    const double cos_theta = row_cos_[y] + u_within * (row_cos_[y + 1] - row_cos_[y]);
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const glm::dvec3 map_direction(sin_theta * std::cos(phi), cos_theta, sin_theta * std::sin(phi));
    const std::size_t pixel = y * std::size_t(width_) + x;
    return {equirect::rotate_yaw(map_direction, yaw_degrees_), radiance_[pixel],
            luminance_[pixel] / total_weight_};
}

std::size_t EnvironmentSampler::pixel_of(const glm::dvec3& world_direction) const {
    // The map is turned by +yaw into the world, so a world direction looks it up turned back.
    const glm::dvec2 position = equirect::position_of(
        equirect::rotate_yaw(world_direction, -yaw_degrees_), width_, height_);
    const int x = std::clamp(int(position.x), 0, width_ - 1);
    const int y = std::clamp(int(position.y), 0, height_ - 1);
    return std::size_t(y) * std::size_t(width_) + std::size_t(x);
}

glm::dvec3 EnvironmentSampler::radiance(const glm::dvec3& world_direction) const {
    return radiance_[pixel_of(world_direction)];
}

double EnvironmentSampler::pdf(const glm::dvec3& world_direction) const {
    return can_sample() ? luminance_[pixel_of(world_direction)] / total_weight_ : 0.0;
}

}  // namespace oer::reference
