#include <iostream>

#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/rig_json.hpp"

namespace oer::cli {

int preprocess_command(const std::vector<std::string>& arguments) {
    const CommandLine line = parse_command_line(arguments, rig_option_flags(), {});
    if (line.positional.size() != 1) {
        throw UsageError("preprocess takes one MAP (a file, or 'default')");
    }
    const RigOptions options = rig_options_from(line);
    const EnvironmentInput input = read_environment(line.positional[0], line);
    const Rig rig = build_rig(input.loaded.image, input.loaded.repaired, options);
    std::cout << api::rig_to_json(rig, api::rig_id(input.digest, options)).dump(2) << "\n";
    return 0;
}

}  // namespace oer::cli
