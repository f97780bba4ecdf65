#pragma once
// Meshes ready for drawing: every glTF node transform baked into the positions and normals
// (world space of the file, no rescaling), every primitive as an indexed triangle list, with
// the materials and base-color textures they use. Produced by the loaders (mesh_loading.hpp)
// and by code (default_product.hpp); validated before anything reaches GL.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace oer {

// An 8-bit sRGB RGBA image (a base-color texture), row 0 at the top.
struct Texture {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  // width * height * 4
};

struct Material {
    std::string name;
    // Linear RGBA multiplier of the base color (glTF baseColorFactor).
    glm::vec4 base_color{1.0f, 1.0f, 1.0f, 1.0f};
    int base_color_texture = -1;  // index into Mesh::textures, or -1
    // Kept for later shading models (glTF defaults: metallic 1, roughness 1).
    float metallic = 1.0f;
    float roughness = 1.0f;
    // Whether the Blinn-Phong specular term applies. An OBJ without a material is pure
    // Lambertian with albedo 0.8 and no specular term (DESIGN.md section 3).
    bool specular = true;
};

struct Primitive {
    std::string name;                  // "mesh 'Box' primitive 0" etc., for messages
    std::vector<glm::vec3> positions;  // world space of the file
    std::vector<glm::vec3> normals;    // unit, one per position
    // Empty, or one per position; never empty when the material has a texture (a glTF
    // primitive without TEXCOORD_0 whose material has one gets (0, 0) everywhere).
    std::vector<glm::vec2> texcoords;
    std::vector<std::uint32_t> indices;  // triangle list, 3 per triangle, all < positions.size()
    int material = 0;                    // index into Mesh::materials
};

struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
    glm::vec3 centre() const { return (min + max) * 0.5f; }
};

// What the loaders repaired rather than rejected, for the API to report.
struct MeshRepairs {
    // Normals present in the file but zero-length or non-finite, computed from the triangles
    // instead (angle-weighted, as for a file without normals).
    std::uint64_t normals_replaced = 0;
    // Normals present in the file whose length was not 1 (beyond 1e-3), normalised.
    std::uint64_t normals_renormalised = 0;
};

struct Mesh {
    std::vector<Primitive> primitives;
    std::vector<Material> materials;  // at least one
    std::vector<Texture> textures;
    Bounds bounds;  // of every position
    std::uint64_t triangle_count = 0;
    std::uint64_t vertex_count = 0;
    MeshRepairs repairs;
    // What was ignored (an OBJ's mtllib, a texture on a texCoord other than 0, ...), one line
    // each, for the API to pass on.
    std::vector<std::string> warnings;
};

}  // namespace oer
