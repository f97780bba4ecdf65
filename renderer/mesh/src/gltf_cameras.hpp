#pragma once
// Private to the glTF loader: the asset's own cameras (glTF 2.0 sections 3.10 and 5.12), each
// placed by the world transform of the node that holds it, as the node walk gives it
// (gltf_node_walk.hpp). A camera that cannot be placed (an index of no camera, a yfov outside
// (0, pi), a position beyond float's range, a node transform that flattens its view) is left out
// with a warning naming it, and so are cameras beyond MeshLimits::max_cameras: a product's
// geometry loads whatever its cameras hold.
#include <tiny_gltf.h>

#include <cstddef>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

class GltfCameras {
  public:
    GltfCameras(const tinygltf::Model& model, std::size_t max_cameras,
                std::vector<AssetCamera>& cameras, std::vector<std::string>& warnings);

    // The camera of node `node` (none: nothing), placed by `world`, the node's world transform.
    // Its target lies down its view, max(1, |eye|) ahead, until aim_asset_cameras.
    void place(int node, const glm::dmat4& world);

    // The warning for the cameras over the limit, if any: call once the walk is done.
    void finish();

  private:
    void leave_out(int node, const std::string& why);

    const tinygltf::Model& model_;
    const std::size_t max_cameras_;
    std::vector<AssetCamera>& cameras_;
    std::vector<std::string>& warnings_;
    std::size_t over_limit_ = 0;
};

// Each camera's target moved along its view to the depth of `bounds`' centre (the finished
// mesh's bounds), or left where GltfCameras::place put it when that centre is not in front.
void aim_asset_cameras(std::vector<AssetCamera>& cameras, const Bounds& bounds);

}  // namespace oer::mesh_detail
