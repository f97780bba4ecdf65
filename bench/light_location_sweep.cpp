// The light-location sweep (sweep 3 of the accuracy report, docs/accuracy.md): synthetic maps whose
// lights are known, the hard cases of light location (one across the seam, one at a pole, a tiny
// sun 10^6 times the sky, two lights 3 degrees apart, a large soft box), each on a uniform sky;
// build_rig with the default options finds the lights (and, to compare, with each departure from
// the thesis undone: no connected-region growth; the thesis's pixel-space clustering), and each
// true light is matched with the found light holding most of its disc's energy. A found light may
// hold several true lights (a merge): then each of them is measured against the group, the
// power-weighted centre of their directions and the sum of their intensities, which is what one
// light standing for them should be. Per true light: the angle between the found and the true
// direction (the disc's centre, or the group's), and the found intensity's relative error in
// luminance against the painted discs' sum(L dOmega). For a merge, what it does to a shadow: a pole
// of height H on the ground, its tip's shadow under each true light against under the merged one
// (below). Prints a table; --json / --csv write one row per true light. A benchmark: it reports,
// the ctest (tests/bench/light_location_sweep_test.cpp) checks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "bench_support.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/light_location.hpp"
#include "oer/lighting/rig.hpp"
#include "sweep_support.hpp"

namespace {

using oer::bench::Clock;
using oer::bench::Disc;
using oer::bench::ms_since;

constexpr double kSky = 1.0;  // uniform grey sky radiance
constexpr int kRepetitions = 3;

struct Case {
    const char* name;
    std::vector<Disc> discs;
};

// The hard cases of light location, each disc in azimuth and elevation degrees (docs/design.md
// section 3; azimuth 180 is -X, on the seam), radius degrees and radiance.
std::vector<Case> cases() {
    const glm::vec3 lamp(200.0f), pair_first(600.0f), pair_second(400.0f);
    return {
        {"seam", {{180.0, 20.0, 4.0, lamp}}},
        {"pole", {{0.0, 90.0, 4.0, lamp}}},
        // Twice the real sun's angular radius, so that even the 1024x512 map paints a few pixels
        // (0.35 degrees each) of it.
        {"sun", {{40.0, 35.0, 0.5, glm::vec3(1e6f * float(kSky))}}},
        // Along a meridian, so the centres are exactly 3 degrees apart; bright enough that each
        // alone darkens its shadow by more than build_rig's 5 % (about 18 % and 12 %), so the
        // automatic light count keeps both once they are told apart.
        {"pair_3deg", {{-60.0, 28.5, 1.0, pair_first}, {-60.0, 31.5, 1.0, pair_second}}},
        {"soft_box", {{90.0, 45.0, 15.0, glm::vec3(20.0f * float(kSky))}}},
    };
}

struct Match {
    std::optional<std::size_t> found;       // index into the rig's lights, none when missed
    std::size_t merged_lights = 0;          // true lights the found light holds (1: no merge)
    double angular_error_degrees = 0.0;     // when found, to the group's power-weighted centre
    double intensity_relative_error = 0.0;  // against the group's summed luminance
};

// What a merge does to a shadow, for a vertical pole of height H standing on the ground (the
// scale of the object: for the bunny, its height): the shadow of its tip falls at
// -H (d.x, d.z) / d.y for a light towards d (above the horizon), so lights delta apart in
// elevation e put it H delta / sin^2(e) apart. Between the true lights' tips the truth is
// partly shadowed (some lights occluded, others not), where one merged light says all or none:
// that band's width, and its largest error, the irradiance on the ground of the brightest true
// light of the group over the ground's whole irradiance (sky and lights, normal +Y). Beside it,
// how far each disc's own extent spreads its tip (cot(e - r) - cot(e + r), the penumbra a light
// of radius r casts there), which point lights leave out anyway.
struct MergedShadow {
    std::vector<std::size_t> lights;  // the true lights (indices) merged into one found light
    double true_tips_apart = 0.0;     // largest distance between their tips' shadows, in H
    double merged_tip_offset = 0.0;   // merged tip from their power-weighted mean tip, in H
    double band_error_share = 0.0;    // largest irradiance error in the band / ground's
    double own_penumbra = 0.0;        // largest of the discs' own tip spreads, in H
};

// The light-location options compared: the defaults (what the sweep is about), and each of the
// two departures from the thesis undone, so that the figures say what each buys.
struct Variant {
    const char* name;
    oer::RigOptions options;
};

std::vector<Variant> variants() {
    oer::RigOptions no_growth;
    no_growth.location.grow_connected = false;
    oer::RigOptions pixels;
    pixels.location.clustering = oer::Clustering::Pixels;
    return {{"default", {}}, {"no_growth", no_growth}, {"thesis_pixels", pixels}};
}

struct CaseResult {
    std::string name;
    std::string variant;
    int width = 0, height = 0;
    double rig_ms = 0.0;  // median build_rig with the defaults
    std::vector<glm::dvec3> true_directions;
    std::vector<glm::dvec3> true_intensities;
    std::vector<oer::Light> found;
    std::vector<Match> matches;  // per true light
    std::vector<MergedShadow> merges;
    std::size_t extra_lights = 0;
};

// The shadow on the ground of the tip of a pole of height 1 at the origin, for a light towards
// direction (above the horizon).
glm::dvec2 tip_shadow(const glm::dvec3& direction) {
    return -glm::dvec2(direction.x, direction.z) / direction.y;
}

double cot_degrees(double degrees) {
    return 1.0 / std::tan(degrees * std::numbers::pi / 180.0);
}

std::vector<std::uint32_t> all_pixels(int width, int height) {
    std::vector<std::uint32_t> pixels(std::size_t(width) * std::size_t(height));
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        pixels[i] = std::uint32_t(i);
    }
    return pixels;
}

