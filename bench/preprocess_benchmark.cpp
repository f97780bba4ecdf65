// Preprocessing benchmark (docs/design.md section 8): oer::build_rig against a literal
// implementation of the thesis's algorithm (bench/support/literal_thesis.hpp), measured in
// the same run on the same maps, and the throughput of oer::project_environment.
// Beside each Blender world's rig, the prefiltering of its residual and of each light into the
// specular cubes (oer::prefilter_specular at the default options) and the cubes' bytes.
// Prints plain text; a missed target is reported, never an error (benchmarks report, tests
// check). `--quick` runs the 2048x1024, 4-light case and the projection throughput only;
// `--world NAME` the real-maps table for that Blender world alone (e.g. `--world studio`).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <sched.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "bench_support.hpp"
#include "literal_thesis.hpp"
#include "oer/core/error.hpp"
#include "oer/core/image.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "sweep_support.hpp"
#include "targets.hpp"

namespace {

using oer::bench::best_ms;
using oer::bench::Clock;
using oer::bench::kDiscs;
using oer::bench::kMaxDiscs;
using oer::bench::make_synthetic_map;
using oer::bench::ms_since;
using std::numbers::pi;

namespace targets = oer::bench::targets;

constexpr int kOursRepetitions = 5;
constexpr int kLiteralMaxRepetitions = 3;
constexpr double kLiteralBudgetMs = 4000.0;  // no further repetition once this much is spent
constexpr int kProjectionRepetitions = 20;
constexpr int kSpecularRepetitions = 3;
constexpr double kSpecularTargetMs = 400.0;  // a 2048x1024 map, at most

// How many of the first `discs` discs have a light direction inside them.
int discs_hit(const std::vector<glm::dvec3>& directions, int discs) {
    int hit = 0;
    for (int k = 0; k < discs; ++k) {
        const glm::dvec3 centre = disc_centre(kDiscs[k]);
        const double cos_radius = std::cos(kDiscs[k].radius_degrees * pi / 180.0);
        for (const glm::dvec3& d : directions) {
            if (glm::dot(glm::normalize(d), centre) >= cos_radius) {
                ++hit;
                break;
            }
        }
    }
    return hit;
}

std::vector<glm::dvec3> directions_of(const oer::Rig& rig) {
    std::vector<glm::dvec3> directions;
    for (const oer::Light& light : rig.lights) {
        directions.push_back(light.direction);
    }
    return directions;
}

std::vector<glm::dvec3> directions_of(const oer::bench::LiteralResult& literal) {
    std::vector<glm::dvec3> directions;
    for (const oer::bench::LiteralLight& light : literal.lights) {
        directions.push_back(light.direction);
    }
    return directions;
}

oer::RigOptions fixed_options(int lights) {
    oer::RigOptions options;
    options.light_count = lights;
    options.sh_order = targets::kPreprocessOrder;
    options.window = oer::WindowChoice::None;
    return options;
}

// max |ours - literal| over the 9 coefficients and 3 channels, relative to the largest
// literal coefficient magnitude (per-coefficient ratios are meaningless for coefficients
// near zero).
double max_relative_difference(const oer::ShRgb& ours, const oer::bench::LiteralSh3& literal) {
    if (ours.coefficients.size() < literal.size()) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    double largest = 0.0, difference = 0.0;
    for (std::size_t i = 0; i < literal.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            largest = std::max(largest, std::abs(literal[i][c]));
            difference = std::max(difference, std::abs(ours.coefficients[i][c] - literal[i][c]));
        }
    }
    return largest > 0.0 ? difference / largest : difference;
}

const char* verdict(bool met) {
    return met ? "met" : "NOT met";
}

// Runs f with the calling thread, and every thread it starts, pinned to one CPU (the first the
// process may use), then restores the affinity. The lighting code picks its thread count from
// the map size alone (sh_projection.hpp: 2 threads from 64 Ki pixels), so this is how "ours"
// runs on one core: its two projection threads share it. Throws if the affinity cannot be set.
template <class F>
void on_one_core(F&& f) {
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) {
        throw std::runtime_error("sched_getaffinity failed");
    }
    int first = 0;
    while (first < CPU_SETSIZE && !CPU_ISSET(first, &allowed)) {
        ++first;
    }
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0) {
        throw std::runtime_error("sched_setaffinity to one CPU failed");
    }
    try {
        f();
    } catch (...) {
        sched_setaffinity(0, sizeof allowed, &allowed);
        throw;
    }
    sched_setaffinity(0, sizeof allowed, &allowed);
}

