#include <iostream>

#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/irradiance_map.hpp"

namespace oer::cli {

namespace {
// --exact sums over at most this many area-preserving samples of the map (see
// ReferenceIrradiance); --reference-samples 0 sums over every pixel.
constexpr std::size_t kDefaultReferenceSamples = 65536;
}  // namespace

int irradiance_map_command(const std::vector<std::string>& arguments) {
    CLI::App app("Writes the irradiance of MAP's rig (or, with --exact, of MAP itself).",
                 "oer irradiance-map");
    std::vector<std::string> maps;
    app.add_option("MAP", maps, "an .hdr or .exr file, or 'default'");
    std::string output, size = "400x200";
    std::optional<std::string> lights, reference_samples;
    bool exact = false;
    app.add_option("-o", output, "the map, OUT.(exr|hdr)");
    add_value_flag(app, "size", "WxH", [&size](const std::string& text) { size = text; });
    add_value_flag(app, "lights", "1,0,...", [&lights](const std::string& text) { lights = text; });
    add_value_flag(app, "reference-samples", "N",
                   [&reference_samples](const std::string& text) { reference_samples = text; });
    app.add_flag("--exact", exact, "sum over the map's pixels instead of the rig's SH");
    EnvironmentFlags environment;
    add_environment_flags(app, environment);
    if (!parse_flags(app, arguments)) {
        return 0;
    }
    if (maps.size() != 1 || output.empty()) {
        throw UsageError("irradiance-map takes one MAP and -o OUT.(exr|hdr)");
    }
    const auto [width, height] = parse_size("size", size, 16384);
    const EnvironmentInput input = read_environment(maps[0], environment);
    HdrImage map;
    if (exact) {
        std::size_t samples = kDefaultReferenceSamples;
        if (reference_samples) {
            const auto [count, one] =
                parse_size("reference-samples", *reference_samples + "x1", 1 << 30);
            samples = std::size_t(count) * std::size_t(one);
        }
        map = irradiance_map_exact(input.loaded.image, width, height, samples);
        std::cerr << "irradiance-map: exact reference over "
                  << (samples == 0 ? input.loaded.image.pixel_count() : samples)
                  << " samples at most\n";
    } else {
        const Rig rig = build_rig(input.loaded, rig_options_from(environment));
        const std::vector<double> visibility = api::parse_light_switches(lights, rig.lights.size());
        map = irradiance_map_from_sh(
            irradiance_coefficients(visibility_coefficients(rig.sh, visibility), rig.window), width,
            height);
    }
    write_image_file(map, output);
    return 0;
}

}  // namespace oer::cli