double angle_degrees(const glm::dvec3& a, const glm::dvec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) *
           180.0 / std::numbers::pi;
}

CaseResult run_case(const Case& c, const Variant& variant, int width, int height) {
    CaseResult result;
    result.name = c.name;
    result.variant = variant.name;
    result.width = width;
    result.height = height;
    const oer::bench::DiscMap map =
        oer::bench::make_disc_map(width, height, glm::vec3(kSky), c.discs);
    const oer::equirect::Grid grid(width, height);
    for (std::size_t k = 0; k < c.discs.size(); ++k) {
        result.true_directions.push_back(oer::bench::disc_centre(c.discs[k]));
        glm::dvec3 intensity(0.0);
        for (const std::uint32_t i : map.disc_pixels[k]) {
            intensity +=
                glm::dvec3(map.image.rgb(i)) * grid.row_solid_angle[i / std::uint32_t(width)];
        }
        result.true_intensities.push_back(intensity);
    }
    oer::Rig rig;
    result.rig_ms = oer::bench::median_ms(kRepetitions, [&] {
        rig = oer::build_rig(map.image, oer::RepairCounts{}, variant.options);
    });
    result.found = rig.lights;

    // Each true light belongs to the found light holding most of its disc's energy (L dOmega
    // luminance); true lights sharing one are a merge, measured against the group.
    std::vector<int> owner(std::size_t(width) * std::size_t(height), -1);
    for (std::size_t f = 0; f < rig.lights.size(); ++f) {
        for (const std::uint32_t i : rig.lights[f].pixels) {
            owner[i] = int(f);
        }
    }
    result.matches.resize(c.discs.size());
    std::vector<bool> used(rig.lights.size(), false);
    for (std::size_t t = 0; t < c.discs.size(); ++t) {
        std::vector<double> held(rig.lights.size(), 0.0);
        for (const std::uint32_t i : map.disc_pixels[t]) {
            if (owner[i] >= 0) {
                held[std::size_t(owner[i])] += oer::luminance(glm::dvec3(map.image.rgb(i))) *
                                               grid.row_solid_angle[i / std::uint32_t(width)];
            }
        }
        const auto most = std::max_element(held.begin(), held.end());
        if (most != held.end() && *most > 0.0) {
            result.matches[t].found = std::size_t(most - held.begin());
            used[*result.matches[t].found] = true;
        }
    }
    const std::vector<glm::dvec3> ground_irradiance = oer::bench::pixels_irradiance(
        map.image, all_pixels(width, height), std::vector<glm::dvec3>{{0.0, 1.0, 0.0}});
    for (std::size_t f = 0; f < rig.lights.size(); ++f) {
        std::vector<std::size_t> group;
        glm::dvec3 centre(0.0);
        glm::dvec2 mean_tip(0.0);
        double power = 0.0;
        for (std::size_t t = 0; t < c.discs.size(); ++t) {
            if (result.matches[t].found == f) {
                const double luminance = oer::luminance(result.true_intensities[t]);
                group.push_back(t);
                centre += luminance * result.true_directions[t];
                mean_tip += luminance * tip_shadow(result.true_directions[t]);
                power += luminance;
            }
        }
        if (group.empty()) {
            continue;
        }
        const oer::Light& found = rig.lights[f];
        for (const std::size_t t : group) {
            Match& match = result.matches[t];
            match.merged_lights = group.size();
            match.angular_error_degrees = angle_degrees(centre, found.direction);
            match.intensity_relative_error = (oer::luminance(found.intensity) - power) / power;
        }
        if (group.size() < 2 || found.direction.y <= 0.0) {
            continue;
        }
        MergedShadow merge;
        merge.lights = group;
        merge.merged_tip_offset = glm::length(tip_shadow(found.direction) - mean_tip / power);
        for (const std::size_t a : group) {
            const Disc& disc = c.discs[a];
            merge.own_penumbra = std::max(
                merge.own_penumbra, cot_degrees(disc.elevation_degrees - disc.radius_degrees) -
                                        cot_degrees(disc.elevation_degrees + disc.radius_degrees));
            merge.band_error_share =
                std::max(merge.band_error_share, oer::luminance(result.true_intensities[a]) *
                                                     result.true_directions[a].y /
                                                     oer::luminance(ground_irradiance[0]));
            for (const std::size_t b : group) {
                merge.true_tips_apart = std::max(
                    merge.true_tips_apart, glm::length(tip_shadow(result.true_directions[a]) -
                                                       tip_shadow(result.true_directions[b])));
            }
        }
        result.merges.push_back(merge);
    }
    result.extra_lights = std::size_t(std::count(used.begin(), used.end(), false));
    return result;
}