struct CaseResult {
    double ours_ms = 0.0;
    double ours_one_core_ms = 0.0;
    double literal_ms = 0.0;
    std::map<std::string, double> ours_phases_ms;  // of the last run of ours
};

// "4lt o3": what the defaults chose. (snprintf rather than "literal" + std::string, on which
// GCC 12 warns falsely, -Wrestrict.)
std::string auto_pick(const oer::Rig& rig) {
    char text[32];
    std::snprintf(text, sizeof text, "%zult o%d", rig.lights.size(), rig.order);
    return text;
}

std::string size_text(const oer::HdrImage& image) {
    char text[32];
    std::snprintf(text, sizeof text, "%dx%d", image.width, image.height);
    return text;
}

std::string literal_split(const oer::bench::LiteralResult& literal) {
    char text[48];
    std::snprintf(text, sizeof text, "%.0f + %.0f", literal.locate_ms, literal.oems_ms);
    return text;
}

void print_table_header() {
    std::printf("%-10s %6s %7s %9s %9s %9s %-7s %10s %-15s %9s %9s %12s\n", "map", "lights",
                "hit o/l", "ours ms", "1-core ms", "auto ms", "auto", "literal ms",
                "(locate + OEMs)", "lit/ours", "lit/1core", "max rel diff");
}

CaseResult run_synthetic_case(int width, int height, int lights) {
    const oer::HdrImage image = make_synthetic_map(width, height, lights);
    const oer::RepairCounts repaired;
    const double unlimited = std::numeric_limits<double>::infinity();

    oer::Rig ours;
    const oer::RigOptions options = fixed_options(lights);
    const double ours_ms = best_ms(kOursRepetitions, unlimited,
                                   [&] { ours = oer::build_rig(image, repaired, options); });
    double ours_one_core_ms = 0.0;
    on_one_core([&] {
        ours_one_core_ms = best_ms(kOursRepetitions, unlimited,
                                   [&] { ours = oer::build_rig(image, repaired, options); });
    });
    oer::Rig ours_auto;
    const double auto_ms = best_ms(kOursRepetitions, unlimited, [&] {
        ours_auto = oer::build_rig(image, repaired, oer::RigOptions{});
    });

    oer::bench::LiteralOptions literal_options;
    literal_options.light_count = lights;
    oer::bench::LiteralResult literal, best_literal;
    const double literal_ms = best_ms(kLiteralMaxRepetitions, kLiteralBudgetMs, [&] {
        literal = oer::bench::literal_thesis_preprocess(image, literal_options);
        if (best_literal.oems.empty() ||
            literal.locate_ms + literal.oems_ms < best_literal.locate_ms + best_literal.oems_ms) {
            best_literal = literal;
        }
    });

    char hit[16];
    std::snprintf(hit, sizeof hit, "%d/%d", discs_hit(directions_of(ours), lights),
                  discs_hit(directions_of(best_literal), lights));
    std::printf("%-10s %6d %7s %9.1f %9.1f %9.1f %-7s %10.1f %-15s %8.1fx %8.1fx %12.2e\n",
                size_text(image).c_str(), lights, hit, ours_ms, ours_one_core_ms, auto_ms,
                auto_pick(ours_auto).c_str(), literal_ms, literal_split(best_literal).c_str(),
                literal_ms / ours_ms, literal_ms / ours_one_core_ms,
                max_relative_difference(ours.sh.all, best_literal.oems.back()));
    std::fflush(stdout);
    return {ours_ms, ours_one_core_ms, literal_ms, ours.timings_ms};
}

// Projection throughput on 2048x1024 with the pixels of 4 light masks, in map Gpixel/s;
// returns the order-3 figure.
double projection_throughput() {
    const int width = targets::kPreprocessWidth, height = targets::kPreprocessHeight,
              lights = targets::kPreprocessLights;
    const oer::HdrImage image = make_synthetic_map(width, height, lights);
    const oer::Rig rig = oer::build_rig(image, oer::RepairCounts{}, fixed_options(lights));
    std::vector<std::vector<std::uint32_t>> masks;
    std::size_t mask_pixels = 0;
    for (const oer::Light& light : rig.lights) {
        masks.push_back(light.pixels);
        mask_pixels += light.pixels.size();
    }
    std::printf(
        "\noer::project_environment, %dx%d map plus %zu light masks (%zu mask pixels), best of "
        "%d;\nGpixel/s counts the map's pixels only:\n",
        width, height, masks.size(), mask_pixels, kProjectionRepetitions);
    std::printf("%6s %10s %10s\n", "order", "ms", "Gpixel/s");
    double order3_gpixels = 0.0;
    for (const int order : {3, 5, 9}) {
        oer::ShProjection projection;
        const double ms =
            best_ms(kProjectionRepetitions, std::numeric_limits<double>::infinity(),
                    [&] { projection = oer::project_environment(image, masks, order); });
        const double gpixels = double(image.pixel_count()) / (ms * 1e6);
        std::printf("%6d %10.2f %10.3f", order, ms, gpixels);
        if (order == targets::kPreprocessOrder) {
            order3_gpixels = gpixels;
            std::printf("   target >= %.1f Gpixel/s: %s", targets::kProjectionGpixelsPerSecond,
                        verdict(gpixels >= targets::kProjectionGpixelsPerSecond));
        }
        std::printf("\n");
        std::fflush(stdout);
    }
    return order3_gpixels;
}

