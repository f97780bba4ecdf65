#pragma once
// Private to the glTF loader: KHR_materials_variants (Khronos, 2021), the product's own
// colourways. The root lists the variants by name; each primitive maps some of them to another
// material. Both are validated here (names unique and non-empty, every index in range, no
// variant mapped twice in a primitive); the loader converts the materials (gltf_materials.hpp).
#include <tiny_gltf.h>

#include <cstddef>
#include <string>
#include <vector>

namespace oer::mesh_detail {

// The most variants a mesh may declare: a configurator's colourways are tens, not thousands,
// and every primitive keeps one material index per variant.
inline constexpr std::size_t kMaxVariants = 256;

// The variants' names, in order; empty when the asset declares none.
std::vector<std::string> read_variants(const tinygltf::Model& model, const std::string& asset);

// Marks a variant a primitive does not map in variant_material_indices' answer.
inline constexpr int kUnmappedVariant = -2;

// Per variant (variant_count of them), the glTF material index the primitive `source` (named
// `primitive`) maps it to, or kUnmappedVariant; empty when the mesh has no variants.
std::vector<int> variant_material_indices(const tinygltf::Primitive& source,
                                          std::size_t variant_count, std::size_t material_count,
                                          const std::string& asset, const std::string& primitive);

}  // namespace oer::mesh_detail
