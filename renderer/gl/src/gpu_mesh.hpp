#pragma once
// A Mesh uploaded to GL: one vertex array per primitive (positions, normals, uv, tangents at
// attribute locations 0, 1, 2, 3, each only when the primitive has it; 32-bit indices) and its
// textures, sRGB or linear by their encoding, with their mipmaps.
#include <GL/glcorearb.h>

#include <limits>
#include <vector>

#include <glm/vec3.hpp>

#include "gl_objects.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_lod.hpp"

namespace oer {

struct GpuPrimitive {
    gl::Object vertex_array;
    std::vector<gl::Object> buffers;
    std::vector<LodLevel> lods;  // finest first; their indices share one element buffer
    glm::vec3 centre{0.0f};      // of the primitive's bounds, in the mesh's space: the blend order
};

// The per-vertex transferred irradiance of an occlusion frame at attribute location 4
// (mesh.vert): the primitive's vertices from `first_vertex` on in `buffer` (RGB floats), or,
// with buffer 0, the constant (0, 0, 0) of a frame without occlusion.
void attach_transferred_irradiance(const GpuPrimitive& primitive, GLuint buffer,
                                   std::size_t first_vertex);

// Draws the coarsest level of the primitive (its vertex array bound) whose error is at most
// max_error and whose longest edge at most max_edge, in the mesh's units (choose_lod).
void draw_primitive(const GpuPrimitive& primitive, float max_error,
                    float max_edge = std::numeric_limits<float>::infinity());

struct GpuMesh {
    std::vector<GpuPrimitive> primitives;
    std::vector<gl::Object> textures;  // parallel to Mesh::textures
};

GpuMesh upload_mesh(const Mesh& mesh);

}  // namespace oer
