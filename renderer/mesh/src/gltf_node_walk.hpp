#pragma once
// Private to the glTF loader: the scene's node graph walked depth first from its roots (the
// default scene's nodes, or with no scene every node that is nobody's child), each node's local
// transform (its matrix, or translation * rotation * scale) composed with its parent's. A node
// met again while on the stack is a cycle, met again after it was done, a node with two parents:
// both invalid glTF, refused, as are missing nodes, malformed or non-finite transforms and a
// graph deeper than the limit (oer::Error naming the asset).
#include <tiny_gltf.h>

#include <functional>
#include <string>

#include <glm/mat4x4.hpp>

namespace oer::mesh_detail {

// Called, in depth-first pre-order, for every node of the scene as it is entered: the node's
// index and world transform. The loader places the node's mesh and its camera by the same
// transform, so that both are walked one way.
using NodeVisitor = std::function<void(int node, const glm::dmat4& world)>;

void walk_nodes(const tinygltf::Model& model, const std::string& asset, int max_node_depth,
                const NodeVisitor& visit);

}  // namespace oer::mesh_detail
