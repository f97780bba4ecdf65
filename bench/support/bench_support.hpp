#pragma once
// Shared by the benchmarks: timing by best of several runs, percentiles, the server's
// Server-Timing header read back, and synthetic environment maps with known bright discs.
#include <chrono>
#include <cstddef>
#include <ctime>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/core/image.hpp"

namespace oer::bench {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// CPU time of the whole process (every thread: llvmpipe's rasteriser threads included), in ms.
// On a shared machine other processes inflate wall times but not this.
inline double process_cpu_ms() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}

// Best (minimum) wall time of up to max_repetitions runs of f, at least one, stopping early
// once budget_ms has been spent.
template <class F>
double best_ms(int max_repetitions, double budget_ms, F&& f) {
    double best = std::numeric_limits<double>::infinity();
    double spent = 0.0;
    for (int r = 0; r < max_repetitions; ++r) {
        const auto start = Clock::now();
        f();
        const double elapsed = ms_since(start);
        best = std::min(best, elapsed);
        spent += elapsed;
        if (spent + best > budget_ms) {
            break;
        }
    }
    return best;
}

// The p-quantile (p in [0, 1]) of `values`, the nearest-rank sample of the sorted values; 0 when
// there are none.
double percentile(std::vector<double> values, double p);

// A file's whole content. Throws oer::Error (Io) naming the path when it cannot be read.
std::string read_file(const std::string& path);

// The entries of a W3C Server-Timing header as oer-server writes them, "name;dur=1.25, ...",
// as (name, milliseconds) in order. Throws oer::Error (InvalidInput) quoting the header when an
// entry has no name or no readable dur.
std::vector<std::pair<std::string, double>> parse_server_timing(std::string_view header);

// The bright discs of the synthetic maps: distinct sizes, colors and radiances, of comparable
// power, away from the seam and the poles (the literal thesis clusters in pixel space).
struct Disc {
    double azimuth_degrees;    // phi of docs/design.md section 3
    double elevation_degrees;  // 90 - theta
    double radius_degrees;
    glm::vec3 radiance;
};
inline constexpr Disc kDiscs[] = {
    {-120.0, 35.0, 4.0, {60.0f, 57.0f, 51.0f}},   {-50.0, 55.0, 3.2, {76.5f, 81.0f, 90.0f}},
    {20.0, 25.0, 2.6, {130.0f, 91.0f, 58.5f}},    {80.0, 45.0, 2.1, {108.0f, 144.0f, 180.0f}},
    {140.0, 15.0, 1.7, {250.0f, 212.5f, 150.0f}}, {-10.0, 70.0, 1.4, {315.0f, 350.0f, 280.0f}},
};
inline constexpr int kMaxDiscs = int(std::size(kDiscs));

glm::dvec3 disc_centre(const Disc& disc);

// A dim sky gradient (horizon to zenith, brighter towards +X) over a darker ground, plus the
// first `lights` discs.
HdrImage make_synthetic_map(int width, int height, int lights);

}  // namespace oer::bench
