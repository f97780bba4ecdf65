#pragma once
// Levels of detail of a primitive (meshoptimizer's quadric edge-collapse simplification,
// Garland and Heckbert 1997): on llvmpipe the vertex and triangle set-up work of a dense mesh
// drawn a few hundred pixels tall costs more than all its shading, and triangles smaller than
// a pixel add nothing to the picture. A frame draws the coarsest level whose geometric error
// is under half a pixel (or half a shadow-map texel).
#include <cstdint>
#include <limits>
#include <vector>

#include "oer/mesh/mesh.hpp"

namespace oer {

struct LodLevel {
    std::uint32_t first_index = 0;  // into LodIndices::indices
    std::uint32_t index_count = 0;
    float error = 0.0f;  // largest distance from the full mesh, in the mesh's units
    // Its longest triangle edge, in the mesh's units: per-vertex lighting (the transfer's)
    // is interpolated along it, so a frame lit through a transfer needs short edges too.
    float longest_edge = 0.0f;
};

struct LodIndices {
    std::vector<std::uint32_t> indices;  // every level's triangles, one after another
    std::vector<LodLevel> levels;        // finest (the whole primitive, error 0) first
};

// The full primitive reordered for the post-transform vertex cache, then levels of about half
// the triangles each while simplification still removes a fifth of them. Borders stay fixed,
// so that a primitive's level never opens a crack against its neighbours.
LodIndices build_lods(const Primitive& primitive);

// The coarsest level whose error is at most max_error and whose longest edge is at most
// max_edge (the finest when none is). A flat face simplifies to two triangles at no geometric
// error, which would interpolate a transfer between its corners alone: frames lit through a
// transfer bound the edge by the refinement's length (mesh_refinement.hpp).
const LodLevel& choose_lod(const std::vector<LodLevel>& levels, float max_error,
                           float max_edge = std::numeric_limits<float>::infinity());

}  // namespace oer
