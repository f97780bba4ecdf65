#pragma once
// Refinement of coarse meshes for per-vertex lighting data. The renderer stores precomputed
// radiance transfer per vertex (P.-P. Sloan, J. Kautz and J. Snyder, "Precomputed Radiance Transfer
// for Real-Time Rendering in Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002, which
// computes transfer at mesh vertices) and interpolates it across each triangle: on a box of 24
// vertices a face would get one value per corner and a blotchy, wrong gradient. Every mesh is
// therefore refined when it is finished (mesh_finishing.hpp, before tangents and before any
// level of detail) until no triangle edge is longer than transfer_edge_length; a mesh that is
// already finer is left unchanged.
#include <cstdint>

#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer {

// The longest triangle edge per-vertex transfer is given: 1/16 of the diagonal of the mesh's
// bounds (0 for bounds of zero size: no edge is split). Why 1/16: piecewise-linear
// interpolation between samples h apart misses a smooth function f by at most h^2 |f''| / 8,
// and occlusion that changes by D over a distance d (the gap to an occluder, the height above
// the ground) has |f''| of about D / d^2; the error stays under 1 % of D for every change over
// d >= 3.5 h, a quarter of the diagonal. A unit cube (diagonal sqrt 3) gets 16 segments along
// every side of every face, 1,734 vertices: a small fraction of the 35,000 of the Stanford bunny
// that the bake's cost is sized for.
double transfer_edge_length(const Bounds& bounds);

struct MeshRefinement {
    std::uint64_t vertices_added = 0;
    std::uint64_t triangles_added = 0;
    int passes = 0;              // passes that split edges
    bool stopped_early = false;  // by the limits, with a warning in the mesh's warnings
};

// Splits every triangle edge longer than max_edge_length (by more than a relative 1e-6, so
// that float rounding does not decide edges of exactly that length) at its midpoint, in passes.
// Each pass splits exactly the edges that are too long (the same decision, from the two end
// positions alone, for every triangle that has the edge), and replaces each triangle by the
// templates of red-green refinement (R. E. Bank, A. H. Sherman and A. Weiser, "Refinement
// Algorithms and Data Structures for Regular Local Mesh Refinement", 1983): two, three (the
// quadrilateral cut along its shorter diagonal) or four triangles for one, two or three split
// edges, each wound as its parent. A midpoint is one vertex for every triangle of the primitive
// with the edge's two vertex indices, so a closed surface stays closed; where vertices are
// duplicated for their attributes (a box's 24), or primitives meet, both sides split the edge
// at the same position, so no T-junction opens either. The new edges are halves, half-edges
// between midpoints, and medians: a median to a split edge between two that are not is shorter
// than max_edge_length, and the shorter diagonal of the three-triangle case is at most sqrt(3)/2
// of the longest edge, so the longest edge still too long shrinks by sqrt(3)/2 a pass at least.
// New vertices interpolate every attribute at the midpoint: position and texture coordinates
// (exactly, rounded once), the normal (the endpoints' sum, normalised), the tangent (xyz as the
// normal; w the endpoints' sign, or the lower-indexed endpoint's where they differ, a mirroring
// seam glTF leaves undefined). An edge whose midpoint rounds onto an end is not split.
// A pass that would take the mesh's vertices beyond min(limits.max_refined_vertices,
// limits.max_vertices), or its triangles beyond limits.max_triangles, is not made: refinement
// stops with the mesh as the last pass left it (still conforming), and a warning in
// mesh.warnings. Bounds and counts of `mesh` are not updated (finish_mesh computes them).
MeshRefinement refine_mesh(Mesh& mesh, double max_edge_length, const MeshLimits& limits);

}  // namespace oer
