#pragma once
// The environment as the reference renderer sees it: the request's map with each light's
// pixels scaled by its weight, piecewise constant over its pixels, turned by the yaw, and a
// distribution for importance sampling it.
//
// The distribution has the shape of pbrt-v4's ImageInfiniteLight (M. Pharr, W. Jakob and
// G. Humphreys, "Physically Based Rendering", 4th ed., sections 12.5.2 and A.5.6): a
// piecewise-constant 2D distribution over the equirectangular image, a marginal over rows and
// a conditional over the columns of each row. pbrt weights a pixel by its value and converts
// with the Jacobian 1 / (2 pi^2 sin theta) at the sampled point; here each pixel is weighted
// by its luminance times its exact solid angle dOmega(y) (docs/design.md section 3) and sampled
// uniformly in solid angle within the pixel (uniform in phi and in cos theta), so that the
// density in solid angle is exactly luminance / sum(luminance dOmega), constant over a pixel.
#include <cstddef>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "oer/core/image.hpp"
#include "oer/lighting/rig.hpp"

namespace oer::reference {

struct EnvironmentSample {
    glm::dvec3 direction;  // world space, unit
    glm::dvec3 radiance;
    double pdf = 0.0;  // per steradian
};

class EnvironmentSampler {
  public:
    // `weights`: one per rig light (empty: all 1). Throws oer::Error (InvalidInput) when the
    // map does not have the rig's size or a weight is negative.
    EnvironmentSampler(const HdrImage& map, const Rig& rig, const std::vector<float>& weights,
                       double yaw_degrees);

    // Whether the map carries any light to sample (an all-black map does not).
    bool can_sample() const { return total_weight_ > 0.0; }
    // Three uniform numbers in [0, 1): u_row picks the row, u_column the column within it (and
    // by its remainder in that column's bin, phi), u_within cos theta within the row.
    // Requires can_sample().
    EnvironmentSample sample(double u_row, double u_column, double u_within) const;

    glm::dvec3 radiance(const glm::dvec3& world_direction) const;
    double pdf(const glm::dvec3& world_direction) const;  // 0 when !can_sample()

  private:
    std::size_t pixel_of(const glm::dvec3& world_direction) const;

    int width_ = 0;
    int height_ = 0;
    double yaw_degrees_ = 0.0;
    std::vector<glm::dvec3> radiance_;  // the weighted map
    std::vector<double> luminance_;
    std::vector<double> row_cdf_;     // height + 1 entries, from 0 to 1
    std::vector<double> column_cdf_;  // (width + 1) per row, from 0 to 1 (rows of weight 0: 0s)
    std::vector<double> row_cos_;     // cos(pi y / H), height + 1 entries
    double total_weight_ = 0.0;       // sum of luminance dOmega
};

}  // namespace oer::reference
