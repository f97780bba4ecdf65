#pragma once
// Private to the mesh loading: one loader per file format (gltf_loading.cpp, obj_loading.cpp),
// called by load_mesh_memory (mesh_loading.cpp) once the size has been checked. Each returns
// a mesh already passed through finish_mesh (mesh_finishing.hpp).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

// folder: the canonical folder whose files the asset's URIs may name (a local .gltf's own), or
// nothing, when only data: URIs are read (uploads).
Mesh load_gltf(std::span<const std::byte> bytes, const std::string& name, bool binary,
               const MeshLimits& limits, const std::optional<std::filesystem::path>& folder);
Mesh load_obj(std::span<const std::byte> bytes, const std::string& name, const MeshLimits& limits);

}  // namespace oer::mesh_detail
