#include "mesh_registry.hpp"

#include "oer/transfer/transfer_bake.hpp"

#include <set>
#include <span>

#include "oer/api/content_id.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/mesh/default_product.hpp"

namespace oer::server {

namespace {

// Memory that loading a mesh holds, per byte of its file, at most: measured 5.3 for a binary
// glTF (2CylinderEngine.glb, 1.8 MB: +9.7 MB peak resident) and 7.2 for OBJ text (glmark2's
// bunny.obj, 2.4 MB: +17 MB), the parsed document, the decoded arrays and the welded mesh.
// The JSON of a glTF is bounded in elements while it is parsed (checked_json.hpp), so a small
// file cannot claim more.
constexpr std::uint64_t kDecodeBytesPerUploadByte = 8;

// What a mesh holds in memory (and, roughly, on the GPU).
std::size_t charge_of(const Mesh& mesh) {
    std::size_t bytes = 0;
    for (const Primitive& primitive : mesh.primitives) {
        bytes += primitive.positions.size() * sizeof(glm::vec3) * 2 +
                 (primitive.texcoords.size() + primitive.texcoords1.size()) * sizeof(glm::vec2) +
                 primitive.colors.size() * sizeof(glm::vec4) +
                 primitive.indices.size() * sizeof(std::uint32_t);
    }
    for (const Texture& texture : mesh.textures) {
        bytes += texture.rgba.size();
    }
    return bytes;
}

MeshSummary summary_of(const Mesh& mesh) {
    MeshSummary summary{mesh.triangle_count, mesh.vertex_count, 0, charge_of(mesh),
                        object_bounce_vectors(mesh)};
    for (const Texture& texture : mesh.textures) {
        summary.texture_bytes += texture.rgba.size();
    }
    return summary;
}

std::string summary_record(const MeshSummary& summary) {
    return nlohmann::json{{"triangles", summary.triangles},
                          {"vertices", summary.vertices},
                          {"texture_bytes", summary.texture_bytes},
                          {"resident_bytes", summary.resident_bytes},
                          {"bounce_vectors", summary.bounce_vectors}}
        .dump();
}

// nullopt for a record that does not read as one (it is then made again from the mesh).
std::optional<MeshSummary> parse_summary_record(const std::string& text) {
    const nlohmann::json record = nlohmann::json::parse(text, nullptr, false);
    const auto count = [&](const char* name) -> std::optional<std::uint64_t> {
        if (!record.is_object() || !record.contains(name) ||
            !record.at(name).is_number_unsigned()) {
            return std::nullopt;
        }
        return record.at(name).get<std::uint64_t>();
    };
    const auto triangles = count("triangles");
    const auto vertices = count("vertices");
    const auto texture_bytes = count("texture_bytes");
    const auto resident_bytes = count("resident_bytes");
    const auto bounce_vectors = count("bounce_vectors");
    if (!triangles || !vertices || !texture_bytes || !resident_bytes || !bounce_vectors) {
        return std::nullopt;
    }
    return MeshSummary{*triangles, *vertices, *texture_bytes, *resident_bytes, *bounce_vectors};
}

}  // namespace

MeshRegistry::MeshRegistry(AssetStore& store, ServiceMetrics& metrics, UploadBudget& budget,
                           const MeshLimits& limits, std::size_t cache_bytes)
    : store_(store),
      metrics_(metrics),
      budget_(budget),
      limits_(limits),
      meshes_(metrics, CacheName::Mesh, cache_bytes) {
    auto mesh = std::make_shared<const Mesh>(make_default_product());
    const std::string id(api::kDefaultPresetId);
    meshes_.set_preset(
        std::make_shared<const StoredMesh>(StoredMesh{id, mesh, api::mesh_to_json(*mesh, id)}));
    summaries_.emplace(id, summary_of(*mesh));
}

MeshRegistry::Upload MeshRegistry::upload(std::string_view bytes, MeshFormat format,
                                          const std::string& file_name) {
    const std::string id = api::sha256_hex(bytes);
    return meshes_.upload(
        id,
        [&]() -> std::shared_ptr<const StoredMesh> {
            return store_.contains(SourceKind::Mesh, id) ? find(id) : nullptr;
        },
        [&] {
            // Loaded before it is stored, so that bytes that are not a mesh never enter the
            // store.
            const auto lease = budget_.acquire(kDecodeBytesPerUploadByte * bytes.size(),
                                               bytes.size(), "this mesh");
            Mesh mesh = load(bytes, file_name, format);
            store_.put_source(SourceKind::Mesh, bytes, api::to_string(format));
            return remember(id, std::move(mesh), format);
        });
}

std::shared_ptr<const StoredMesh> MeshRegistry::find(const std::string& id) {
    return meshes_.find(id, [&] { return read_stored(id); });
}

std::optional<MeshSummary> MeshRegistry::summary(const std::string& id) {
    {
        const std::lock_guard lock(summaries_mutex_);
        if (const auto found = summaries_.find(id); found != summaries_.end()) {
            return found->second;
        }
    }
    if (!api::is_content_id(id) || !store_.contains(SourceKind::Mesh, id)) {
        return std::nullopt;
    }
    if (const auto record = store_.get_derived(DerivedKind::MeshSummary, id)) {
        if (const auto parsed = parse_summary_record(*record)) {
            const std::lock_guard lock(summaries_mutex_);
            summaries_[id] = *parsed;
            return parsed;
        }
    }
    const auto stored = find(id);  // decodes it, which remembers its summary
    if (!stored) {
        return std::nullopt;
    }
    return summary_of(*stored->mesh);
}

std::shared_ptr<const StoredMesh> MeshRegistry::read_stored(const std::string& id) {
    const auto source = store_.get_source(SourceKind::Mesh, id);
    if (!source) {
        return nullptr;
    }
    const MeshFormat format = api::mesh_format_from_string(source->extension);
    return remember(id, load(source->bytes, "stored." + source->extension, format), format);
}

ListedPage MeshRegistry::list(std::string_view after, std::size_t limit) {
    return meshes_.guarded([&] {
        return listed_page(store_.list(SourceKind::Mesh, after, limit + 1), limit,
                           [&](const std::string& id) -> std::optional<ListedAsset> {
                               auto source = store_.info(SourceKind::Mesh, id);
                               if (!source) {
                                   return std::nullopt;
                               }
                               const auto stored = source->written;
                               return ListedAsset{id, id, std::move(source), stored};
                           });
    });
}

bool MeshRegistry::remove(const std::string& id) {
    if (!api::is_content_id(id)) {
        return false;
    }
    return meshes_.remove(id, [&] {
        const bool removed = store_.remove(SourceKind::Mesh, id);
        store_.remove(DerivedKind::MeshSummary, id);
        const std::lock_guard lock(summaries_mutex_);
        summaries_.erase(id);
        return removed;
    });
}

Mesh MeshRegistry::load(std::string_view bytes, const std::string& name, MeshFormat format) {
    Mesh mesh = load_mesh_memory(as_bytes(bytes), name, format, limits_);
    metrics_.meshes_loaded.increment();
    return mesh;
}

std::shared_ptr<const StoredMesh> MeshRegistry::remember(const std::string& id, Mesh mesh,
                                                         MeshFormat format) {
    auto shared = std::make_shared<const Mesh>(std::move(mesh));
    auto stored = std::make_shared<const StoredMesh>(
        StoredMesh{id, shared, api::mesh_to_json(*shared, id, format)});
    meshes_.remember(id, stored, charge_of(*shared));
    const MeshSummary summary = summary_of(*shared);
    bool known = false;
    {
        const std::lock_guard lock(summaries_mutex_);
        known = !summaries_.emplace(id, summary).second;
    }
    if (!known && !store_.get_derived(DerivedKind::MeshSummary, id)) {
        store_.put_derived_if_room(DerivedKind::MeshSummary, id, summary_record(summary));
    }
    return stored;
}

}  // namespace oer::server
