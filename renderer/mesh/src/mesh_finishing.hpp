#pragma once
// Private to the mesh loading: what every loader does last (mesh_loading.cpp). Normals are
// made unit or computed, the mesh refined for per-vertex data, tangents generated where a normal
// texture needs them, every invariant of oer::Mesh is checked, counts, limits and bounds.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

// Per-vertex normals of a triangle list: the sum over the triangles at a vertex of their unit
// geometric normals (counter-clockwise front faces) weighted by the triangle's angle at that
// vertex, normalised. A vertex on no triangle of non-zero area gets (0, 0, 0).
std::vector<glm::vec3> angle_weighted_normals(std::span<const glm::vec3> positions,
                                              std::span<const std::uint32_t> indices);

// Normals read from a file: a finite normal whose length is off 1 by more than 1e-3 is
// normalised (and counted, the return value); a zero-length or non-finite one becomes
// (0, 0, 0), for finish_mesh to compute.
std::uint64_t normalise_file_normals(std::vector<glm::vec3>& normals);

// Checks indices (a multiple of 3, each < positions.size()), finite positions and texture
// coordinates, attribute sizes (tangents: none or one per position, finite, w = +1 or -1),
// material indices and every texture reference of every material (each < textures.size(): an
// Internal error otherwise); computes normals where missing (an empty vector) or (0, 0, 0)
// (counted in mesh.repairs.normals_replaced); gives a primitive whose material uses any texture
// but which has no texture coordinates (0, 0) everywhere; refines the mesh until no edge is
// longer than transfer_edge_length, within limits.max_refined_vertices (none if that is 0;
// mesh_refinement.hpp);
// generates tangents with MikkTSpace (tangent_generation.hpp) for a primitive whose material has
// a normal texture and which has none, splitting vertices where needed; drops primitives without
// triangles; checks limits (vertices counted after those splits); fills bounds and counts.
// Throws oer::Error naming `asset` and the primitive.
void finish_mesh(Mesh& mesh, const std::string& asset, const MeshLimits& limits);

}  // namespace oer::mesh_detail
