#pragma once
// Loading meshes: glTF 2.0 (.glb, and .gltf whose buffers and images are data: URIs, or, from a
// local file, files inside its own folder) through tinygltf, and OBJ through tinyobjloader.
// Every failure is an oer::Error naming the asset, the primitive and the reason.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "oer/mesh/mesh.hpp"

namespace oer {

enum class MeshFormat { Glb, Gltf, Obj };
// From a file name's extension (.glb, .gltf, .obj; case-insensitive); throws oer::Error.
MeshFormat mesh_format_from_name(const std::string& name);

// Checked before the memory they bound is allocated where the format allows (an OBJ's
// triangles and 'v' lines are counted before parsing; accessors before reading; images on
// their headers; compressed glTF data on its declared counts before it is decoded). Vertices are
// counted after baking, every node's instance of a mesh apart, and every instance of an
// EXT_mesh_gpu_instancing node apart.
struct MeshLimits {
    // The asset's bytes (a .gltf's files together), and apart the bytes its
    // EXT_meshopt_compression views decode to, together.
    std::uint64_t max_bytes = 256ull << 20;
    std::uint64_t max_triangles = 5'000'000;
    std::uint64_t max_vertices = 5'000'000;
    // The vertices refinement for per-vertex transfer (mesh_refinement.hpp) may bring a mesh
    // to: it stops there with a warning instead of failing. Far below max_vertices, so that the
    // copies MikkTSpace makes afterwards for tangents still fit, and so that a coarse mesh of
    // many large triangles cannot turn into a bake of millions of vertices. 0: no refinement
    // (the triangles as the file has them).
    std::uint64_t max_refined_vertices = 1'000'000;
    std::uint64_t max_primitives = 10'000;
    std::uint64_t max_texture_pixels = 16ull << 20;        // per image, checked on its header
    std::uint64_t max_total_texture_pixels = 64ull << 20;  // every decoded texture together
    int max_node_depth = 64;
    // The asset's cameras listed (Mesh::cameras): the rest are left out with a warning.
    std::size_t max_cameras = 64;
};

// The bytes are checked against limits.max_bytes first; `name` (a file name or an upload's
// name) starts every error message. Nothing but `bytes` is ever read: a glTF URI that is not
// a data: URI is an error naming it. Safe to call from several threads at once.
Mesh load_mesh_memory(std::span<const std::byte> bytes, const std::string& name, MeshFormat format,
                      const MeshLimits& limits = {});
// The file at `path`, as load_mesh_memory would load its bytes, except that a .gltf's URIs may
// also name files inside the .gltf's own folder (its buffers and images beside it): a URI
// whose file lies outside that folder, by ".." or an absolute path or a symbolic link leading
// out, is an error naming it, and nothing outside is read. The referenced files count against
// limits.max_bytes together.
Mesh load_mesh_file(const std::string& path, const MeshLimits& limits = {});

}  // namespace oer
