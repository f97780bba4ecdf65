#pragma once
// Private to the mesh loading: tangents for normal mapping where a file has none, by MikkTSpace
// (M. Mikkelsen, "Simulation of Wrinkled Surfaces Revisited", 2008; third_party/mikktspace),
// as the glTF 2.0 specification (section 3.7.2.1, "Meshes") asks of a client.
#include <cstddef>
#include <string>

#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

// Fills primitive.tangents, one per position, in glTF's convention (xyz the unit tangent along
// increasing u, w = +1 or -1 with bitangent = w * cross(normal, tangent) pointing up the
// image, that is along decreasing v). Needs unit normals and texcoords, one per position, and a
// valid triangle list. MikkTSpace gives a tangent per triangle corner; a vertex whose corners
// got different ones (a uv mirror seam, a hard edge of the uv mapping) is split into one
// vertex per tangent, its position, normal, texcoords (both sets) and colour copied. Returns the
// number of vertices added. A corner without a defined tangent (its triangles have no uv area) gets
// a unit vector perpendicular to its normal. Throws oer::Error (LimitExceeded) naming `asset` and
// the primitive when MikkTSpace runs out of memory.
std::size_t generate_tangents(Primitive& primitive, const std::string& asset);

}  // namespace oer::mesh_detail
