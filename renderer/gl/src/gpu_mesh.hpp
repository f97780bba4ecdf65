#pragma once
// A Mesh uploaded to GL: one vertex array per primitive (positions, normals, uv at attribute
// locations 0, 1, 2; 32-bit indices) and its base-color textures as sRGB textures.
#include <GL/glcorearb.h>

#include <vector>

#include "gl_objects.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_lod.hpp"

namespace oer {

struct GpuPrimitive {
    gl::Object vertex_array;
    std::vector<gl::Object> buffers;
    std::vector<LodLevel> lods;  // finest first; their indices share one element buffer
    int material = 0;
};

// Draws the coarsest level of the primitive (its vertex array bound) whose error is at most
// max_error, in the mesh's units.
void draw_primitive(const GpuPrimitive& primitive, float max_error);

struct GpuMesh {
    std::vector<GpuPrimitive> primitives;
    std::vector<gl::Object> textures;  // parallel to Mesh::textures
};

GpuMesh upload_mesh(const Mesh& mesh);

}  // namespace oer
