#pragma once
// Internal to the SH projection (sh_projection.cpp), its only user; the basis itself is
// oer/lighting/sh.hpp. The inner loop of the separable SH projection: per image row, the azimuthal
// Fourier sums
//   sum over x of L(x, y) cos(m phi_x)   and   sum over x of L(x, y) sin(m phi_x)
// for m = 0 .. order - 1 and each RGB channel, in double, from a per-column table.
#include <cstddef>
#include <vector>

namespace oer::detail {

// Term k of column x: 1 for k = 0, cos(m phi_x) for k = 2m - 1, sin(m phi_x) for k = 2m
// (m = 1 .. order - 1), phi_x the equirect azimuth of docs/design.md section 3. Rows of the table
// are padded with zeros to a multiple of 4 columns.
class AzimuthTable {
  public:
    AzimuthTable(int width, int order);

    int width() const { return width_; }
    int terms() const { return terms_; }
    std::size_t stride() const { return stride_; }
    double at(int k, int x) const { return values_[std::size_t(k) * stride_ + std::size_t(x)]; }
    const double* data() const { return values_.data(); }

  private:
    int width_;
    int terms_;
    std::size_t stride_;
    std::vector<double> values_;  // terms x stride
};

// sums[3 k + c] = sum over the row of channel c times term k. row_rgb holds width interleaved
// RGB floats; scratch holds at least 3 * table.stride() doubles (overwritten).
void row_harmonic_sums(const AzimuthTable& table, const float* row_rgb, double* scratch,
                       double* sums);

}  // namespace oer::detail
