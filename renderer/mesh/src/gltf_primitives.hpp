#pragma once
// Private to the glTF loader: one primitive's geometry read from its accessors (gltf_accessors.hpp)
// and checked: its mode (triangles, strips and fans, the last two made lists; lines and points
// refused), POSITION, NORMAL, TEXCOORD_0 and COLOR_0 (RGB or RGBA, made RGBA) of one count, indices
// in range, finite positions, and the limits on vertices and triangles counted over every primitive
// read. TANGENT and TEXCOORD_1 are read apart, only where a material needs them.
#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "gltf_accessors.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

// How many triangles `count` vertices (or indices) make in `mode` (a triangle mode).
std::uint64_t triangles_of(int mode, std::uint64_t count);

class PrimitiveReader {
  public:
    PrimitiveReader(const tinygltf::Model& model, const std::string& asset,
                    const MeshLimits& limits)
        : model_(model), asset_(asset), limits_(limits), accessors_(model, asset) {}

    // The vertices the next primitive may have within limits.max_vertices.
    std::uint64_t vertex_budget() const { return limits_.max_vertices - vertices_; }
    // Likewise the triangles within limits.max_triangles.
    std::uint64_t triangle_budget() const { return limits_.max_triangles - triangles_; }

    // The primitive `name` ("mesh 'Box' primitive 0") as in the file (positions, normals and
    // texture coordinates, indices as a triangle list; no material, no tangents), each
    // attribute read within `vertex_budget`; its vertices and triangles are counted.
    Primitive read(const tinygltf::Primitive& source, const std::string& name,
                   std::uint64_t vertex_budget);

    // TANGENT (accessor `accessor`): VEC4 of FLOAT, `vertex_count` of them, finite; xyz made
    // unit; w, the bitangent's sign, must be +1 or -1 (within 1e-3, then made exact). Read
    // within `vertex_budget`, the one the primitive's POSITION was read within.
    std::vector<glm::vec4> tangents(int accessor, const std::string& name, std::size_t vertex_count,
                                    std::uint64_t vertex_budget) const;

    // TEXCOORD_1, as TEXCOORD_0 is read (accessor formats, finite values are checked later),
    // `vertex_count` of them; empty when the primitive has none. Read apart, only where a
    // material the primitive may be drawn with has a texture on set 1.
    std::vector<glm::vec2> texcoords1(const tinygltf::Primitive& source, const std::string& name,
                                      std::size_t vertex_count, std::uint64_t vertex_budget) const;

  private:
    std::vector<glm::vec4> read_colors(int accessor, const std::string& name,
                                       std::uint64_t vertex_budget) const;
    void read_attributes(const tinygltf::Primitive& source, const std::string& name,
                         std::uint64_t vertex_budget, Primitive& primitive) const;
    std::vector<std::uint32_t> read_indices(const tinygltf::Primitive& source,
                                            const std::string& name,
                                            std::size_t vertex_count) const;
    void check_positions_finite(const Primitive& primitive, const std::string& name) const;

    const tinygltf::Model& model_;
    const std::string& asset_;
    const MeshLimits& limits_;
    AccessorReader accessors_;
    std::uint64_t vertices_ = 0;
    std::uint64_t triangles_ = 0;
};

}  // namespace oer::mesh_detail
