#pragma once
// Loading meshes from bytes: glTF 2.0 (.glb, and .gltf whose buffers and images are data:
// URIs; a URI naming a file is never read) through tinygltf, and OBJ through tinyobjloader.
// Every failure is an oer::Error naming the asset, the primitive and the reason.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "oer/mesh.hpp"

namespace oer {

enum class MeshFormat { Glb, Gltf, Obj };
// From a file name's extension (.glb, .gltf, .obj; case-insensitive); throws oer::Error.
MeshFormat mesh_format_from_name(const std::string& name);

struct MeshLimits {
    std::uint64_t max_bytes = 256ull << 20;
    std::uint64_t max_triangles = 5'000'000;
    std::uint64_t max_vertices = 5'000'000;
    std::uint64_t max_primitives = 10'000;
    std::uint64_t max_texture_pixels = 16ull << 20;
    int max_node_depth = 64;
};

Mesh load_mesh_memory(std::span<const std::byte> bytes, const std::string& name, MeshFormat format,
                      const MeshLimits& limits = {});
Mesh load_mesh_file(const std::string& path, const MeshLimits& limits = {});

}  // namespace oer
