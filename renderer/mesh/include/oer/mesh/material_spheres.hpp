#pragma once
// A glTF 2.0 sample made by code in the manner of Khronos's MetalRoughSpheres
// (KhronosGroup/glTF-Sample-Models, 2.0/MetalRoughSpheres): a grid of spheres, one row of
// dielectrics above one row of metals, roughness rising from 0 on the left (-X) to 1 on the
// right, facing +Z, the grid's bottom at y = 0. Written as a binary glTF (.glb) so that it is
// read back through the same loader as a user's file: the built-in "spheres" preset, the
// frame tests' glossy scene and the material gallery all see what an upload of it would give.
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

namespace oer {

struct MaterialSpheresOptions {
    int columns = 5;  // roughness steps, in [2, 16]: roughness i / (columns - 1)
    glm::vec3 dielectric_color{0.80f, 0.10f, 0.08f};  // linear base colour of the top row
    glm::vec3 metal_color{1.00f, 0.78f, 0.34f};       // gold-like F0 of the bottom row
    // The columns' roughness, each in [0, 1], 2 to 16 of them; empty: i / (columns - 1).
    std::vector<float> roughness{};
    int rings = 32;  // the UV spheres' latitude rings, in [4, 256]; 2 x rings segments
};

// Radius and spacing of the grid's spheres, in the glTF's units (metres).
constexpr float kMaterialSphereRadius = 0.4f;
constexpr float kMaterialSphereSpacing = 1.0f;

// The .glb bytes. Material of row r (0 dielectric, 1 metal), column c: named
// "dielectric roughness 0.25" etc., metallicFactor r, roughnessFactor c / (columns - 1);
// sphere centre (c - (columns - 1) / 2, (1 - r) + radius', 0) times the spacing, where the
// bottom row's lowest point is y = 0. Throws oer::Error (InvalidInput) for options out of range.
std::vector<std::byte> material_spheres_glb(const MaterialSpheresOptions& options = {});

}  // namespace oer
