#pragma once
// The subcommands of `oer`; each takes the arguments after its name and returns the exit
// status. Errors are thrown (oer::Error, UsageError) and reported by main.
#include <string>
#include <vector>

namespace oer::cli {

int preprocess_command(const std::vector<std::string>& arguments);
int irradiance_map_command(const std::vector<std::string>& arguments);
int masks_command(const std::vector<std::string>& arguments);
int render_command(const std::vector<std::string>& arguments);

}  // namespace oer::cli
