#include "sh_row_harmonics.hpp"

#include <cmath>
#include <cstring>
#include <numbers>

#include "oer/lighting/sh.hpp"

namespace oer::detail {

AzimuthTable::AzimuthTable(int width, int order)
    : width_(width),
      terms_(2 * order - 1),
      stride_((std::size_t(width) + 3) / 4 * 4),
      values_(std::size_t(terms_) * stride_, 0.0) {
    for (int x = 0; x < width; ++x) {
        const double phi = 2.0 * std::numbers::pi * (x + 0.5) / width - std::numbers::pi;
        values_[x] = 1.0;
        for (int m = 1; m < order; ++m) {
            values_[std::size_t(2 * m - 1) * stride_ + x] = std::cos(m * phi);
            values_[std::size_t(2 * m) * stride_ + x] = std::sin(m * phi);
        }
    }
}

namespace {

// Four columns at a time, each lane its own partial sum (a fixed summation order, so the
// result does not depend on the instruction set the compiler picked).
typedef double v4d __attribute__((vector_size(32)));

// (By reference: returning a 32-byte vector warns about the ABI in the baseline clone.)
[[gnu::always_inline]] inline void load4(v4d& v, const double* p) {
    std::memcpy(&v, p, sizeof v);
}

template <int K>
[[gnu::always_inline]] inline void accumulate(const double* table, std::size_t stride,
                                              const double* r, const double* g, const double* b,
                                              double* sums) {
    v4d acc[K][3] = {};
    for (std::size_t x = 0; x < stride; x += 4) {
        v4d vr, vg, vb;
        load4(vr, r + x);
        load4(vg, g + x);
        load4(vb, b + x);
        acc[0][0] += vr;
        acc[0][1] += vg;
        acc[0][2] += vb;
        for (int k = 1; k < K; ++k) {
            v4d t;
            load4(t, table + std::size_t(k) * stride + x);
            acc[k][0] += t * vr;
            acc[k][1] += t * vg;
            acc[k][2] += t * vb;
        }
    }
    for (int k = 0; k < K; ++k) {
        for (int c = 0; c < 3; ++c) {
            sums[3 * k + c] = (acc[k][c][0] + acc[k][c][1]) + (acc[k][c][2] + acc[k][c][3]);
        }
    }
}

#define OER_ROW_CASE(order)                                      \
    case 2 * order - 1:                                          \
        accumulate<2 * order - 1>(table, stride, r, g, b, sums); \
        break;

__attribute__((target_clones("arch=x86-64-v4", "avx2", "default"))) void row_sums_dispatch(
    int terms, const double* table, std::size_t stride, int width, const float* row,
    double* scratch, double* sums) {
    double* r = scratch;
    double* g = scratch + stride;
    double* b = scratch + 2 * stride;
    for (int x = 0; x < width; ++x) {
        r[x] = row[3 * x];
        g[x] = row[3 * x + 1];
        b[x] = row[3 * x + 2];
    }
    for (std::size_t x = std::size_t(width); x < stride; ++x) {
        r[x] = g[x] = b[x] = 0.0;
    }
    switch (terms) {
        OER_ROW_CASE(1)
        OER_ROW_CASE(2)
        OER_ROW_CASE(3)
        OER_ROW_CASE(4)
        OER_ROW_CASE(5)
        OER_ROW_CASE(6)
        OER_ROW_CASE(7)
        OER_ROW_CASE(8)
        OER_ROW_CASE(9)
        OER_ROW_CASE(10)
        OER_ROW_CASE(11)
        OER_ROW_CASE(12)
        OER_ROW_CASE(13)
        OER_ROW_CASE(14)
        OER_ROW_CASE(15)
        OER_ROW_CASE(16)
        default:
            break;
    }
}
#undef OER_ROW_CASE

static_assert(kMaxShOrder == 16, "row_sums_dispatch has one case per order");

}  // namespace

void row_harmonic_sums(const AzimuthTable& table, const float* row_rgb, double* scratch,
                       double* sums) {
    row_sums_dispatch(table.terms(), table.data(), table.stride(), table.width(), row_rgb, scratch,
                      sums);
}

}  // namespace oer::detail
