#include "mesh_registry.hpp"

#include <span>

#include "oer/api/content_id.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/mesh/default_product.hpp"

namespace oer::server {

namespace {

std::span<const std::byte> as_bytes(std::string_view text) {
    return std::as_bytes(std::span(text.data(), text.size()));
}

// What a mesh holds in memory (and, roughly, on the GPU).
std::size_t charge_of(const Mesh& mesh) {
    std::size_t bytes = 0;
    for (const Primitive& primitive : mesh.primitives) {
        bytes += primitive.positions.size() * sizeof(glm::vec3) * 2 +
                 primitive.texcoords.size() * sizeof(glm::vec2) +
                 primitive.indices.size() * sizeof(std::uint32_t);
    }
    for (const Texture& texture : mesh.textures) {
        bytes += texture.rgba.size();
    }
    return bytes;
}

}  // namespace

MeshRegistry::MeshRegistry(AssetStore& store, ServiceMetrics& metrics, const MeshLimits& limits,
                           std::size_t cache_bytes)
    : store_(store), metrics_(metrics), limits_(limits), meshes_(cache_bytes) {
    auto mesh = std::make_shared<const Mesh>(make_default_product());
    const std::string id(api::kDefaultPresetId);
    preset_ =
        std::make_shared<const StoredMesh>(StoredMesh{id, mesh, api::mesh_to_json(*mesh, id)});
}

MeshRegistry::Upload MeshRegistry::upload(std::string_view bytes, MeshFormat format) {
    const std::string id = api::sha256_hex(bytes);
    if (store_.contains(SourceKind::Mesh, id)) {
        if (auto known = find(id)) {
            return {std::move(known), true};
        }
    }
    // Loaded before it is stored, so that bytes that are not a mesh never enter the store.
    Mesh mesh =
        load_mesh_memory(as_bytes(bytes), "upload." + api::to_string(format), format, limits_);
    store_.put_source(SourceKind::Mesh, bytes, api::to_string(format));
    return {remember(id, std::move(mesh), format), false};
}

std::shared_ptr<const StoredMesh> MeshRegistry::find(const std::string& id) {
    if (id == api::kDefaultPresetId) {
        return preset_;
    }
    if (!api::is_content_id(id)) {
        return nullptr;
    }
    if (auto known = meshes_.get(id)) {
        metrics_.cache(CacheName::Mesh, true);
        return known;
    }
    metrics_.cache(CacheName::Mesh, false);
    const auto source = store_.get_source(SourceKind::Mesh, id);
    if (!source) {
        return nullptr;
    }
    const MeshFormat format = api::mesh_format_from_string(source->extension);
    return remember(
        id,
        load_mesh_memory(as_bytes(source->bytes), "stored." + source->extension, format, limits_),
        format);
}

std::shared_ptr<const StoredMesh> MeshRegistry::remember(const std::string& id, Mesh mesh,
                                                         MeshFormat format) {
    auto shared = std::make_shared<const Mesh>(std::move(mesh));
    auto stored = std::make_shared<const StoredMesh>(
        StoredMesh{id, shared, api::mesh_to_json(*shared, id, format)});
    meshes_.put(id, stored, charge_of(*shared));
    return stored;
}

}  // namespace oer::server
