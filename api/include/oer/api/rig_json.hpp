#pragma once
// The light rig as JSON (docs/design.md section 7): the same document from the CLI and the API.
#include <string>

#include <nlohmann/json.hpp>

#include "oer/lighting/rig.hpp"

namespace oer::api {

nlohmann::json rig_to_json(const Rig& rig, const std::string& id);

}  // namespace oer::api
