// glTF 2.0 (see oer/mesh_loading.hpp): the model parsed by tinygltf (gltf_parsing.hpp) becomes
// an oer::Mesh. The scene's node graph is walked (gltf_node_walk.hpp); each mesh a node
// instantiates has its primitives read (gltf_primitives.hpp), the node's transform baked into
// them (gltf_baking.hpp), and the materials they use converted (gltf_materials.hpp, with their
// textures: gltf_textures.hpp, gltf_samplers.hpp, gltf_texture_images.hpp). Compressed geometry
// is decoded first (EXT_meshopt_compression: gltf_meshopt.hpp; KHR_draco_mesh_compression:
// gltf_draco.hpp), instanced nodes are placed once per instance (gltf_instancing.hpp), and the
// materials of KHR_materials_variants are read beside the default ones (gltf_variants.hpp). TANGENT
// is read only where a normal texture needs it; finish_mesh generates it where the file has none.
// The cameras the nodes hold are placed by the same walk (gltf_cameras.hpp) and aimed at the
// finished mesh's bounds.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>

#include "gltf_baking.hpp"
#include "gltf_cameras.hpp"
#include "gltf_draco.hpp"
#include "gltf_instancing.hpp"
#include "gltf_materials.hpp"
#include "gltf_meshopt.hpp"
#include "gltf_node_walk.hpp"
#include "gltf_parsing.hpp"
#include "gltf_primitives.hpp"
#include "gltf_texture_images.hpp"
#include "gltf_textures.hpp"
#include "gltf_variants.hpp"
#include "mesh_errors.hpp"
#include "mesh_finishing.hpp"
#include "mesh_loaders.hpp"

namespace oer::mesh_detail {

namespace {

class GltfConverter {
  public:
    GltfConverter(const tinygltf::Model& model, const ParseContext& context,
                  const MeshLimits& limits)
        : model_(model),
          context_(context),
          limits_(limits),
          asset_(context.asset),
          primitives_(model, context.asset, limits),
          images_(model, context, limits, mesh_.textures),
          textures_(model, context.asset, images_, mesh_.warnings),
          materials_(model, context.asset, textures_, mesh_.materials, mesh_.warnings),
          cameras_(model, limits.max_cameras, mesh_.cameras, mesh_.warnings) {}

    Mesh convert() {
        mesh_.variants = read_variants(model_, asset_);
        walk_nodes(model_, asset_, limits_.max_node_depth,
                   [this](int node, const glm::dmat4& world) {
                       const int mesh = model_.nodes[std::size_t(node)].mesh;
                       if (mesh >= 0) {
                           instantiate(mesh, node, world);
                       }
                       cameras_.place(node, world);
                   });
        cameras_.finish();
        materials_.ensure_one();
        for (const std::string& extension : model_.extensionsUsed) {
            if (!supported_extension(extension)) {
                mesh_.warnings.push_back("the asset uses the extension " + one_line(extension, 80) +
                                         ", which is not supported: ignored");
            }
        }
        if (!context_.warnings.empty()) {
            mesh_.warnings.push_back("tinygltf: " + one_line(context_.warnings));
        }
        return std::move(mesh_);
    }

  private:
    // Every primitive of mesh `mesh_index`, placed by `world`, the transform of node `node`,
    // once per instance where the node has EXT_mesh_gpu_instancing.
    void instantiate(int mesh_index, int node, const glm::dmat4& world) {
        if (std::size_t(mesh_index) >= model_.meshes.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 "node " + std::to_string(node) + " refers to mesh " + std::to_string(mesh_index) +
                     ", which does not exist");
        }
        const tinygltf::Mesh& mesh = model_.meshes[std::size_t(mesh_index)];
        const std::string mesh_name = mesh.name.empty() ? "mesh " + std::to_string(mesh_index)
                                                        : "mesh '" + one_line(mesh.name, 80) + "'";
        if (mesh.primitives.empty()) {
            fail(ErrorKind::InvalidInput, asset_, mesh_name + " has no primitives");
        }
        const InstanceBudget budget{primitives_.triangle_budget(), primitives_.vertex_budget(),
                                    limits_.max_primitives - mesh_.primitives.size()};
        const std::vector<glm::dmat4> instances =
            instance_transforms(model_, node, mesh, mesh_name, asset_, budget);
        for (std::size_t i = 0; i < instances.size(); ++i) {
            const std::string instance_name =
                instances.size() == 1 ? mesh_name : mesh_name + " instance " + std::to_string(i);
            place(mesh, instance_name, world * instances[i]);
        }
    }

