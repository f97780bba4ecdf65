#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/light_overlay.hpp"
#include "oer/lighting/tonemap.hpp"

namespace oer::cli {

int masks_command(const std::vector<std::string>& arguments) {
    CLI::App app("Writes MAP with every light's outline drawn on it.", "oer masks");
    std::vector<std::string> maps;
    app.add_option("MAP", maps, "an .hdr or .exr file, or 'default'");
    std::string output, exposure = "0", tonemap = "neutral";
    add_value_flag(app, "exposure", "EV",
                   [&exposure](const std::string& text) { exposure = text; });
    add_value_flag(app, "tonemap", "neutral|aces|none",
                   [&tonemap](const std::string& text) { tonemap = text; });
    app.add_option("-o", output, "the picture, OUT.png");
    EnvironmentFlags environment;
    add_environment_flags(app, environment);
    if (!parse_flags(app, arguments)) {
        return 0;
    }
    if (maps.size() != 1 || output.empty()) {
        throw UsageError("masks takes one MAP and -o OUT.png");
    }
    const double exposure_ev = parse_double("exposure", exposure);
    const ToneMapper mapper = tone_mapper_from_string(tonemap);
    const EnvironmentInput input = read_environment(maps[0], environment);
    const Rig rig = build_rig(input.loaded, rig_options_from(environment));
    const HdrImage display = to_display(input.loaded.image, exposure_ev, mapper);
    write_image_file(draw_light_overlay(display, rig.lights), output);
    return 0;
}

}  // namespace oer::cli