void print_case(const CaseResult& result) {
    for (std::size_t t = 0; t < result.matches.size(); ++t) {
        const Match& match = result.matches[t];
        std::printf("%-10s %-13s %-9s %5zu %6zu %6zu %9.1f ", result.name.c_str(),
                    result.variant.c_str(),
                    (std::to_string(result.width) + "x" + std::to_string(result.height)).c_str(),
                    t + 1, result.found.size(), result.extra_lights, result.rig_ms);
        if (match.found) {
            std::printf("%10.3f %+11.2f %% %6zu\n", match.angular_error_degrees,
                        100.0 * match.intensity_relative_error, match.merged_lights);
        } else {
            std::printf("%10s %13s %6s\n", "missed", "-", "-");
        }
    }
    for (const MergedShadow& merge : result.merges) {
        std::string lights;
        for (const std::size_t t : merge.lights) {
            if (!lights.empty()) {
                lights += '+';
            }
            lights += std::to_string(t + 1);
        }
        std::printf(
            "  lights %s as one: shadow of a pole of height H, the true tips %.3f H apart (the "
            "band the merge gets wrong,\n  by up to %.1f %% of the ground's irradiance), the "
            "merged tip %.3f H from their power-weighted mean;\n  each disc's own extent "
            "spreads its tip over %.3f H (a penumbra point lights leave out too)\n",
            lights.c_str(), merge.true_tips_apart, 100.0 * merge.band_error_share,
            merge.merged_tip_offset, merge.own_penumbra);
    }
    std::fflush(stdout);
}

nlohmann::json vector_json(const glm::dvec3& v) {
    return {v.x, v.y, v.z};
}

