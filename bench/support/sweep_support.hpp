#pragma once
// Shared by the accuracy sweeps (lighting_sweep, light_location_sweep): the brute-force
// irradiance of a set of pixels, area-preserving map downsampling, the irradiance error
// figures, median timing, the Pareto front of time against error, and CSV fields.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "bench_support.hpp"
#include "oer/core/image.hpp"

namespace oer::bench {

// Median wall time, in ms, of `repetitions` (at least 1) runs of f (the nearest-rank median
// of bench_support.hpp's percentile).
template <class F>
double median_ms(int repetitions, F&& f) {
    std::vector<double> times;
    for (int r = 0; r < std::max(1, repetitions); ++r) {
        const auto start = Clock::now();
        f();
        times.push_back(ms_since(start));
    }
    return percentile(std::move(times), 0.5);
}

// E(n) = sum over the listed pixels of L(pixel) max(0, n . dir) dOmega, in double, at each
// normal: the brute-force irradiance of reference_irradiance.hpp restricted to some pixels
// (a light's own pixels), so that by linearity the truth of the map with lights switched off
// is truth(all) - sum over the lights off of truth(light). Throws oer::Error (InvalidInput) on
// a pixel index outside the map.
std::vector<glm::dvec3> pixels_irradiance(const HdrImage& image,
                                          std::span<const std::uint32_t> pixels,
                                          std::span<const glm::dvec3> normals);

// The map reduced by `factor` in each direction (factor divides width and height, else
// oer::Error InvalidInput): each output pixel is the solid-angle-weighted mean radiance of its
// factor x factor block, sum(L dOmega) / sum(dOmega). The block's source solid angles add up to
// the output pixel's exact solid angle (the row terms of docs/design.md section 3 telescope), so
// sum(L dOmega) over the map, and over every block, is kept.
HdrImage downsample_equirect(const HdrImage& image, int factor);

// The light masks of `image` carried to its downsampled map: an output pixel belongs to the
// light whose pixels carry the most luminance energy (luminance * dOmega) in its block, if any
// light pixel is in the block. A light smaller than a block (a sun) keeps its block, so
// switching it off still removes its energy; the sky in its blocks goes with it. The lists are
// disjoint and sorted.
std::vector<std::vector<std::uint32_t>> downsample_light_pixels(
    const HdrImage& image, std::span<const std::vector<std::uint32_t>> light_pixels, int factor);

// A map of constant sky radiance with hard-edged discs painted over it (a pixel takes a disc's
// radiance when its centre lies within the disc; a later disc paints over an earlier one), and
// each disc's pixels as painted: the known lights of the light-location sweep.
struct DiscMap {
    HdrImage image;
    std::vector<std::vector<std::uint32_t>> disc_pixels;  // per disc, sorted
};
DiscMap make_disc_map(int width, int height, glm::vec3 sky, std::span<const Disc> discs);

// Irradiance of an approximation against the truth at the same normals.
struct IrradianceError {
    // sqrt(sum |approx - truth|^2) / sqrt(sum |truth|^2) over normals and RGB
    // (relative_rms_error of reference_irradiance.hpp).
    double relative_rms = 0.0;
    // max over normals of |approx - truth| / |truth| (RGB vector norms); a normal whose truth
    // is black counts only if the approximation is not (then infinity).
    double max_relative = 0.0;
    // The ringing: per RGB channel the smallest approximate irradiance divided by the largest
    // true irradiance of that channel, the minimum over the channels whose largest truth is
    // positive, at most 0 (the measure of min_relative_irradiance in irradiance.hpp).
    double most_negative = 0.0;
};
// Sizes must match and be non-zero (else oer::Error InvalidInput).
IrradianceError irradiance_error(std::span<const glm::dvec3> approx,
                                 std::span<const glm::dvec3> truth);

// Indices of the points not dominated in (time, error), both smaller-is-better: no other point
// is at most as slow and at most as wrong and better in one. Sorted by time, then error; of
// equal points the first is kept. Sizes must match (else oer::Error InvalidInput).
std::vector<std::size_t> pareto_front(std::span<const double> time, std::span<const double> error);

// Blender's studio-light worlds (Debian's blender-data, docs/design.md section 5), the real maps of
// the sweeps: the .exr files of kBlenderWorldDirectory, sorted by name. Throws oer::Error (Io)
// saying to install blender-data when there are none.
inline constexpr const char* kBlenderWorldDirectory =
    "/usr/share/blender/datafiles/studiolights/world";
std::vector<std::filesystem::path> blender_worlds();

// The command line both sweeps take: [--quick] [--json FILE] [--csv FILE]. Throws oer::Error
// (InvalidInput) naming an unknown flag or a missing file name.
struct SweepArguments {
    bool quick = false;
    std::string json_path;  // empty: no JSON
    std::string csv_path;   // empty: no CSV
};
SweepArguments parse_sweep_arguments(int argc, const char* const* argv);

// Writes text to path; throws oer::Error (Io) naming the path when it cannot.
void write_text_file(const std::string& path, const std::string& text);

// A CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, quote or newline.
std::string csv_field(const std::string& text);

// "a,b,c" as {"a", "b", "c"}: a sweep's --worlds and --meshes.
std::vector<std::string> split_names(const std::string& text);

// The value after the flag argv[i] (i moves past it); throws oer::Error (InvalidInput) when the
// flag is the last argument.
std::string flag_value(int argc, const char* const* argv, int& i);

// A reference's samples per pixel from a flag's text: an even number of at least 2 (the
// reference estimates its noise from two halves); throws oer::Error (InvalidInput) naming the
// flag otherwise.
int reference_samples(const std::string& flag, const std::string& text);

}  // namespace oer::bench
