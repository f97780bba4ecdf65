#pragma once
// The flags `oer render` and `oer reference` share (-o, --env, --mesh, --size, the query flags
// and the preprocessing flags), and the frame request they make: both commands see the same
// scene, camera, environment and lights from the same command line.
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "environment_input.hpp"
#include "oer/api/render_request.hpp"
#include "oer/scene/frame_request.hpp"

namespace oer::cli {

struct RenderInputs {
    std::string output;
    std::string environment_path;
    std::vector<std::string> mesh_paths;
    std::map<std::string, std::string> flags;  // the query flags given, and --size
    EnvironmentFlags environment;
};

// Declares the shared flags, storing into `inputs` (which must outlive the parse). `omitted`
// names query flags the command does not take from the service (`oer reference` gives
// --samples its own meaning).
void add_render_inputs(CLI::App& app, RenderInputs& inputs,
                       const std::set<std::string>& omitted = {});

struct RenderScene {
    api::RenderSpec spec;
    std::shared_ptr<const Rig> rig;
    FrameRequest request;
};

// Reads the flags through the service's parser (api::parse_render_query) and the files they
// name into a frame request of `format` ("jpeg", "png" or "exr"). Throws UsageError naming the
// flag at fault, oer::Error for unreadable files.
RenderScene read_render_scene(const RenderInputs& inputs, const std::string& format);

// The lowercase extension of a path ("exr" of "a/b.EXR"), empty without one.
std::string extension_of(const std::string& path);

}  // namespace oer::cli
