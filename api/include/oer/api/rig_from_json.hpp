#pragma once
// The inverse of rig_to_json: a stored rig document turned back into an oer::Rig for rendering,
// so that a rig computed before a restart is served after it without recomputation.
//
// The rig JSON gives each light's pixel count, not its pixels (which only the preview with its
// outlined lights needs): light_masks_to_json keeps them compactly beside the document, and
// rig_from_json restores them from it, checking each count.
#include <cstdint>

#include <nlohmann/json.hpp>

#include "oer/core/checked_json.hpp"
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

// What a stored rig ({"rig": rig_to_json's document, "masks": light_masks_to_json's}) of a map
// of at most max_map_pixels pixels holds at most, to parse it within these bounds
// (checked_json::parse_bounded) before rig_from_json reads it: the masks, two values per run
// of a light's pixels (the lights' pixels are disjoint: at most one run per pixel of the map)
// and an array per light; the rest under 2^17 values (up to 65 lists of SH coefficients of
// order 16, 1024 values each, and a few dozen values per light), counted as 2^18; nesting 6
// levels (document, rig, sh, per_light, light, coefficient), counted as 16.
checked_json::JsonBounds stored_rig_bounds(std::uint64_t max_map_pixels);

}  // namespace oer::api
