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
    std::set<std::string> valued = rig_option_flags();
    valued.insert({"o", "size", "lights", "reference-samples"});
    const CommandLine line = parse_command_line(arguments, valued, {"exact"});
    if (line.positional.size() != 1 || !line.value("o")) {
        throw UsageError("irradiance-map takes one MAP and -o OUT.(exr|hdr)");
    }
    const auto [width, height] = parse_size("size", line.value("size").value_or("400x200"), 16384);
    const EnvironmentInput input = read_environment(line.positional[0], line);
    HdrImage map;
    if (line.has("exact")) {
        std::size_t samples = kDefaultReferenceSamples;
        if (const auto text = line.value("reference-samples")) {
            const auto [count, one] = parse_size("reference-samples", *text + "x1", 1 << 30);
            samples = std::size_t(count) * std::size_t(one);
        }
        map = irradiance_map_exact(input.loaded.image, width, height, samples);
        std::cerr << "irradiance-map: exact reference over "
                  << (samples == 0 ? input.loaded.image.pixel_count() : samples)
                  << " samples at most\n";
    } else {
        const Rig rig =
            build_rig(input.loaded.image, input.loaded.repaired, rig_options_from(line));
        const std::vector<double> visibility =
            api::parse_light_switches(line.value("lights"), rig.lights.size());
        map = irradiance_map_from_sh(
            irradiance_coefficients(visibility_coefficients(rig.sh, visibility), rig.window), width,
            height);
    }
    write_image_file(map, *line.value("o"));
    return 0;
}

}  // namespace oer::cli
