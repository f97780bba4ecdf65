#pragma once
// Private to the glTF loader: EXT_mesh_gpu_instancing. A node with the extension places its
// mesh once per instance, at the node's world transform times the instance's translation,
// rotation and scale (the extension's TRANSLATION, ROTATION and SCALE accessors, of one count;
// each absent one the identity). The loader bakes every instance as a copy of the mesh's
// primitives, so the copies' triangles, vertices and primitives are checked against the
// limits from the accessors' declared counts before any instance is read: an instancing bomb
// (a million instances of a large mesh) is refused before anything is allocated.
#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

namespace oer::mesh_detail {

// What the mesh's instances may still add within the limits.
struct InstanceBudget {
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;
    std::uint64_t primitives = 0;
};

// The instances' transforms of node `node` (relative to the node), or one identity when the
// node has no EXT_mesh_gpu_instancing; `mesh` is the node's mesh, `mesh_name` names it.
std::vector<glm::dmat4> instance_transforms(const tinygltf::Model& model, int node,
                                            const tinygltf::Mesh& mesh,
                                            const std::string& mesh_name, const std::string& asset,
                                            const InstanceBudget& budget);

}  // namespace oer::mesh_detail
