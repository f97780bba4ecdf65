#pragma once
// What fuzz_gltf and fuzz_obj share: a mesh upload as the service reads it
// (server/src/mesh_registry.cpp): oer::load_mesh_memory at the service's default limits, then
// the description the service answers with (oer::api::mesh_to_json, serialised).
//
// Checked beyond the documented refusals: the loaded mesh keeps its limits, and the resident set
// grows while loading by at most what the service lets one upload of these bytes cost,
// max(64 MiB, 200 x its size) at the default expansion (server/src/upload_budget.hpp).
#include <cstddef>
#include <string>

#include "fuzz_support.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::fuzz {

// The limits the service reads meshes with at its default configuration (server/src/service.cpp).
inline MeshLimits service_mesh_limits() {
    const server::ServiceConfig config;
    MeshLimits limits;
    limits.max_bytes = config.max_upload_bytes;
    limits.max_triangles = config.max_triangles;
    return limits;
}

inline void load_uploaded_mesh(std::span<const std::byte> bytes, MeshFormat format) {
    const MeshLimits limits = service_mesh_limits();
    const std::string name = "upload." + api::to_string(format);
    ResidentGrowth growth;
    const Mesh mesh = load_mesh_memory(bytes, name, format, limits);
    const std::uint64_t grown = growth.bytes();
    if (mesh.triangle_count > limits.max_triangles || mesh.vertex_count > limits.max_vertices ||
        mesh.primitives.size() > limits.max_primitives) {
        finding("a mesh over the limits was loaded: " + std::to_string(mesh.triangle_count) +
                " triangles, " + std::to_string(mesh.vertex_count) + " vertices");
    }
    if (grown > upload_expansion_bound(bytes.size())) {
        finding("loading " + std::to_string(bytes.size()) + " bytes (" +
                std::to_string(mesh.triangle_count) + " triangles, " +
                std::to_string(mesh.vertex_count) + " vertices) grew the resident set by " +
                std::to_string(grown) + " bytes, over the upload's bound of " +
                std::to_string(upload_expansion_bound(bytes.size())));
    }
    const std::string described = api::mesh_to_json(mesh, "fuzz", format).dump();
    if (described.empty()) {
        finding("an empty mesh description");
    }
}

}  // namespace oer::fuzz
