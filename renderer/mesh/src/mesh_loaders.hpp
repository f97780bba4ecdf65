#pragma once
// Private to the mesh loading: one loader per file format (gltf_loading.cpp, obj_loading.cpp),
// called by load_mesh_memory (mesh_loading.cpp) once the size has been checked. Each returns
// a mesh already passed through finish_mesh (mesh_finishing.hpp).
#include <cstddef>
#include <span>
#include <string>

#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

Mesh load_gltf(std::span<const std::byte> bytes, const std::string& name, bool binary,
               const MeshLimits& limits);
Mesh load_obj(std::span<const std::byte> bytes, const std::string& name, const MeshLimits& limits);

}  // namespace oer::mesh_detail
