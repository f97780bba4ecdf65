#pragma once
// The subcommands of `oer`; each takes the arguments after its name and returns the exit
// status. Errors are thrown (oer::Error, UsageError) and reported by run_command.
#include <string>
#include <vector>

namespace oer::cli {

int preprocess_command(const std::vector<std::string>& arguments);
int irradiance_map_command(const std::vector<std::string>& arguments);
int masks_command(const std::vector<std::string>& arguments);
// The path-traced ground truth of a render (renderer/reference, Embree; no GL).
int reference_command(const std::vector<std::string>& arguments);
// In oer-render, the one executable that links GL; `oer render` runs it.
int render_command(const std::vector<std::string>& arguments);

}  // namespace oer::cli
