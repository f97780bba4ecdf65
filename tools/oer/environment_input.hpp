#pragma once
// The MAP argument of every command: a file (or, for --layout cube-faces, six comma-separated
// files), or the word `default` for the built-in studio. Files go through the same in-memory
// decoder as uploads to the service.
#include <map>
#include <optional>
#include <string>

#include "command_line.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"

namespace oer::cli {

struct EnvironmentInput {
    LoadedImage loaded;
    std::string digest;  // SHA-256 of the source bytes (or of the built-in's name and version)
};

// The flags every command takes for its MAP and the rig it builds from it.
struct EnvironmentFlags {
    std::optional<std::string> layout;      // --layout
    std::optional<std::string> max_pixels;  // --max-pixels WxH
    // The preprocessing flags (--light-count, --sh-order, ...), by the api's option name.
    std::map<std::string, std::string> rig_options;
};

// Declares --layout, --max-pixels and one flag per api rig option (light_count as
// --light-count), stored in `flags`, which must outlive the parse.
void add_environment_flags(CLI::App& app, EnvironmentFlags& flags);

EnvironmentInput read_environment(const std::string& map, const EnvironmentFlags& flags);
RigOptions rig_options_from(const EnvironmentFlags& flags);

}  // namespace oer::cli
