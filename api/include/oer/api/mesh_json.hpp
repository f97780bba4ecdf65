#pragma once
// A stored mesh described as JSON (the answer of POST /v1/meshes and GET /v1/meshes/{id}, the
// schema `Mesh` of api/openapi.yaml), and the names of the mesh file formats.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::api {

std::string to_string(MeshFormat format);                     // "glb", "gltf", "obj"
MeshFormat mesh_format_from_string(const std::string& name);  // throws oer::Error

// { id, format (when known: the built-in product has none), counts {triangles, vertices,
// primitives, materials, textures}, bounds {min, max}, materials [{name, model ("lambertian",
// "metallic_roughness"), base_color (linear RGBA), has_texture (= textures.base_color, kept for
// older clients), metallic, roughness, emissive (linear RGB, times the emissive strength),
// alpha_mode ("opaque", "mask", "blend"), alpha_cutoff (mask only), double_sided, textures
// {base_color, metallic_roughness, normal, occlusion, emissive} (whether it has each), specular
// (whether it has a specular term)}], variants [{name, materials (the indices it draws),
// swatch {material, base_color, has_texture}}] (KHR_materials_variants, in the file's order;
// a render chooses one by name), cameras [{index, name, type ("perspective", "orthographic"),
// eye, target, up, fov_y (degrees; perspective only), znear, and as the file gives them
// aspect_ratio and zfar}] (the asset's own, Mesh::cameras: `camera=asset:N` in a render),
// repairs {normals_replaced, normals_renormalised}, warnings [...] }. Floats appear as their
// shortest decimal form.
nlohmann::json mesh_to_json(const Mesh& mesh, const std::string& id,
                            std::optional<MeshFormat> format = std::nullopt);

}  // namespace oer::api