// Only the world named `only` when it is not empty.
void real_maps(const std::string& only) {
    std::vector<std::filesystem::path> paths;
    try {
        paths = oer::bench::blender_worlds();
    } catch (const oer::Error& error) {
        std::printf("\nReal maps: %s; skipped.\n", error.what());
        return;
    }
    if (!only.empty()) {
        std::erase_if(paths, [&](const auto& path) { return path.stem().string() != only; });
        if (paths.empty()) {
            std::printf("\nReal maps: no world named '%s' in %s.\n", only.c_str(),
                        oer::bench::kBlenderWorldDirectory);
            return;
        }
    }
    std::printf(
        "\nReal maps (%s):\nours with the defaults (auto light count and SH order), "
        "literal at the number of lights ours found (at least 1);\nspec ms: "
        "oer::prefilter_specular of ours at the default options (best of %d), cube MB the "
        "residual's and the lights' bytes:\n",
        oer::bench::kBlenderWorldDirectory, kSpecularRepetitions);
    std::printf("%-10s %-9s %9s %-7s %10s %-15s %9s %12s %8s %8s\n", "map", "size", "auto ms",
                "auto", "literal ms", "(locate + OEMs)", "lit/ours", "max rel diff", "spec ms",
                "cube MB");
    for (const auto& path : paths) {
        const std::string name = path.stem().string();
        try {
            const oer::LoadedImage loaded = oer::load_image_file(path.string());
            oer::Rig ours;
            const double ours_ms = best_ms(
                kOursRepetitions, std::numeric_limits<double>::infinity(),
                [&] { ours = oer::build_rig(loaded.image, loaded.repaired, oer::RigOptions{}); });
            oer::bench::LiteralOptions literal_options;
            literal_options.light_count = std::max(1, int(ours.lights.size()));
            oer::bench::LiteralResult literal, best_literal;
            const double literal_ms = best_ms(kLiteralMaxRepetitions, kLiteralBudgetMs, [&] {
                literal = oer::bench::literal_thesis_preprocess(loaded.image, literal_options);
                if (best_literal.oems.empty() ||
                    literal.locate_ms + literal.oems_ms <
                        best_literal.locate_ms + best_literal.oems_ms) {
                    best_literal = literal;
                }
            });
            // The first 9 coefficients of any order >= 3 are the order-3 projection.
            char difference[32] = "- (order < 3)";
            if (ours.order >= 3) {
                std::snprintf(difference, sizeof difference, "%.2e",
                              max_relative_difference(ours.sh.all, best_literal.oems.back()));
            }
            oer::SpecularEnvironment cube;
            const double specular_ms =
                best_ms(kSpecularRepetitions, std::numeric_limits<double>::infinity(),
                        [&] { cube = oer::prefilter_specular(loaded.image, ours); });
            std::printf("%-10s %-9s %9.1f %-7s %10.1f %-15s %8.1fx %12s %8.1f %8.2f\n",
                        name.c_str(), size_text(loaded.image).c_str(), ours_ms,
                        auto_pick(ours).c_str(), literal_ms, literal_split(best_literal).c_str(),
                        literal_ms / ours_ms, difference, specular_ms,
                        double(cube.byte_size()) / (1 << 20));
        } catch (const std::exception& e) {
            std::printf("%-10s failed: %s\n", name.c_str(), e.what());
        }
        std::fflush(stdout);
    }
}

}  // namespace

// The prefiltering at the default options on the 2048x1024 synthetic map of the preprocessing
// target with its rig, best of kSpecularRepetitions: the residual's cube and the lights'.
struct SpecularTimes {
    double residual_ms = 0.0;
    double lights_ms = 0.0;
};

