#pragma once
// The inverse of rig_to_json: a stored rig document turned back into an oer::Rig for rendering,
// so that a rig computed before a restart is served after it without recomputation.
//
// The rig JSON gives each light's pixel count, not its pixels (which only the preview with its
// outlined lights needs): light_masks_to_json keeps them compactly beside the document, and
// rig_from_json restores them from it, checking each count.
#include <nlohmann/json.hpp>

#include "oer/lighting/rig.hpp"

namespace oer::api {

// Per light, its pixel indices as runs of consecutive indices: [first, length, first, length...].
nlohmann::json light_masks_to_json(const Rig& rig);

// Every member of the rig document is validated (types, ranges, one coefficient list of order^2
// RGB triples for the map and per light, one mask per light matching its pixel count); any
// damage throws oer::Error (InvalidInput) naming the member by its path, e.g. "sh/per_light/1".
// rig_to_json(rig_from_json(document, masks), id) gives back the document (numbers JSON holds
// exactly come back bit for bit).
Rig rig_from_json(const nlohmann::json& document, const nlohmann::json& masks);

}  // namespace oer::api
