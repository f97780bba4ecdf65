#include <iostream>

#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/rig_json.hpp"

namespace oer::cli {

int preprocess_command(const std::vector<std::string>& arguments) {
    CLI::App app("Prints the rig of MAP (lights, SH) as JSON.", "oer preprocess");
    std::vector<std::string> maps;
    app.add_option("MAP", maps, "an .hdr or .exr file, or 'default'");
    EnvironmentFlags environment;
    add_environment_flags(app, environment);
    if (!parse_flags(app, arguments)) {
        return 0;
    }
    if (maps.size() != 1) {
        throw UsageError("preprocess takes one MAP (a file, or 'default')");
    }
    const RigOptions options = rig_options_from(environment);
    const EnvironmentInput input = read_environment(maps[0], environment);
    const Rig rig = build_rig(input.loaded, options);
    std::cout << api::rig_to_json(rig, api::rig_id(input.digest, options)).dump(2) << "\n";
    return 0;
}

}  // namespace oer::cli
