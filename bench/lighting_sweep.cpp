// The lighting sweep (sweep 1 of the accuracy report, docs/accuracy.md): SH projection time against
// irradiance error over the sphere, for SH order x window x map downsampling, on every Blender
// world, for the whole map and for every on/off subset of its lights (the lights build_rig finds
// with the default options). The truth is the brute-force irradiance of the full-resolution map in
// double over all its pixels (reference_irradiance.hpp, no reduction) at a Fibonacci lattice of
// normals; a subset's truth is that of the map with the switched-off lights' pixels removed, which
// by linearity is truth(all) - sum over the lights off of truth(light's pixels), computed once per
// map. Prints per world the Pareto front of time against error and where the automatic order
// and window land; --json / --csv write one row per configuration. A benchmark: it reports,
// the ctest (tests/bench/lighting_sweep_test.cpp) checks.
#include <algorithm>
#include <array>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_support.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/reference_irradiance.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "sweep_support.hpp"

namespace {

using oer::bench::Clock;
using oer::bench::ms_since;

// Normals the error is measured on: enough that a light's ringing lobe (a few tens of degrees
// wide at order <= 9) is sampled, few enough that the brute-force truth over every pixel stays
// well under a second a map.
constexpr int kNormals = 512;
constexpr int kMaxOrder = 9;
constexpr int kFullRepetitions = 9;
constexpr int kQuickRepetitions = 3;

enum class WindowMode { None, Hanning, Lanczos, Auto };

// The cutoffs tried for Hanning and Lanczos, as multiples of the order (the cutoff rule is
// what build_rig's default must choose: a larger multiple is a weaker window). 1x zeroes
// nothing but weighs the top band least; 8x is close to no window at orders <= 9.
constexpr double kCutoffFactors[] = {1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0};

// One window setting of the sweep: a mode and, for Hanning and Lanczos, its cutoff over the
// order (0 for none and auto).
struct WindowSetting {
    WindowMode mode = WindowMode::None;
    double cutoff_factor = 0.0;
};

std::vector<WindowSetting> window_settings() {
    std::vector<WindowSetting> settings{{WindowMode::None, 0.0}};
    for (const WindowMode mode : {WindowMode::Hanning, WindowMode::Lanczos}) {
        for (const double factor : kCutoffFactors) {
            settings.push_back({mode, factor});
        }
    }
    settings.push_back({WindowMode::Auto, 0.0});
    return settings;
}

const char* name_of(WindowMode mode) {
    switch (mode) {
        case WindowMode::None:
            return "none";
        case WindowMode::Hanning:
            return "hanning";
        case WindowMode::Lanczos:
            return "lanczos";
        case WindowMode::Auto:
            return "auto";
    }
    return "?";
}

// The window a setting means at an order: Hanning and Lanczos at cutoff factor x order; auto is
// choose_deringing_window's weakest Hanning window keeping every on/off subset non-negative,
// as build_rig applies it (rig.cpp).
oer::ShWindow window_for(const WindowSetting& setting, const oer::ShProjection& projection) {
    const double cutoff = setting.cutoff_factor * projection.all.order;
    switch (setting.mode) {
        case WindowMode::None:
            return {};
        case WindowMode::Hanning:
            return {oer::WindowKind::Hanning, cutoff};
        case WindowMode::Lanczos:
            return {oer::WindowKind::Lanczos, cutoff};
        case WindowMode::Auto:
            return oer::choose_deringing_window(projection, oer::WindowKind::Hanning);
    }
    return {};
}

// The on/off state of every light of a rig (build_rig finds at most 16).
struct Subset {
    std::array<bool, 16> flags{};
    std::size_t count = 0;
    std::span<const bool> on() const { return {flags.data(), count}; }
    std::vector<bool> as_vector() const {
        return std::vector<bool>(flags.begin(), flags.begin() + long(count));
    }
};

// One configuration's figures for one subset.
struct Row {
    std::string world;
    std::vector<bool> on;  // per light of the rig, true = on
    int order = 0;
    WindowSetting window;
    double window_cutoff = 0.0;  // of the window applied (0 for none)
    int downsampling = 1;
    double projection_ms = 0.0;  // median; whole (downsampled) map plus every light mask
    double window_ms = 0.0;      // choosing the window (auto only)
    oer::bench::IrradianceError error;
};

std::string subset_name(const std::vector<bool>& on) {
    std::string name;
    for (const bool light : on) {
        name += light ? '1' : '0';
    }
    return name;
}

// A configuration over every subset: what the Pareto front compares. The rig serves every
// subset from the same coefficients, so its error is the worst subset's.
struct Configuration {
    int order = 0;
    WindowSetting window;
    double window_cutoff = 0.0;  // of the window applied (0 for none)
    int downsampling = 1;
    double time_ms = 0.0;  // projection + window choice
    double worst_relative_rms = 0.0;
    double most_negative = 0.0;  // over every subset
};

std::string describe(const Configuration& c) {
    char window[32];
    if (c.window.cutoff_factor > 0.0) {
        std::snprintf(window, sizeof window, "%s %gx", name_of(c.window.mode),
                      c.window.cutoff_factor);
    } else {
        std::snprintf(window, sizeof window, "%s", name_of(c.window.mode));
    }
    char text[64];
    std::snprintf(text, sizeof text, "order %d, %s, 1/%d", c.order, window, c.downsampling);
    return text;
}

struct WorldResult {
    std::string name;
    int width = 0, height = 0;
    std::size_t lights = 0;
    int auto_order = 0;
    double auto_order_reference_error = 0.0;  // what build_rig measured when choosing it
    std::string order_reason;
    double truth_ms = 0.0;
    std::vector<Configuration> configurations;
    std::vector<std::size_t> front;  // indices into configurations
};

// The orders a cutoff rule is judged at: those the auto order picks above 2 (build_rig skips
// 4, 6 and 8, which add only odd bands, whose irradiance factor is 0). At order 2 (bands 0 and
// 1) every window above about 1.2 x order rings on studio and sunrise.
constexpr int kJudgedOrders[] = {3, 5, 7, 9};
// Ringing no worse than the auto window's: the most negative value at most this far below
// auto's (which is non-negative on choose_deringing_window's own 2048 normals).
constexpr double kRingingTolerance = 1e-6;

const Configuration* find_configuration(const WorldResult& world, int order,
                                        const WindowSetting& setting) {
    for (const Configuration& c : world.configurations) {
        if (c.order == order && c.downsampling == 1 && c.window.mode == setting.mode &&
            c.window.cutoff_factor == setting.cutoff_factor) {
            return &c;
        }
    }
    return nullptr;
}

// At full resolution, whether a window setting rings no more than the auto window at an order
// (nullopt when the sweep did not run that order).
std::optional<bool> rings_within_auto(const WorldResult& world, int order,
                                      const WindowSetting& setting) {
    const Configuration* candidate = find_configuration(world, order, setting);
    const Configuration* automatic = find_configuration(world, order, {WindowMode::Auto, 0.0});
    if (candidate == nullptr || automatic == nullptr) {
        return std::nullopt;
    }
    return candidate->most_negative >= automatic->most_negative - kRingingTolerance;
}

// The cutoff factor of the grid with the lowest worst-subset error among those ringing no more
// than the auto window, at an order (nullptr when the order was not run).
const Configuration* best_cutoff(const WorldResult& world, int order, WindowMode mode) {
    const Configuration* best = nullptr;
    for (const double factor : kCutoffFactors) {
        const WindowSetting setting{mode, factor};
        if (rings_within_auto(world, order, setting).value_or(false)) {
            const Configuration* c = find_configuration(world, order, setting);
            if (best == nullptr || c->worst_relative_rms < best->worst_relative_rms) {
                best = c;
            }
        }
    }
    return best;
}

// The values of the order-kMaxOrder basis at each normal, kept so that every configuration
// evaluates its expansion by dot products: the first order^2 values are the order's basis.
std::vector<double> basis_at(const std::vector<glm::dvec3>& normals) {
    const int count = oer::sh_count(kMaxOrder);
    std::vector<double> basis(normals.size() * std::size_t(count));
    for (std::size_t i = 0; i < normals.size(); ++i) {
        oer::sh_evaluate(kMaxOrder, normals[i],
                         std::span<double>(basis).subspan(i * std::size_t(count), count));
    }
    return basis;
}

std::vector<glm::dvec3> evaluate(const oer::ShRgb& sh, const std::vector<double>& basis,
                                 std::size_t normals) {
    const std::size_t stride = std::size_t(oer::sh_count(kMaxOrder));
    std::vector<glm::dvec3> values(normals, glm::dvec3(0.0));
    for (std::size_t i = 0; i < normals; ++i) {
        for (std::size_t j = 0; j < sh.coefficients.size(); ++j) {
            values[i] += sh.coefficients[j] * basis[i * stride + j];
        }
    }
    return values;
}

WorldResult sweep_world(const std::filesystem::path& path, bool quick, std::vector<Row>& rows) {
    WorldResult world;
    world.name = path.stem().string();
    const oer::LoadedImage loaded = oer::load_image_file(path.string());
    const oer::HdrImage& image = loaded.image;
    world.width = image.width;
    world.height = image.height;
    const oer::Rig rig = oer::build_rig(image, loaded.repaired, oer::RigOptions{});
    world.lights = rig.lights.size();
    world.auto_order = rig.order;
    world.auto_order_reference_error = rig.reference_error;
    world.order_reason = rig.order_reason;

    const std::vector<glm::dvec3> normals = oer::fibonacci_sphere(kNormals);
    const std::vector<double> basis = basis_at(normals);
    auto start = Clock::now();
    const std::vector<glm::dvec3> truth_all = oer::ReferenceIrradiance(image).at(normals);
    std::vector<std::vector<std::uint32_t>> light_pixels;
    std::vector<std::vector<glm::dvec3>> truth_light;
    for (const oer::Light& light : rig.lights) {
        light_pixels.push_back(light.pixels);
        truth_light.push_back(oer::bench::pixels_irradiance(image, light.pixels, normals));
    }
    const std::size_t subsets = std::size_t(1) << rig.lights.size();
    std::vector<Subset> subset_flags(subsets);
    std::vector<std::vector<glm::dvec3>> subset_truth(subsets, truth_all);
    for (std::size_t s = 0; s < subsets; ++s) {
        subset_flags[s].count = rig.lights.size();
        for (std::size_t k = 0; k < rig.lights.size(); ++k) {
            // Subset 0 is every light on, so that the whole map comes first.
            subset_flags[s].flags[k] = ((s >> k) & 1) == 0;
            if (!subset_flags[s].flags[k]) {
                for (std::size_t i = 0; i < normals.size(); ++i) {
                    subset_truth[s][i] -= truth_light[k][i];
                }
            }
        }
    }
    world.truth_ms = ms_since(start);

    std::vector<int> orders;
    if (quick) {
        // The auto order and the candidate below it (build_rig skips orders 4, 6, 8, which add
        // only odd bands), so that --quick still shows it is the lowest under the tolerance.
        orders = {1, 2, 3, std::max(1, rig.order <= 3 ? rig.order - 1 : rig.order - 2), rig.order};
        std::sort(orders.begin(), orders.end());
        orders.erase(std::unique(orders.begin(), orders.end()), orders.end());
    } else {
        for (int order = 1; order <= kMaxOrder; ++order) {
            orders.push_back(order);
        }
    }
    const std::vector<int> downsamplings =
        quick ? std::vector<int>{1, 4} : std::vector<int>{1, 2, 4, 8};
    const int repetitions = quick ? kQuickRepetitions : kFullRepetitions;
    for (const int factor : downsamplings) {
        const oer::HdrImage reduced =
            factor == 1 ? image : oer::bench::downsample_equirect(image, factor);
        const std::vector<std::vector<std::uint32_t>> masks =
            factor == 1 ? light_pixels
                        : oer::bench::downsample_light_pixels(image, light_pixels, factor);
        for (const int order : orders) {
            oer::ShProjection projection;
            const double projection_ms = oer::bench::median_ms(
                repetitions, [&] { projection = oer::project_environment(reduced, masks, order); });
            for (const WindowSetting& setting : window_settings()) {
                const auto window_start = Clock::now();
                const oer::ShWindow window = window_for(setting, projection);
                const double window_ms =
                    setting.mode == WindowMode::Auto ? ms_since(window_start) : 0.0;
                const double cutoff = window.kind == oer::WindowKind::None ? 0.0 : window.cutoff;
                Configuration configuration{
                    order, setting, cutoff, factor, projection_ms + window_ms, 0.0, 0.0};
                for (std::size_t s = 0; s < subsets; ++s) {
                    const oer::ShRgb irradiance = oer::irradiance_coefficients(
                        oer::subset_coefficients(projection, subset_flags[s].on()), window);
                    const oer::bench::IrradianceError error = oer::bench::irradiance_error(
                        evaluate(irradiance, basis, normals.size()), subset_truth[s]);
                    rows.push_back({world.name, subset_flags[s].as_vector(), order, setting, cutoff,
                                    factor, projection_ms, window_ms, error});
                    configuration.worst_relative_rms =
                        std::max(configuration.worst_relative_rms, error.relative_rms);
                    configuration.most_negative =
                        std::min(configuration.most_negative, error.most_negative);
                }
                world.configurations.push_back(configuration);
            }
        }
    }
    std::vector<double> times, errors;
    for (const Configuration& c : world.configurations) {
        times.push_back(c.time_ms);
        errors.push_back(c.worst_relative_rms);
    }
    world.front = oer::bench::pareto_front(times, errors);
    return world;
}

// The configuration build_rig's defaults pick (auto order, full resolution) with a window.
const Configuration* auto_configuration(const WorldResult& world, WindowMode window) {
    for (const Configuration& c : world.configurations) {
        if (c.order == world.auto_order && c.window.mode == window && c.downsampling == 1) {
            return &c;
        }
    }
    return nullptr;
}

// "on the front", or the front's configuration that beats it on both counts.
std::string front_verdict(const WorldResult& world, const Configuration& candidate) {
    for (const std::size_t i : world.front) {
        if (&world.configurations[i] == &candidate) {
            return "on the front";
        }
    }
    for (const std::size_t i : world.front) {
        const Configuration& c = world.configurations[i];
        if (c.time_ms <= candidate.time_ms &&
            c.worst_relative_rms <= candidate.worst_relative_rms) {
            char text[128];
            std::snprintf(text, sizeof text, "dominated by %s (%.2f ms, %.2f %%)",
                          describe(c).c_str(), c.time_ms, 100.0 * c.worst_relative_rms);
            return text;
        }
    }
    return "dominated";
}

void print_world(const WorldResult& world) {
    std::printf(
        "\n%s (%dx%d): %zu lights (%zu subsets), auto order %d (%s); truth %.0f ms\n"
        "  Pareto front of time (projection + window choice) against the worst subset's "
        "relative RMS:\n",
        world.name.c_str(), world.width, world.height, world.lights, std::size_t(1) << world.lights,
        world.auto_order, world.order_reason.c_str(), world.truth_ms);
    std::printf("    %-24s %9s %12s %14s\n", "configuration", "ms", "worst rms %",
                "most negative %");
    for (const std::size_t i : world.front) {
        const Configuration& c = world.configurations[i];
        std::printf("    %-24s %9.2f %12.3f %14.3f\n", describe(c).c_str(), c.time_ms,
                    100.0 * c.worst_relative_rms, 100.0 * c.most_negative);
    }
    for (const WindowMode window : {WindowMode::None, WindowMode::Auto}) {
        const Configuration* chosen = auto_configuration(world, window);
        if (chosen != nullptr) {
            std::printf("  auto order, window %-5s %-24s %7.2f ms %7.3f %% %8.3f %%  %s\n",
                        name_of(window), describe(*chosen).c_str(), chosen->time_ms,
                        100.0 * chosen->worst_relative_rms, 100.0 * chosen->most_negative,
                        front_verdict(world, *chosen).c_str());
        }
    }
    std::printf("  best cutoff / order ringing no more than auto (worst subset's rms):\n");
    for (const WindowMode mode : {WindowMode::Hanning, WindowMode::Lanczos}) {
        std::string line;
        for (const int order : kJudgedOrders) {
            if (const Configuration* best = best_cutoff(world, order, mode)) {
                char text[64];
                std::snprintf(text, sizeof text, "  order %d: %gx (%.2f %%)", order,
                              best->window.cutoff_factor, 100.0 * best->worst_relative_rms);
                line += text;
            }
        }
        std::printf("    %-8s%s\n", name_of(mode), line.c_str());
    }
    std::fflush(stdout);
}

// A fixed cutoff rule (cutoff = factor x order) for a window kind: the largest factor of the
// grid that rings no more than the auto window at every judged order of every world, and where
// the next factor rings (empty when the largest factor passes).
struct CutoffRule {
    double factor = 0.0;  // 0 when even the smallest factor rings somewhere
    std::string next_rings;
};

CutoffRule fixed_cutoff_rule(const std::vector<WorldResult>& worlds, WindowMode mode) {
    CutoffRule rule;
    for (const double factor : kCutoffFactors) {
        for (const WorldResult& world : worlds) {
            for (const int order : kJudgedOrders) {
                const WindowSetting setting{mode, factor};
                if (rings_within_auto(world, order, setting).value_or(true)) {
                    continue;
                }
                char text[128];
                std::snprintf(text, sizeof text, "%gx rings on %s at order %d (%.2f %%)", factor,
                              world.name.c_str(), order,
                              100.0 * find_configuration(world, order, setting)->most_negative);
                rule.next_rings = text;
                return rule;
            }
        }
        rule.factor = factor;
    }
    return rule;
}

void print_cutoff_rules(const std::vector<WorldResult>& worlds) {
    std::printf(
        "\nFixed cutoff rules (cutoff = factor x order, full resolution): the largest factor "
        "ringing no more than the auto window at orders 3, 5, 7, 9 on every world, and "
        "build_rig's default:\n");
    for (const auto& [mode, kind] : {std::pair{WindowMode::Hanning, oer::WindowKind::Hanning},
                                     std::pair{WindowMode::Lanczos, oer::WindowKind::Lanczos}}) {
        const CutoffRule rule = fixed_cutoff_rule(worlds, mode);
        std::printf("  %-8s %gx (default %gx)%s%s\n", name_of(mode), rule.factor,
                    oer::default_window_cutoff(kind, 1), rule.next_rings.empty() ? "" : "; ",
                    rule.next_rings.c_str());
    }
}

// Across the worlds: how often the defaults' choice (auto order, no window, full resolution)
// is on its world's front, and its worst-subset error.
void print_overview(const std::vector<WorldResult>& worlds) {
    std::size_t on_front = 0;
    double largest_error = 0.0;
    std::string off_front;
    for (const WorldResult& world : worlds) {
        const Configuration* chosen = auto_configuration(world, WindowMode::None);
        if (chosen == nullptr) {
            continue;
        }
        largest_error = std::max(largest_error, chosen->worst_relative_rms);
        if (front_verdict(world, *chosen) == "on the front") {
            ++on_front;
        } else {
            off_front += " " + world.name;
        }
    }
    std::printf(
        "\nThe defaults (auto order, window none, full resolution) are on the front on %zu of %zu "
        "worlds%s%s;\ntheir worst subset's relative RMS is at most %.3f %%.\n",
        on_front, worlds.size(), off_front.empty() ? "" : ", not on:", off_front.c_str(),
        100.0 * largest_error);
}

nlohmann::json configuration_json(const Configuration& c) {
    return {{"order", c.order},
            {"window", name_of(c.window.mode)},
            {"cutoff_per_order", c.window.cutoff_factor},
            {"window_cutoff", c.window_cutoff},
            {"downsampling", c.downsampling},
            {"time_ms", c.time_ms},
            {"worst_relative_rms", c.worst_relative_rms},
            {"most_negative", c.most_negative}};
}

nlohmann::json to_json(const std::vector<WorldResult>& worlds, const std::vector<Row>& rows,
                       bool quick) {
    nlohmann::json out = {{"benchmark", "lighting_sweep"},
                          {"quick", quick},
                          {"normals", kNormals},
                          {"repetitions", quick ? kQuickRepetitions : kFullRepetitions},
                          {"worlds", nlohmann::json::array()},
                          {"rows", nlohmann::json::array()}};
    for (const WorldResult& world : worlds) {
        nlohmann::json front = nlohmann::json::array();
        for (const std::size_t i : world.front) {
            front.push_back(configuration_json(world.configurations[i]));
        }
        nlohmann::json entry = {{"world", world.name},
                                {"width", world.width},
                                {"height", world.height},
                                {"lights", world.lights},
                                {"auto_order", world.auto_order},
                                {"auto_order_reference_error", world.auto_order_reference_error},
                                {"order_reason", world.order_reason},
                                {"truth_ms", world.truth_ms},
                                {"pareto_front", front}};
        for (const WindowMode window : {WindowMode::None, WindowMode::Auto}) {
            if (const Configuration* chosen = auto_configuration(world, window)) {
                nlohmann::json figures = configuration_json(*chosen);
                figures["verdict"] = front_verdict(world, *chosen);
                entry[std::string("auto_window_") + name_of(window)] = figures;
            }
        }
        for (const WindowMode mode : {WindowMode::Hanning, WindowMode::Lanczos}) {
            nlohmann::json best = nlohmann::json::object();
            for (const int order : kJudgedOrders) {
                if (const Configuration* c = best_cutoff(world, order, mode)) {
                    best[std::to_string(order)] = configuration_json(*c);
                }
            }
            entry["best_cutoff"][name_of(mode)] = best;
        }
        out["worlds"].push_back(entry);
    }
    for (const auto& [mode, kind] : {std::pair{WindowMode::Hanning, oer::WindowKind::Hanning},
                                     std::pair{WindowMode::Lanczos, oer::WindowKind::Lanczos}}) {
        const CutoffRule rule = fixed_cutoff_rule(worlds, mode);
        out["fixed_cutoff_rules"][name_of(mode)] = {
            {"cutoff_per_order", rule.factor},
            {"default_cutoff_per_order", oer::default_window_cutoff(kind, 1)},
            {"next_rings", rule.next_rings}};
    }
    for (const Row& row : rows) {
        out["rows"].push_back({{"world", row.world},
                               {"subset", subset_name(row.on)},
                               {"lights_on", row.on},
                               {"order", row.order},
                               {"window", name_of(row.window.mode)},
                               {"cutoff_per_order", row.window.cutoff_factor},
                               {"window_cutoff", row.window_cutoff},
                               {"downsampling", row.downsampling},
                               {"projection_ms", row.projection_ms},
                               {"window_ms", row.window_ms},
                               {"relative_rms", row.error.relative_rms},
                               {"max_relative_error", row.error.max_relative},
                               {"most_negative", row.error.most_negative}});
    }
    return out;
}

std::string to_csv(const std::vector<Row>& rows) {
    std::string csv =
        "world,subset,order,window,window_cutoff,downsampling,projection_ms,window_ms,"
        "relative_rms,max_relative_error,most_negative\n";
    char numbers[256];
    for (const Row& row : rows) {
        std::snprintf(numbers, sizeof numbers, ",%d,%s,%.6g,%d,%.6g,%.6g,%.9g,%.9g,%.9g\n",
                      row.order, name_of(row.window.mode), row.window_cutoff, row.downsampling,
                      row.projection_ms, row.window_ms, row.error.relative_rms,
                      row.error.max_relative, row.error.most_negative);
        csv += oer::bench::csv_field(row.world) + "," + oer::bench::csv_field(subset_name(row.on)) +
               numbers;
    }
    return csv;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const oer::bench::SweepArguments arguments = oer::bench::parse_sweep_arguments(argc, argv);
        const auto start = Clock::now();
        const std::vector<std::filesystem::path> paths = oer::bench::blender_worlds();
        std::printf(
            "oer lighting sweep%s: SH order x window x downsampling on %zu worlds, every on/off "
            "subset of the lights build_rig finds with its defaults.\n"
            "Error against the brute-force irradiance of the full map (double, every pixel) at "
            "%d Fibonacci normals;\nprojection time the median of %d runs of "
            "project_environment (whole map plus every light mask).\n",
            arguments.quick ? " (--quick)" : "", paths.size(), kNormals,
            arguments.quick ? kQuickRepetitions : kFullRepetitions);
        std::vector<WorldResult> worlds;
        std::vector<Row> rows;
        for (const auto& path : paths) {
            worlds.push_back(sweep_world(path, arguments.quick, rows));
            print_world(worlds.back());
        }
        if (!arguments.json_path.empty()) {
            oer::bench::write_text_file(arguments.json_path,
                                        to_json(worlds, rows, arguments.quick).dump(1) + "\n");
        }
        if (!arguments.csv_path.empty()) {
            oer::bench::write_text_file(arguments.csv_path, to_csv(rows));
        }
        print_cutoff_rules(worlds);
        print_overview(worlds);
        std::printf("\n%zu rows; sweep took %.1f s\n", rows.size(), ms_since(start) / 1e3);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lighting_sweep: %s\n", e.what());
        return 1;
    }
}
