// `oer`: the command line over the renderer library (docs/design.md section 7). It links no GL:
// `oer render` runs `oer-render`, the executable beside it that does.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "commands.hpp"
#include "oer/api/version.hpp"

namespace {

constexpr const char* kUsage = R"(usage:
  oer preprocess MAP [--light-count auto|N] [--sh-order auto|N] [--window none|hanning|lanczos|auto]
                     [--model hdr|thesis] [--clustering directions|pixels] [options]
  oer irradiance-map MAP [--size WxH] [--exact] [--lights 1,0,...] -o OUT.(exr|hdr)
  oer masks MAP [--exposure EV] [--tonemap neutral|aces|none] -o OUT.png
  oer render --env MAP --mesh MESH [--mesh MESH ...] [--eye X,Y,Z --target X,Y,Z --up X,Y,Z
             --fov DEG] [--lights 1,0,1] [--size WxH] [--ground on|off]
             [--background env|transparent|#rrggbb] [--tonemap neutral|aces|none]
             [--exposure EV] [--shadows on|off] [--shadow-resolution N] [--shadow-filter pcf|hard]
             [--samples N] [--yaw DEG] [--quality Q] -o OUT.(jpg|png|exr)
  oer reference (the scene, camera, environment and light flags of render) [--bounce none|one]
                [--samples N] [--sample-seed N] [--threads N] [--stats FILE.json] -o OUT.exr
  oer --version

MAP is an .hdr or .exr file, or 'default' for the built-in studio environment; MESH is a .glb,
.gltf (embedded data) or .obj file, or 'default' for the built-in dress form.
--layout equirect|cross|mirror-ball|cube-faces reads other layouts (cube-faces: MAP is six
comma-separated files +X,-X,+Y,-Y,+Z,-Z). --max-pixels WxH bounds the decoded map.
Preprocessing options (every command): --max-lights N --shadow-threshold F --max-sh-order N
--sh-tolerance F --window-cutoff F --blur-radius F --light-percentile F --halo-percentile F
--clusters N --seed N --grow-connected true|false
)";

// Replaces this process with `oer-render` from this executable's folder, with the arguments
// after "render"; returns only when that fails.
int run_render(char** argv) {
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error) {
        std::cerr << "oer render: cannot find this executable (/proc/self/exe): " << error.message()
                  << "\n";
        return 1;
    }
    const std::string render = (self.parent_path() / "oer-render").string();
    std::vector<char*> render_argv{const_cast<char*>(render.c_str())};
    for (char** argument = argv + 2; *argument != nullptr; ++argument) {
        render_argv.push_back(*argument);
    }
    render_argv.push_back(nullptr);
    ::execv(render.c_str(), render_argv.data());
    std::cerr << "oer render: cannot run " << render << ": " << std::strerror(errno) << "\n";
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    if (arguments.empty() || arguments[0] == "--help" || arguments[0] == "-h") {
        std::cout << kUsage;
        return arguments.empty() ? 2 : 0;
    }
    if (arguments[0] == "--version") {
        std::cout << "oer " << oer::api::kVersion << "\n";
        return 0;
    }
    if (arguments[0] == "render") {
        return run_render(argv);
    }
    const std::map<std::string, oer::cli::Command> commands = {
        {"preprocess", oer::cli::preprocess_command},
        {"irradiance-map", oer::cli::irradiance_map_command},
        {"masks", oer::cli::masks_command},
        {"reference", oer::cli::reference_command},
    };
    const auto command = commands.find(arguments[0]);
    if (command == commands.end()) {
        std::cerr << "oer: unknown command '" << arguments[0] << "'\n" << kUsage;
        return 2;
    }
    return oer::cli::run_command(arguments[0], command->second,
                                 {arguments.begin() + 1, arguments.end()});
}
