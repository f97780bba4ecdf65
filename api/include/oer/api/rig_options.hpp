#pragma once
// Preprocessing options from string parameters: the query parameters of
// POST /v1/environments and the flags of `oer preprocess` (the CLI maps --light-count to
// light_count). One parser, so both accept and reject exactly the same values.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "oer/lighting/rig.hpp"

namespace oer::api {

// Recognised names: light_count (auto|0..16), max_lights, shadow_threshold, sh_order
// (auto|1..16), max_sh_order, sh_tolerance, window (none|hanning|lanczos|auto), window_cutoff,
// model (hdr|thesis), clustering (directions|pixels), blur_radius, light_percentile,
// halo_percentile, clusters, seed, grow_connected (true|false). Unknown names and bad values throw
// InvalidParameter.
RigOptions parse_rig_options(const std::map<std::string, std::string>& parameters);

// Is name one of the recognised option names?
bool is_rig_option(const std::string& name);

// Every recognised option name, sorted (for the published API description and its test).
std::vector<std::string> rig_option_names();

// Every option with defaults filled in, in a canonical form (the rig id hashes it).
nlohmann::json rig_options_to_json(const RigOptions& options);

// The inverse of rig_options_to_json, through parse_rig_options (so a stored document is held
// to the same ranges as a query): an object of option names to numbers, booleans or strings.
// Throws InvalidParameter naming the offending option.
RigOptions rig_options_from_json(const nlohmann::json& options);

}  // namespace oer::api
