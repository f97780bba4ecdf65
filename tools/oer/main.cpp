// `oer`: the command line over the renderer library (DESIGN.md section 7).
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "commands.hpp"
#include "oer/api/version.hpp"
#include "oer/core/error.hpp"

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
  oer --version

MAP is an .hdr or .exr file, or 'default' for the built-in studio environment; MESH is a .glb,
.gltf (embedded data) or .obj file, or 'default' for the built-in dress form.
--layout equirect|cross|mirror-ball|cube-faces reads other layouts (cube-faces: MAP is six
comma-separated files +X,-X,+Y,-Y,+Z,-Z). --max-pixels WxH bounds the decoded map.
Preprocessing options (every command): --max-lights N --shadow-threshold F --max-sh-order N
--sh-tolerance F --window-cutoff F --blur-radius F --light-percentile F --halo-percentile F
--clusters N --seed N --grow-connected true|false
)";

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
    const std::map<std::string, int (*)(const std::vector<std::string>&)> commands = {
        {"preprocess", oer::cli::preprocess_command},
        {"irradiance-map", oer::cli::irradiance_map_command},
        {"masks", oer::cli::masks_command},
        {"render", oer::cli::render_command},
    };
    const auto command = commands.find(arguments[0]);
    if (command == commands.end()) {
        std::cerr << "oer: unknown command '" << arguments[0] << "'\n" << kUsage;
        return 2;
    }
    try {
        return command->second({arguments.begin() + 1, arguments.end()});
    } catch (const oer::cli::UsageError& error) {
        std::cerr << "oer " << arguments[0] << ": " << error.what() << "\n";
        return 2;
    } catch (const oer::Error& error) {
        std::cerr << "oer " << arguments[0] << ": " << error.what() << "\n";
        return 1;
    } catch (const std::exception& error) {
        std::cerr << "oer " << arguments[0] << ": unexpected error: " << error.what() << "\n";
        return 1;
    }
}
