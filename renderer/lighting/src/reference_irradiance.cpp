#include "oer/lighting/reference_irradiance.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <thread>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"

namespace oer {
namespace {

// Normals per pass over the samples: each sample is loaded once for this many normals.
constexpr std::size_t kNormalBlock = 8;
// Below this many (normal, sample) pairs a second thread costs more than it saves.
constexpr double kMinPairsForThreads = 1 << 22;

typedef double v4d __attribute__((vector_size(32)));

// E(n) for up to kNormalBlock normals at once; every normal sums the samples in sample order,
// exactly as a scalar loop would.
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default"))) void irradiance_block(
    const glm::dvec3* directions, const glm::dvec3* weights, std::size_t samples,
    const glm::dvec3* normals, std::size_t count, glm::dvec3* out) {
    double nx[kNormalBlock] = {}, ny[kNormalBlock] = {}, nz[kNormalBlock] = {};
    for (std::size_t j = 0; j < count; ++j) {
        nx[j] = normals[j].x;
        ny[j] = normals[j].y;
        nz[j] = normals[j].z;
    }
    constexpr std::size_t kVectors = kNormalBlock / 4;
    v4d vx[kVectors], vy[kVectors], vz[kVectors];
    v4d r[kVectors] = {}, g[kVectors] = {}, b[kVectors] = {};
    for (std::size_t v = 0; v < kVectors; ++v) {
        std::memcpy(&vx[v], nx + 4 * v, sizeof(v4d));
        std::memcpy(&vy[v], ny + 4 * v, sizeof(v4d));
        std::memcpy(&vz[v], nz + 4 * v, sizeof(v4d));
    }
    const v4d zero = {};
    for (std::size_t i = 0; i < samples; ++i) {
        const glm::dvec3 d = directions[i];
        const glm::dvec3 w = weights[i];
        for (std::size_t v = 0; v < kVectors; ++v) {
            const v4d dot = vx[v] * d.x + vy[v] * d.y + vz[v] * d.z;
            const v4d cosine = dot > zero ? dot : zero;
            r[v] += cosine * w.x;
            g[v] += cosine * w.y;
            b[v] += cosine * w.z;
        }
    }
    for (std::size_t j = 0; j < count; ++j) {
        out[j] = {r[j / 4][j % 4], g[j / 4][j % 4], b[j / 4][j % 4]};
    }
}

}  // namespace

std::vector<glm::dvec3> fibonacci_sphere(int n) {
    if (n < 0) {
        throw Error(ErrorKind::InvalidInput,
                    "fibonacci_sphere: negative point count " + std::to_string(n));
    }
    const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
    std::vector<glm::dvec3> points(n);
    for (int i = 0; i < n; ++i) {
        const double y = 1.0 - (2.0 * i + 1.0) / n;
        const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
        const double phi = golden_angle * i;
        points[i] = {r * std::cos(phi), y, r * std::sin(phi)};
    }
    return points;
}

ReferenceIrradiance::ReferenceIrradiance(const HdrImage& image, std::size_t max_samples) {
    if (image.width <= 0 || image.height <= 0 || image.pixels.size() != image.pixel_count() * 3) {
        throw Error(ErrorKind::InvalidInput,
                    "ReferenceIrradiance: image of " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + " with " +
                        std::to_string(image.pixels.size()) + " floats is not a valid RGB map");
    }
    const int width = image.width, height = image.height;
    const equirect::Grid grid(width, height);
    // Square blocks of b x b pixels (cut short at the right and bottom edges), the smallest b
    // that gives at most max_samples blocks.
    int b = 1;
    if (max_samples > 0 && image.pixel_count() > max_samples) {
        const auto blocks = [&](int size) {
            return std::size_t((width + size - 1) / size) * std::size_t((height + size - 1) / size);
        };
        b = std::max(1, int(std::sqrt(double(image.pixel_count()) / double(max_samples))));
        while (blocks(b) > max_samples) {
            ++b;
        }
    }
    const std::size_t blocks_x = std::size_t((width + b - 1) / b);
    const std::size_t blocks_y = std::size_t((height + b - 1) / b);
    directions_.reserve(blocks_x * blocks_y);
    weighted_radiance_.reserve(blocks_x * blocks_y);
    if (b == 1) {
        for (int y = 0; y < height; ++y) {
            const double d_omega = grid.row_solid_angle[y];
            for (int x = 0; x < width; ++x) {
                const float* p = image.at(x, y);
                directions_.push_back(grid.direction(x, y));
                weighted_radiance_.push_back(d_omega * glm::dvec3(p[0], p[1], p[2]));
            }
        }
        return;
    }
    for (int y0 = 0; y0 < height; y0 += b) {
        const int y1 = std::min(height, y0 + b);
        for (int x0 = 0; x0 < width; x0 += b) {
            const int x1 = std::min(width, x0 + b);
            glm::dvec3 radiance(0.0), direction(0.0);
            double solid_angle = 0.0;
            for (int y = y0; y < y1; ++y) {
                const double d_omega = grid.row_solid_angle[y];
                for (int x = x0; x < x1; ++x) {
                    const float* p = image.at(x, y);
                    radiance += d_omega * glm::dvec3(p[0], p[1], p[2]);
                    direction += d_omega * grid.direction(x, y);
                    solid_angle += d_omega;
                }
            }
            const double length = glm::length(direction);
            if (length > 1e-9 * solid_angle) {
                direction /= length;
            } else {
                // A block symmetric about the centre of the sphere has no mean direction.
                direction = grid.direction((x0 + x1) / 2, (y0 + y1) / 2);
            }
            directions_.push_back(direction);
            weighted_radiance_.push_back(radiance);
        }
    }
}

glm::dvec3 ReferenceIrradiance::at(const glm::dvec3& normal) const {
    glm::dvec3 result;
    irradiance_block(directions_.data(), weighted_radiance_.data(), directions_.size(), &normal, 1,
                     &result);
    return result;
}

std::vector<glm::dvec3> ReferenceIrradiance::at(std::span<const glm::dvec3> normals) const {
    std::vector<glm::dvec3> result(normals.size());
    const auto run = [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; i += kNormalBlock) {
            irradiance_block(directions_.data(), weighted_radiance_.data(), directions_.size(),
                             normals.data() + i, std::min(kNormalBlock, end - i), &result[i]);
        }
    };
    const bool two_threads =
        normals.size() >= 2 * kNormalBlock &&
        double(normals.size()) * double(directions_.size()) >= kMinPairsForThreads;
    if (!two_threads) {
        run(0, normals.size());
        return result;
    }
    // Whole blocks for the first thread, the rest for the second.
    const std::size_t split = (normals.size() / 2 + kNormalBlock - 1) / kNormalBlock * kNormalBlock;
    std::thread worker([&] { run(split, normals.size()); });  // does not throw
    run(0, split);
    worker.join();
    return result;
}

double relative_rms_error(std::span<const glm::dvec3> approx,
                          std::span<const glm::dvec3> reference) {
    if (approx.size() != reference.size() || reference.empty()) {
        throw Error(ErrorKind::InvalidInput,
                    "relative_rms_error: " + std::to_string(approx.size()) + " values against " +
                        std::to_string(reference.size()) + " reference values");
    }
    double error = 0.0, norm = 0.0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
        const glm::dvec3 d = approx[i] - reference[i];
        error += glm::dot(d, d);
        norm += glm::dot(reference[i], reference[i]);
    }
    if (norm == 0.0) {
        return error == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    }
    return std::sqrt(error / norm);
}

}  // namespace oer