SpecularTimes specular_prefilter_ms() {
    const oer::HdrImage image = make_synthetic_map(
        targets::kPreprocessWidth, targets::kPreprocessHeight, targets::kPreprocessLights);
    const oer::Rig rig =
        oer::build_rig(image, oer::RepairCounts{}, fixed_options(targets::kPreprocessLights));
    return {best_ms(kSpecularRepetitions, std::numeric_limits<double>::infinity(),
                    [&] { oer::prefilter_residual(image, rig); }),
            best_ms(kSpecularRepetitions, std::numeric_limits<double>::infinity(),
                    [&] { oer::prefilter_lights(image, rig); })};
}

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
    if (argc > 2 && std::string(argv[1]) == "--world") {
        real_maps(argv[2]);
        return 0;
    }
    const auto start = Clock::now();
    std::printf("oer preprocessing benchmark (%u hardware threads)%s\n\n",
                std::thread::hardware_concurrency(), quick ? ", --quick" : "");
    std::printf(
        "Synthetic maps: a dim sky gradient plus k bright discs of distinct sizes and colors.\n"
        "ours ms     oer::build_rig, light_count = k, sh_order = 3, no window; best of %d\n"
        "1-core ms   the same, the process pinned to one CPU (the literal runs on one thread)\n"
        "auto ms     oer::build_rig with the defaults (auto light count, auto SH order); best "
        "of %d;\n"
        "            'auto' = lights and order it chose\n"
        "literal ms  the thesis's algorithm as written (bench/support/literal_thesis.hpp,\n"
        "            2^k occluded maps); best of up to %d, split into light finding + OEMs\n"
        "hit o/l     discs with a light inside them, ours / literal\n"
        "max rel diff  all-on order-3 SH, ours vs literal: max |difference| / largest "
        "coefficient\n\n",
        kOursRepetitions, kOursRepetitions, kLiteralMaxRepetitions);

    print_table_header();
    CaseResult target_case;
    if (quick) {
        target_case = run_synthetic_case(targets::kPreprocessWidth, targets::kPreprocessHeight,
                                         targets::kPreprocessLights);
    } else {
        run_synthetic_case(1024, 512, 4);
        for (int lights = 1; lights <= kMaxDiscs; ++lights) {
            CaseResult result =
                run_synthetic_case(targets::kPreprocessWidth, targets::kPreprocessHeight, lights);
            if (lights == targets::kPreprocessLights) {
                target_case = std::move(result);
            }
        }
        run_synthetic_case(4096, 2048, 4);
    }
    std::printf("\nours, 2048x1024, 4 lights, order 3, phases of the last run (ms):");
    for (const auto& [phase, ms] : target_case.ours_phases_ms) {
        std::printf(" %s %.1f", phase.c_str(), ms);
    }
    std::printf("\n");

    const double projection_gpixels = projection_throughput();
    const SpecularTimes specular = specular_prefilter_ms();
    const double specular_ms = specular.residual_ms + specular.lights_ms;
    if (!quick) {
        real_maps("");
    }

    const double speedup = target_case.literal_ms / target_case.ours_ms;
    const double speedup_one_core = target_case.literal_ms / target_case.ours_one_core_ms;
    std::printf("\ndocs/design.md section 8 targets (%dx%d, %d lights, order %d):\n",
                targets::kPreprocessWidth, targets::kPreprocessHeight, targets::kPreprocessLights,
                targets::kPreprocessOrder);
    std::printf("  preprocess time    %9.1f ms        target <= %.0f ms          %s\n",
                target_case.ours_ms, targets::kPreprocessMs,
                verdict(target_case.ours_ms <= targets::kPreprocessMs));
    std::printf("  vs literal thesis  %9.1fx          target >= %.0fx             %s\n", speedup,
                targets::kSpeedupOverLiteral, verdict(speedup >= targets::kSpeedupOverLiteral));
    std::printf("    (ours on one core: %.1f ms, %.1fx; the literal runs on one thread)\n",
                target_case.ours_one_core_ms, speedup_one_core);
    std::printf("  SH projection      %9.3f Gpixel/s  target >= %.1f Gpixel/s    %s\n",
                projection_gpixels, targets::kProjectionGpixelsPerSecond,
                verdict(projection_gpixels >= targets::kProjectionGpixelsPerSecond));
    std::printf("  specular prefilter %9.1f ms        target <= %.0f ms         %s\n", specular_ms,
                kSpecularTargetMs, verdict(specular_ms <= kSpecularTargetMs));
    std::printf("    (the residual's cube %.1f ms, the %d lights' %.1f ms)\n", specular.residual_ms,
                targets::kPreprocessLights, specular.lights_ms);
    std::printf("\nbenchmark took %.1f s\n", ms_since(start) / 1e3);
    return 0;
}