    // Every primitive of `mesh` (named `mesh_name`), placed by `world`.
    void place(const tinygltf::Mesh& mesh, const std::string& mesh_name, const glm::dmat4& world) {
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const std::string name = mesh_name + " primitive " + std::to_string(p);
            if (mesh_.primitives.size() >= limits_.max_primitives) {
                fail(ErrorKind::LimitExceeded, asset_,
                     "more than the limit of " + std::to_string(limits_.max_primitives) +
                         " primitives (counting every node's instance)");
            }
            Primitive primitive = build(mesh.primitives[p], name, world);
            if (!primitive.indices.empty()) {
                mesh_.primitives.push_back(std::move(primitive));
            } else {
                mesh_.warnings.push_back(name + " has no triangles and was left out");
            }
        }
    }

    // The primitive read, baked by `world`, with its material and its variants' (a primitive
    // without TEXCOORD_0 gets each material without its normal texture instead), TEXCOORD_1
    // where a texture of one of them reads it and, where a normal texture needs them, the file's
    // tangents.
    Primitive build(const tinygltf::Primitive& source, const std::string& name,
                    const glm::dmat4& world) {
        const std::uint64_t vertex_budget = primitives_.vertex_budget();
        Primitive primitive = primitives_.read(source, name, vertex_budget);
        mesh_.repairs.normals_renormalised += bake_transform(primitive, world);
        primitive.material = material_of(source.material, primitive, name);
        for (const int index : variant_material_indices(source, mesh_.variants.size(),
                                                        model_.materials.size(), asset_, name)) {
            primitive.variant_materials.push_back(index == kUnmappedVariant
                                                      ? primitive.material
                                                      : material_of(index, primitive, name));
        }
        if (reads_uv_set_1(primitive)) {
            primitive.texcoords1 =
                primitives_.texcoords1(source, name, primitive.positions.size(), vertex_budget);
        }
        const auto tangent = source.attributes.find("TANGENT");
        if (tangent != source.attributes.end() && !primitive.texcoords.empty() &&
            needs_tangents(primitive)) {
            primitive.tangents = primitives_.tangents(tangent->second, name,
                                                      primitive.positions.size(), vertex_budget);
            bake_tangents(primitive.tangents, world);
        }
        return primitive;
    }

    // The index in mesh_.materials of glTF material `index` (-1: the default) as `primitive`
    // draws it: without its normal texture when it has no TEXCOORD_0 to map it with.
    int material_of(int index, const Primitive& primitive, const std::string& name) {
        const int slot = materials_.slot(index, name);
        if (mesh_.materials[std::size_t(slot)].needs_tangents() && primitive.texcoords.empty()) {
            return materials_.without_normal_texture(index, slot, name);
        }
        return slot;
    }

    // Whether a material the primitive may be drawn with has a texture on TEXCOORD_1.
    bool reads_uv_set_1(const Primitive& primitive) const {
        for (const int material : primitive.materials_drawn()) {
            if (mesh_.materials[std::size_t(material)].reads_uv_set(1)) {
                return true;
            }
        }
        return false;
    }

    // Whether a material the primitive may be drawn with has a normal texture (its own or its
    // clear coat's).
    bool needs_tangents(const Primitive& primitive) const {
        for (const int material : primitive.materials_drawn()) {
            if (mesh_.materials[std::size_t(material)].needs_tangents()) {
                return true;
            }
        }
        return false;
    }

    const tinygltf::Model& model_;
    const ParseContext& context_;
    const MeshLimits& limits_;
    const std::string& asset_;
    Mesh mesh_;  // before the parts that append to it
    PrimitiveReader primitives_;
    TextureImages images_;
    TextureReferences textures_;
    GltfMaterials materials_;
    GltfCameras cameras_;
};

}  // namespace

Mesh load_gltf(std::span<const std::byte> bytes, const std::string& name, bool binary,
               const MeshLimits& limits, const std::optional<std::filesystem::path>& folder) {
    ParseContext context;
    context.folder = folder;
    tinygltf::Model model = parse_gltf(bytes, name, binary, limits, context);
    // Compressed geometry decoded into plain buffers and accessors first, so that the rest
    // reads them as any other.
    decode_meshopt_views(model, name, limits);
    decode_draco_primitives(model, name, limits);
    Mesh mesh = GltfConverter(model, context, limits).convert();
    finish_mesh(mesh, name, limits);
    aim_asset_cameras(mesh.cameras, mesh.bounds);
    return mesh;
}

}  // namespace oer::mesh_detail
