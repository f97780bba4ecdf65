#pragma once
// Simple meshes with known geometry for renderer tests.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>

#include "oer/mesh/mesh.hpp"

namespace oer::testing {

inline Material lambertian(glm::vec3 albedo) {
    Material material;
    material.name = "lambertian";
    material.base_color = glm::vec4(albedo, 1.0f);
    material.model = ShadingModel::Lambertian;
    material.double_sided = true;
    return material;
}

// The glTF metallic-roughness material of these factors, single-sided.
inline Material metallic_roughness(glm::vec3 base, float metallic, float roughness) {
    Material material;
    material.name = "metallic-roughness";
    material.base_color = glm::vec4(base, 1.0f);
    material.metallic = metallic;
    material.roughness = roughness;
    return material;
}

inline void finish(Mesh& mesh) {
    mesh.bounds = {mesh.primitives[0].positions[0], mesh.primitives[0].positions[0]};
    for (const Primitive& primitive : mesh.primitives) {
        for (const glm::vec3& p : primitive.positions) {
            mesh.bounds.min = glm::min(mesh.bounds.min, p);
            mesh.bounds.max = glm::max(mesh.bounds.max, p);
        }
        mesh.vertex_count += primitive.positions.size();
        mesh.triangle_count += primitive.indices.size() / 3;
    }
}

// A UV sphere with exact unit normals, counter-clockwise seen from outside.
inline Mesh uv_sphere(glm::vec3 centre, float radius, int segments, int rings, glm::vec3 albedo) {
    Mesh mesh;
    Primitive sphere;
    sphere.name = "sphere";
    for (int r = 0; r <= rings; ++r) {
        const double theta = std::numbers::pi * r / rings;
        for (int s = 0; s <= segments; ++s) {
            const double phi = 2.0 * std::numbers::pi * s / segments;
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                              -std::sin(theta) * std::sin(phi));
            sphere.positions.push_back(centre + radius * n);
            sphere.normals.push_back(n);
        }
    }
    for (int r = 0; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            const std::uint32_t a = r * (segments + 1) + s, b = a + segments + 1;
            sphere.indices.insert(sphere.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    }
    mesh.primitives.push_back(std::move(sphere));
    mesh.materials.push_back(lambertian(albedo));
    finish(mesh);
    return mesh;
}

// An axis-aligned box with flat faces, counter-clockwise seen from outside.
inline Mesh box(glm::vec3 low, glm::vec3 high, glm::vec3 albedo) {
    Mesh mesh;
    Primitive faces;
    faces.name = "box";
    const glm::vec3 normals[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    const glm::vec3 centre = (low + high) * 0.5f, half = (high - low) * 0.5f;
    for (const glm::vec3& n : normals) {
        // Two axes spanning the face, with u x v = n.
        const glm::vec3 u = std::abs(n.y) > 0.5f ? glm::vec3(0, 0, n.y) : glm::vec3(0, 1, 0);
        const glm::vec3 v = glm::cross(n, u);
        const std::uint32_t base = std::uint32_t(faces.positions.size());
        for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
            faces.positions.push_back(centre + half * (n + float(a) * u + float(b) * v));
            faces.normals.push_back(n);
        }
        faces.indices.insert(faces.indices.end(),
                             {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    mesh.primitives.push_back(std::move(faces));
    mesh.materials.push_back(lambertian(albedo));
    finish(mesh);
    return mesh;
}

// A square in the plane z = centre.z facing +Z, 2 half_size wide, as two counter-clockwise
// triangles, uv (0, 0) at its top left (-x, +y) and (1, 1) at its bottom right, with tangents
// along +x (increasing u) and bitangent sign 1 (cross(+z, +x) = +y, the image's up).
inline Mesh quad(glm::vec3 centre, float half_size, glm::vec3 albedo) {
    Mesh mesh;
    Primitive square;
    square.name = "quad";
    for (const auto& [x, y] :
         {std::pair{-1.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, -1.0f}, {-1.0f, -1.0f}}) {
        square.positions.push_back(centre + half_size * glm::vec3(x, y, 0.0f));
        square.normals.emplace_back(0.0f, 0.0f, 1.0f);
        square.texcoords.emplace_back(0.5f * (x + 1.0f), 0.5f * (1.0f - y));
        square.tangents.emplace_back(1.0f, 0.0f, 0.0f, 1.0f);
    }
    square.indices = {0, 3, 2, 0, 2, 1};
    mesh.primitives.push_back(std::move(square));
    mesh.materials.push_back(lambertian(albedo));
    finish(mesh);
    return mesh;
}

// Appends the parallelogram origin + [0, 1] u + [0, 1] v as a divisions x divisions grid of
// vertices with the flat normal `normal` (a unit vector across u and v), its triangles
// counter-clockwise seen from that side.
inline void add_grid_face(Primitive& primitive, glm::vec3 origin, glm::vec3 u, glm::vec3 v,
                          glm::vec3 normal, int divisions) {
    if (glm::dot(glm::cross(u, v), normal) < 0.0f) {
        std::swap(u, v);  // the same parallelogram, turned to face `normal`
    }
    const auto base = std::uint32_t(primitive.positions.size());
    const auto row = std::uint32_t(divisions + 1);
    for (int j = 0; j <= divisions; ++j) {
        for (int i = 0; i <= divisions; ++i) {
            primitive.positions.push_back(origin + (float(i) / float(divisions)) * u +
                                          (float(j) / float(divisions)) * v);
            primitive.normals.push_back(normal);
        }
    }
    for (std::uint32_t j = 0; j < std::uint32_t(divisions); ++j) {
        for (std::uint32_t i = 0; i < std::uint32_t(divisions); ++i) {
            const std::uint32_t a = base + j * row + i, b = a + 1, c = a + row, d = c + 1;
            primitive.indices.insert(primitive.indices.end(), {a, b, d, a, d, c});
        }
    }
}

// A box open at the top with thin walls: primitive 0, "inside", the floor (y = 0) and four
// walls (x and z = +-half_size, up to y = height) facing into the box; primitive 1, "outside",
// the same five faces `thickness` further out (the bottom at y = -thickness) facing away, and
// the rim between them at the top facing up. Each
// face is a divisions x divisions grid (divisions even: a vertex at every face's centre, the
// floor's at the origin).
inline Mesh open_box(float half_size, float height, float thickness, int divisions,
                     glm::vec3 albedo) {
    Mesh mesh;
    const auto add_shell = [&](const char* name, float h, float bottom, float side) {
        Primitive shell;
        shell.name = name;
        const float top = height, wall = top - bottom;
        add_grid_face(shell, {-h, bottom, -h}, {2 * h, 0, 0}, {0, 0, 2 * h}, {0, side, 0},
                      divisions);
        add_grid_face(shell, {h, bottom, -h}, {0, wall, 0}, {0, 0, 2 * h}, {-side, 0, 0},
                      divisions);
        add_grid_face(shell, {-h, bottom, -h}, {0, wall, 0}, {0, 0, 2 * h}, {side, 0, 0},
                      divisions);
        add_grid_face(shell, {-h, bottom, h}, {0, wall, 0}, {2 * h, 0, 0}, {0, 0, -side},
                      divisions);
        add_grid_face(shell, {-h, bottom, -h}, {0, wall, 0}, {2 * h, 0, 0}, {0, 0, side},
                      divisions);
        mesh.primitives.push_back(std::move(shell));
    };
    add_shell("inside", half_size, 0.0f, 1.0f);
    add_shell("outside", half_size + thickness, -thickness, -1.0f);
    // The rim, facing up, closes the gap between the walls: rays never enter it.
    Primitive& outside = mesh.primitives.back();
    const float h = half_size, outer = half_size + thickness, t = thickness, up = height;
    const glm::vec3 y(0, 1, 0);
    add_grid_face(outside, {-outer, up, -outer}, {2 * outer, 0, 0}, {0, 0, t}, y, divisions);
    add_grid_face(outside, {-outer, up, h}, {2 * outer, 0, 0}, {0, 0, t}, y, divisions);
    add_grid_face(outside, {-outer, up, -h}, {t, 0, 0}, {0, 0, 2 * h}, y, divisions);
    add_grid_face(outside, {h, up, -h}, {t, 0, 0}, {0, 0, 2 * h}, y, divisions);
    mesh.materials.push_back(lambertian(albedo));
    finish(mesh);
    return mesh;
}

}  // namespace oer::testing
