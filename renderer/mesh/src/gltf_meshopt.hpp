#pragma once
// Private to the glTF loader: EXT_meshopt_compression. Every bufferView the extension
// compresses is decoded by meshoptimizer (its ATTRIBUTES, TRIANGLES and INDICES modes, then
// the OCTAHEDRAL, QUATERNION and EXPONENTIAL filters) into a buffer of its own, and the view
// is pointed at it, so that accessors read decoded views as any other. Every declared count,
// stride and length is checked against the specification's constraints and the limits before
// the decoded view is allocated: the decoded views of one asset together stay within
// MeshLimits::max_bytes. Fallback buffers (the extension's "fallback": true, a buffer without
// data that only compressed views replace) hold no data: a view into one that is not
// compressed is an error naming it.
#include <tiny_gltf.h>

#include <string>

#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

// Whether buffer `buffer` is marked as EXT_meshopt_compression's fallback.
bool is_fallback_buffer(const tinygltf::Model& model, int buffer);

void decode_meshopt_views(tinygltf::Model& model, const std::string& asset,
                          const MeshLimits& limits);

}  // namespace oer::mesh_detail
