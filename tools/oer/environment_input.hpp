#pragma once
// The MAP argument of every command: a file (or, for --layout cube-faces, six comma-separated
// files), or the word `default` for the built-in studio. Files go through the same in-memory
// decoder as uploads to the service.
#include <string>

#include "command_line.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"

namespace oer::cli {

struct EnvironmentInput {
    LoadedImage loaded;
    std::string digest;  // SHA-256 of the source bytes (or of the built-in's name and version)
};

// Flags it reads: --layout, --max-pixels.
EnvironmentInput read_environment(const std::string& map, const CommandLine& line);

// The preprocessing flags shared by every command (--light-count, --sh-order, ...).
const std::set<std::string>& rig_option_flags();
RigOptions rig_options_from(const CommandLine& line);

}  // namespace oer::cli
