#pragma once
// Private to the glTF loader: the JSON types of the glTF properties the loader uses (and of
// every name, extension and texture reference), checked against the glTF 2.0 schema before
// tinygltf parses the asset. tinygltf silently replaces a property of the wrong type by its
// default ("scene": "hello" becomes the first scene); this refuses it, naming the property.
#include <cstddef>
#include <span>
#include <string>

#include "oer/core/checked_json.hpp"

namespace oer::mesh_detail {

// `json` is the .gltf text or a .glb's JSON chunk, parsed within bounds on its values and
// nesting (gltf_schema.cpp says which) before anything else parses it. Throws oer::Error naming
// `asset`: InvalidInput for JSON that is not, nests too deep, or has a property of the wrong
// type, with its path ("materials[0].pbrMetallicRoughness must be an object"); LimitExceeded
// for more values than the bound. Returns the parsed JSON.
checked_json::Json check_gltf_schema(std::span<const std::byte> json, const std::string& asset);

}  // namespace oer::mesh_detail
