#pragma once
// Private to the glTF loader: a node's world transform baked into its mesh's vertices, so that
// an oer::Mesh is in the file's world space with no node graph left.
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

// Positions by the world matrix, normals (made unit first: normalise_file_normals, whose count
// is returned) by its inverse transpose; a mirroring transform turns the triangles inside out,
// so their winding is flipped back. A flattening transform leaves no normal: they become
// (0, 0, 0), for finish_mesh to compute.
std::uint64_t bake_transform(Primitive& primitive, const glm::dmat4& world);

// Tangents by the world matrix's linear part (a tangent is a difference of positions, so not by
// the inverse transpose), made unit. The frame (tangent, bitangent, normal) transformed by M
// changes handedness with the sign of det(M) (the transformed normal stays on the side of M n),
// so a mirroring transform flips w. A flattening transform leaves no tangent: they are dropped,
// for finish_mesh to generate.
void bake_tangents(std::vector<glm::vec4>& tangents, const glm::dmat4& world);

}  // namespace oer::mesh_detail