nlohmann::json to_json(const std::vector<CaseResult>& results, bool quick) {
    nlohmann::json out = {{"benchmark", "light_location_sweep"},
                          {"quick", quick},
                          {"sky_radiance", kSky},
                          {"cases", nlohmann::json::array()}};
    for (const CaseResult& result : results) {
        nlohmann::json lights = nlohmann::json::array();
        for (std::size_t t = 0; t < result.matches.size(); ++t) {
            const Match& match = result.matches[t];
            nlohmann::json light = {{"true_direction", vector_json(result.true_directions[t])},
                                    {"true_intensity", vector_json(result.true_intensities[t])},
                                    {"found", match.found.has_value()}};
            if (match.found) {
                const oer::Light& found = result.found[*match.found];
                light["found_index"] = *match.found;
                light["found_direction"] = vector_json(found.direction);
                light["found_intensity"] = vector_json(found.intensity);
                light["merged_lights"] = match.merged_lights;
                light["angular_error_degrees"] = match.angular_error_degrees;
                light["intensity_relative_error"] = match.intensity_relative_error;
            }
            lights.push_back(light);
        }
        nlohmann::json merges = nlohmann::json::array();
        for (const MergedShadow& merge : result.merges) {
            merges.push_back({{"lights", merge.lights},
                              {"true_tips_apart", merge.true_tips_apart},
                              {"merged_tip_offset", merge.merged_tip_offset},
                              {"band_error_share", merge.band_error_share},
                              {"own_penumbra", merge.own_penumbra}});
        }
        out["cases"].push_back({{"case", result.name},
                                {"options", result.variant},
                                {"width", result.width},
                                {"height", result.height},
                                {"rig_ms", result.rig_ms},
                                {"lights_found", result.found.size()},
                                {"extra_lights", result.extra_lights},
                                {"lights", lights},
                                {"merged_shadows", merges}});
    }
    return out;
}

std::string to_csv(const std::vector<CaseResult>& results) {
    std::string csv =
        "case,options,width,height,light,found,merged_lights,angular_error_degrees,"
        "intensity_relative_error,lights_found,extra_lights,rig_ms\n";
    char line[256];
    for (const CaseResult& result : results) {
        for (std::size_t t = 0; t < result.matches.size(); ++t) {
            const Match& match = result.matches[t];
            char errors[64] = ",,";  // a missed light has no figures: three empty fields
            if (match.found) {
                std::snprintf(errors, sizeof errors, "%zu,%.9g,%.9g", match.merged_lights,
                              match.angular_error_degrees, match.intensity_relative_error);
            }
            std::snprintf(line, sizeof line, ",%d,%d,%zu,%d,%s,%zu,%zu,%.6g\n", result.width,
                          result.height, t + 1, match.found ? 1 : 0, errors, result.found.size(),
                          result.extra_lights, result.rig_ms);
            csv += oer::bench::csv_field(result.name) + "," +
                   oer::bench::csv_field(result.variant) + line;
        }
    }
    return csv;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const oer::bench::SweepArguments arguments = oer::bench::parse_sweep_arguments(argc, argv);
        const auto start = Clock::now();
        std::printf(
            "oer light-location sweep%s: known lights on a uniform sky of radiance %g, found by "
            "build_rig\nwith the default options, then with connected growth off, then with the "
            "thesis's pixel-space\nclustering (median of %d runs). Per true light: the angle "
            "to the found light holding most of its energy, and the found intensity's\nrelative "
            "error in luminance against the painted disc's sum(L dOmega); when one found light "
            "holds several\ntrue lights (merged), against their power-weighted centre and "
            "summed intensity.\n\n",
            arguments.quick ? " (--quick)" : "", kSky, kRepetitions);
        std::printf("%-10s %-13s %-9s %5s %6s %6s %9s %10s %13s %6s\n", "case", "options", "map",
                    "light", "found", "extra", "rig ms", "angle deg", "intensity", "merged");
        std::vector<std::pair<int, int>> sizes = {{1024, 512}};
        if (!arguments.quick) {
            sizes.emplace_back(2048, 1024);
        }
        std::vector<CaseResult> results;
        for (const auto& [width, height] : sizes) {
            for (const Variant& variant : variants()) {
                for (const Case& c : cases()) {
                    results.push_back(run_case(c, variant, width, height));
                    print_case(results.back());
                }
            }
        }
        if (!arguments.json_path.empty()) {
            oer::bench::write_text_file(arguments.json_path,
                                        to_json(results, arguments.quick).dump(1) + "\n");
        }
        if (!arguments.csv_path.empty()) {
            oer::bench::write_text_file(arguments.csv_path, to_csv(results));
        }
        std::printf("\nsweep took %.1f s\n", ms_since(start) / 1e3);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "light_location_sweep: %s\n", e.what());
        return 1;
    }
}
