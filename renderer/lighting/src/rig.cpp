#include "oer/lighting/rig.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "oer/core/enum_names.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/reference_irradiance.hpp"
#include "oer/lighting/tonemap.hpp"

namespace oer {

namespace {
constexpr EnumNames<LightingModel, 2> kModelNames = {
    {{LightingModel::Hdr, "hdr"}, {LightingModel::Thesis, "thesis"}}};
constexpr EnumNames<Clustering, 2> kClusteringNames = {
    {{Clustering::Directions, "directions"}, {Clustering::Pixels, "pixels"}}};
}  // namespace

std::string to_string(LightingModel model) {
    return name_of(model, kModelNames);
}

LightingModel lighting_model_from_string(const std::string& name) {
    return value_named(name, kModelNames, "lighting model");
}

std::string to_string(Clustering clustering) {
    return name_of(clustering, kClusteringNames);
}

Clustering clustering_from_string(const std::string& name) {
    return value_named(name, kClusteringNames, "clustering");
}

namespace {

// Normals on which light visibility and SH order are judged; the accuracy figures of the
// tests use the same lattice.
constexpr int kJudgingNormals = 1024;
// The exact reference sums over at most this many area-preserving samples of the map: the
// irradiance is a cosine-smoothed signal, and tests/lighting/reference_irradiance_test.cpp
// measures the error this reduction adds.
constexpr std::size_t kReferenceSamples = 16384;

using Clock = std::chrono::steady_clock;

double elapsed_ms(Clock::time_point since) {
    return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

std::string percent(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f %%", fraction * 100.0);
    return text;
}

void validate(const RigOptions& options) {
    const auto fail = [](const std::string& message) {
        throw Error(ErrorKind::InvalidInput, message);
    };
    if (options.light_count && (*options.light_count < 0 || *options.light_count > 16)) {
        fail("light_count must be auto or 0..16, got " + std::to_string(*options.light_count));
    }
    if (options.max_lights < 0 || options.max_lights > 16) {
        fail("max_lights must be 0..16, got " + std::to_string(options.max_lights));
    }
    if (!(options.shadow_visibility_threshold >= 0.0 &&
          options.shadow_visibility_threshold <= 1.0)) {
        fail("shadow_threshold must be in [0, 1]");
    }
    if (options.sh_order && (*options.sh_order < 1 || *options.sh_order > kMaxShOrder)) {
        fail("sh_order must be auto or 1.." + std::to_string(kMaxShOrder) + ", got " +
             std::to_string(*options.sh_order));
    }
    if (options.max_sh_order < 1 || options.max_sh_order > kMaxShOrder) {
        fail("max_sh_order must be 1.." + std::to_string(kMaxShOrder) + ", got " +
             std::to_string(options.max_sh_order));
    }
    if (!(options.sh_tolerance > 0.0 && options.sh_tolerance < 1.0)) {
        fail("sh_tolerance must be in (0, 1)");
    }
    if (!(options.window_cutoff >= 0.0 && options.window_cutoff <= 1000.0)) {
        fail("window_cutoff must be in [0, 1000] (0: twice the SH order)");
    }
}

std::vector<std::vector<std::uint32_t>> pixel_lists(const std::vector<Light>& lights) {
    std::vector<std::vector<std::uint32_t>> lists;
    lists.reserve(lights.size());
    for (const Light& light : lights) {
        lists.push_back(light.pixels);
    }
    return lists;
}

// The largest darkening light k's shadow can cause: max over normals of E_k(n) / E_all(n),
// with irradiance from the order-3 SH the renderer shades with (so the figure is the one a
// viewer would see).
double largest_darkening(const ShRgb& all_irradiance, const ShRgb& light_irradiance,
                         const std::vector<glm::dvec3>& normals) {
    double largest = 0.0;
    for (const glm::dvec3& n : normals) {
        const double total = luminance(all_irradiance.evaluate(n));
        if (total <= 0.0) {
            continue;
        }
        largest = std::max(largest, luminance(light_irradiance.evaluate(n)) / total);
    }
    return std::min(largest, 1.0);
}

struct LightChoice {
    std::vector<std::size_t> kept;  // indices into the candidates, in order
    std::string reason;
};

LightChoice choose_lights(const LightLocation& located, const ShProjection& candidates,
                          const RigOptions& options, const std::vector<glm::dvec3>& normals) {
    LightChoice choice;
    if (options.light_count) {
        for (std::size_t k = 0; k < located.lights.size(); ++k) {
            choice.kept.push_back(k);
        }
        choice.reason = "requested " + std::to_string(*options.light_count);
        if (located.lights.size() < std::size_t(*options.light_count)) {
            choice.reason +=
                "; found " + std::to_string(located.lights.size()) + ": " + located.note;
        }
        return choice;
    }
    const ShRgb all_irradiance = irradiance_coefficients(candidates.all);
    std::string dropped;
    for (std::size_t k = 0; k < located.lights.size(); ++k) {
        const double darkening = largest_darkening(
            all_irradiance, irradiance_coefficients(candidates.per_light[k]), normals);
        if (darkening >= options.shadow_visibility_threshold) {
            choice.kept.push_back(k);
        } else {
            dropped += (dropped.empty() ? "" : ", ") + std::string("candidate ") +
                       std::to_string(k + 1) + " darkens at most " + percent(darkening);
        }
    }
    choice.reason = "auto: " + std::to_string(choice.kept.size()) + " of " +
                    std::to_string(located.lights.size()) +
                    " candidates cast a shadow darkening at least " +
                    percent(options.shadow_visibility_threshold);
    if (!dropped.empty()) {
        choice.reason += " (" + dropped + ")";
    }
    if (!located.note.empty()) {
        choice.reason += "; " + located.note;
    }
    return choice;
}

struct OrderChoice {
    int order = 3;
    double error = -1.0;
    std::string reason;
};

// Lowest order whose irradiance error against the exact reference is under the tolerance.
// Orders 4, 6, 8 add only odd bands, whose clamped-cosine factor A_l is zero: they never
// improve irradiance and are skipped.
OrderChoice choose_order(const HdrImage& image, const ShProjection& order3,
                         const RigOptions& options, const std::vector<glm::dvec3>& normals) {
    OrderChoice choice;
    if (options.sh_order) {
        choice.order = *options.sh_order;
        choice.reason = "requested " + std::to_string(choice.order);
        return choice;
    }
    const ReferenceIrradiance reference(image, kReferenceSamples);
    const std::vector<glm::dvec3> exact = reference.at(normals);
    const auto error_of = [&](const ShRgb& radiance) {
        const ShRgb irradiance = irradiance_coefficients(radiance);
        std::vector<glm::dvec3> approx;
        approx.reserve(normals.size());
        for (const glm::dvec3& n : normals) {
            approx.push_back(irradiance.evaluate(n));
        }
        return relative_rms_error(approx, exact);
    };
    ShRgb high;
    for (int order = 1; order <= options.max_sh_order; order = order < 3 ? order + 1 : order + 2) {
        ShRgb radiance;
        if (order <= 3) {
            radiance = order3.all.truncated(order);
        } else {
            if (high.order == 0) {
                const int max_odd =
                    options.max_sh_order % 2 == 1 ? options.max_sh_order : options.max_sh_order - 1;
                high = project_environment(image, {}, max_odd).all;
            }
            radiance = high.truncated(order);
        }
        choice.order = order;
        choice.error = error_of(radiance);
        if (choice.error <= options.sh_tolerance) {
            choice.reason = "auto: lowest order with irradiance error " + percent(choice.error) +
                            " <= " + percent(options.sh_tolerance);
            return choice;
        }
    }
    choice.reason = "auto: no order up to " + std::to_string(options.max_sh_order) + " reaches " +
                    percent(options.sh_tolerance) + "; order " + std::to_string(choice.order) +
                    " has " + percent(choice.error);
    return choice;
}

}  // namespace

double default_window_cutoff(WindowKind kind, int order) {
    if (order < 1) {
        throw Error(ErrorKind::InvalidInput,
                    "default_window_cutoff: SH order " + std::to_string(order) + " is below 1");
    }
    // The figures behind the factors are in rig.hpp and bench/README.md (lighting_sweep).
    switch (kind) {
        case WindowKind::Hanning:
            return 2.0 * order;
        case WindowKind::Lanczos:
            return 1.5 * order;
        case WindowKind::None:
            break;
    }
    throw Error(ErrorKind::InvalidInput,
                "default_window_cutoff: a window of kind none has no cutoff");
}

Rig build_rig(const LoadedImage& loaded, const RigOptions& options) {
    Rig rig = build_rig(loaded.image, loaded.repaired, options);
    rig.source_range = loaded.range;
    return rig;
}

Rig build_rig(const HdrImage& image, const RepairCounts& repaired, const RigOptions& options) {
    validate(options);
    if (image.width < 1 || image.height < 1) {
        throw Error(ErrorKind::InvalidInput, "environment map is empty");
    }
    Rig rig;
    rig.source_width = image.width;
    rig.source_height = image.height;
    rig.repaired = repaired;
    rig.options = options;
    rig.model = options.model;
    const auto total_start = Clock::now();

    auto start = Clock::now();
    const int candidates = options.light_count.value_or(options.max_lights);
    LightLocation located = locate_lights(image, candidates, options.location);
    rig.timings_ms["locate_lights"] = elapsed_ms(start);

    start = Clock::now();
    const std::vector<glm::dvec3> normals = fibonacci_sphere(kJudgingNormals);
    const ShProjection candidate_sh = project_environment(image, pixel_lists(located.lights), 3);
    const LightChoice chosen = choose_lights(located, candidate_sh, options, normals);
    ShProjection chosen_sh{candidate_sh.all, {}, candidate_sh.all_above_horizon, {}};
    for (const std::size_t k : chosen.kept) {
        rig.lights.push_back(std::move(located.lights[k]));
        chosen_sh.per_light.push_back(candidate_sh.per_light[k]);
        chosen_sh.per_light_above_horizon.push_back(candidate_sh.per_light_above_horizon[k]);
    }
    rig.light_count_reason = chosen.reason;
    rig.timings_ms["choose_lights"] = elapsed_ms(start);

    start = Clock::now();
    const OrderChoice order = choose_order(image, candidate_sh, options, normals);
    rig.order = order.order;
    rig.order_reason = order.reason;
    rig.reference_error = order.error;
    rig.timings_ms["choose_order"] = elapsed_ms(start);

    start = Clock::now();
    const auto light_pixels = pixel_lists(rig.lights);
    if (options.model == LightingModel::Thesis) {
        rig.sh = project_environment(thesis_tone_map(image), light_pixels, rig.order);
    } else if (rig.order <= 3) {
        // Projection at a lower order is the truncation of the order-3 one.
        rig.sh.all = chosen_sh.all.truncated(rig.order);
        rig.sh.all_above_horizon = chosen_sh.all_above_horizon.truncated(rig.order);
        for (std::size_t k = 0; k < chosen_sh.per_light.size(); ++k) {
            rig.sh.per_light.push_back(chosen_sh.per_light[k].truncated(rig.order));
            rig.sh.per_light_above_horizon.push_back(
                chosen_sh.per_light_above_horizon[k].truncated(rig.order));
        }
    } else {
        rig.sh = project_environment(image, light_pixels, rig.order);
    }
    rig.timings_ms["project"] = elapsed_ms(start);

    start = Clock::now();
    switch (options.window) {
        case WindowChoice::None:
            rig.window = {};
            rig.window_reason = "requested none";
            break;
        case WindowChoice::Hanning:
        case WindowChoice::Lanczos:
            rig.window.kind =
                options.window == WindowChoice::Hanning ? WindowKind::Hanning : WindowKind::Lanczos;
            rig.window.cutoff = options.window_cutoff > 0.0
                                    ? options.window_cutoff
                                    : default_window_cutoff(rig.window.kind, rig.order);
            rig.window_reason = "requested " + to_string(rig.window.kind);
            break;
        case WindowChoice::Auto:
            rig.window = choose_deringing_window(rig.sh, WindowKind::Hanning);
            rig.window_reason = rig.window.kind == WindowKind::None
                                    ? "auto: every on/off subset is non-negative without a window"
                                    : "auto: weakest Hanning window keeping every on/off subset "
                                      "non-negative";
            break;
    }
    rig.timings_ms["window"] = elapsed_ms(start);
    rig.timings_ms["total"] = elapsed_ms(total_start);
    return rig;
}

}  // namespace oer
