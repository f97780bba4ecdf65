#pragma once
// Private to the glTF loader: KHR_draco_mesh_compression. Each primitive the extension
// compresses is decoded by Draco (Debian's libdraco 1.5) into a buffer of its own, with a new
// accessor per attribute (matched to the stream's attributes by the extension's attribute ids)
// and one of UNSIGNED_INT for the indices (Draco's faces), which the primitive is pointed at,
// so that it is read as any other. Before Draco allocates anything, the stream's header is read
// here: its counts of faces and points (or encoded vertices) must agree with the primitive's
// accessors and stay within the limits (every primitive decoded counts against
// MeshLimits::max_triangles and max_vertices together), so that a stream claiming 10^9 points
// is refused without decoding it.
#include <tiny_gltf.h>

#include <string>

#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

void decode_draco_primitives(tinygltf::Model& model, const std::string& asset,
                             const MeshLimits& limits);

}  // namespace oer::mesh_detail
