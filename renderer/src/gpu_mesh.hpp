#pragma once
// A Mesh uploaded to GL: one vertex array per primitive (positions, normals, uv at attribute
// locations 0, 1, 2; 32-bit indices) and its base-colour textures as sRGB textures.
#include <GL/glcorearb.h>

#include <vector>

#include "gl_objects.hpp"
#include "oer/mesh.hpp"

namespace oer {

struct GpuPrimitive {
    gl::Object vertex_array;
    std::vector<gl::Object> buffers;
    GLsizei index_count = 0;
    int material = 0;
};

struct GpuMesh {
    std::vector<GpuPrimitive> primitives;
    std::vector<gl::Object> textures;  // parallel to Mesh::textures
};

GpuMesh upload_mesh(const Mesh& mesh);

}  // namespace oer
