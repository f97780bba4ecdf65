#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/light_overlay.hpp"
#include "oer/lighting/tonemap.hpp"

namespace oer::cli {

int masks_command(const std::vector<std::string>& arguments) {
    std::set<std::string> valued = rig_option_flags();
    valued.insert({"o", "exposure", "tonemap"});
    const CommandLine line = parse_command_line(arguments, valued, {});
    if (line.positional.size() != 1 || !line.value("o")) {
        throw UsageError("masks takes one MAP and -o OUT.png");
    }
    const double exposure = parse_double("exposure", line.value("exposure").value_or("0"));
    const ToneMapper mapper = tone_mapper_from_string(line.value("tonemap").value_or("neutral"));
    const EnvironmentInput input = read_environment(line.positional[0], line);
    const Rig rig = build_rig(input.loaded.image, input.loaded.repaired, rig_options_from(line));
    const HdrImage display = to_display(input.loaded.image, exposure, mapper);
    write_image_file(draw_light_overlay(display, rig.lights), *line.value("o"));
    return 0;
}

}  // namespace oer::cli
