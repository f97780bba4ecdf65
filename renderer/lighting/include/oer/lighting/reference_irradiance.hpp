#pragma once
// The brute-force ground truth for every accuracy figure: the exact irradiance of the thesis's
// eq. 2.1 (Ambrosj, "Occluded Environment Maps Rendering", 2016) with each pixel weighted by
// its exact solid angle, E(n) = sum over pixels L(pixel) max(0, n . dir) dOmega, in double.
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/core/image.hpp"

namespace oer {

// n points spread evenly over the unit sphere (the spherical Fibonacci lattice of A. Gonzalez,
// "Measurement of Areas on a Sphere Using Fibonacci and Latitude-Longitude Lattices",
// Mathematical Geosciences, 2010: y = 1 - (2i + 1)/n, azimuth i times the golden angle). n = 0
// gives none; n < 0 throws oer::Error.
std::vector<glm::dvec3> fibonacci_sphere(int n);

class ReferenceIrradiance {
  public:
    // max_samples bounds the work: a larger map is first reduced, area-preservingly, to at
    // most that many samples (blocks of pixels, each carrying sum(L dOmega) of its pixels at
    // their dOmega-weighted mean direction, normalised; square blocks of the smallest size that
    // fits, cut short at the right and bottom edges). 0 means never reduce; unreduced samples
    // sit at the pixel centres. Throws oer::Error (InvalidInput) on an empty or inconsistent
    // image.
    explicit ReferenceIrradiance(const HdrImage& image, std::size_t max_samples = 0);

    glm::dvec3 at(const glm::dvec3& normal) const;
    std::vector<glm::dvec3> at(std::span<const glm::dvec3> normals) const;  // uses 2 threads
    std::size_t sample_count() const { return directions_.size(); }

  private:
    std::vector<glm::dvec3> directions_;
    std::vector<glm::dvec3> weighted_radiance_;  // sum of L * dOmega
};

// Relative RMS error of approx against reference over all normals and channels:
// sqrt(sum |approx - ref|^2) / sqrt(sum |ref|^2). Sizes must match and be non-zero (else
// oer::Error InvalidInput); an all-zero reference gives 0 if approx equals it, else infinity.
double relative_rms_error(std::span<const glm::dvec3> approx,
                          std::span<const glm::dvec3> reference);

}  // namespace oer
