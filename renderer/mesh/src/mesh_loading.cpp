// Mesh loading (see oer/mesh_loading.hpp): the format from the name, the size check, the file
// read, and what every loader does last (mesh_finishing.hpp): normals, refinement, tangents,
// validation, bounds.
#include "oer/mesh/mesh_loading.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <system_error>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "mesh_errors.hpp"
#include "mesh_finishing.hpp"
#include "mesh_loaders.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/mesh_refinement.hpp"
#include "tangent_generation.hpp"

namespace oer {

namespace mesh_detail {

namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool finite(const glm::vec2& v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}

bool reads_uv_set_1(const Material& material) {
    return material.reads_uv_set(1);
}

std::string describe(const glm::vec3& v) {
    std::string text = "(";
    text += std::to_string(v.x);
    text += ", ";
    text += std::to_string(v.y);
    text += ", ";
    text += std::to_string(v.z);
    text += ")";
    return text;
}

// The angle between two edge vectors, robust for small and obtuse angles alike.
float angle_between(const glm::vec3& a, const glm::vec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

void check_primitive(const Primitive& primitive, std::size_t material_count,
                     std::size_t variant_count, const std::string& asset) {
    const std::string& p = primitive.name;
    const std::size_t n = primitive.positions.size();
    if (primitive.indices.size() % 3 != 0) {
        fail(ErrorKind::Internal, asset,
             p + ": " + std::to_string(primitive.indices.size()) +
                 " indices is not a whole number of triangles");
    }
    for (std::size_t i = 0; i < primitive.indices.size(); ++i) {
        if (primitive.indices[i] >= n) {
            fail(ErrorKind::InvalidInput, asset,
                 p + ": index " + std::to_string(primitive.indices[i]) + " out of range (" +
                     std::to_string(n) + " vertices)");
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!finite(primitive.positions[i])) {
            fail(ErrorKind::InvalidInput, asset,
                 p + ": vertex " + std::to_string(i) + " has a non-finite position " +
                     describe(primitive.positions[i]));
        }
    }
    if (!primitive.normals.empty() && primitive.normals.size() != n) {
        fail(ErrorKind::Internal, asset, p + ": normals and positions differ in number");
    }
    for (const auto& [set, texcoords] :
         {std::pair{"", &primitive.texcoords}, std::pair{" (TEXCOORD_1)", &primitive.texcoords1}}) {
        if (texcoords->empty()) {
            continue;
        }
        if (texcoords->size() != n) {
            fail(ErrorKind::Internal, asset,
                 p + ": texture coordinates" + set + " and positions differ in number");
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (!finite((*texcoords)[i])) {
                fail(ErrorKind::InvalidInput, asset,
                     p + ": vertex " + std::to_string(i) + " has non-finite texture coordinates" +
                         set);
            }
        }
    }
    if (!primitive.colors.empty() && primitive.colors.size() != n) {
        fail(ErrorKind::Internal, asset, p + ": colours and positions differ in number");
    }
    if (!primitive.tangents.empty()) {
        if (primitive.tangents.size() != n) {
            fail(ErrorKind::Internal, asset, p + ": tangents and positions differ in number");
        }
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec4& t = primitive.tangents[i];
            if (!finite(glm::vec3(t)) || std::abs(t.w) != 1.0f) {
                fail(ErrorKind::Internal, asset,
                     p + ": vertex " + std::to_string(i) +
                         " has a non-finite tangent or a bitangent sign other than +1 or -1");
            }
        }
    }
    if (!primitive.variant_materials.empty() &&
        primitive.variant_materials.size() != variant_count) {
        fail(ErrorKind::Internal, asset,
             p + ": materials for " + std::to_string(primitive.variant_materials.size()) +
                 " variants, not the mesh's " + std::to_string(variant_count));
    }
    for (const int material : primitive.materials_drawn()) {
        if (material < 0 || std::size_t(material) >= material_count) {
            fail(ErrorKind::Internal, asset,
                 p + ": material " + std::to_string(material) + " does not exist");
        }
    }
}

// Whether any material the primitive may be drawn with satisfies `predicate`.
template <typename Predicate>
bool any_material_drawn(const Mesh& mesh, const Primitive& primitive, Predicate predicate) {
    const std::vector<int> drawn = primitive.materials_drawn();
    return std::any_of(drawn.begin(), drawn.end(), [&](int material) {
        return predicate(mesh.materials[std::size_t(material)]);
    });
}

// Missing normals computed; zero or non-finite ones replaced by computed ones (counted).
void complete_normals(Primitive& primitive, MeshRepairs& repairs) {
    const bool missing = primitive.normals.empty();
    bool any_bad = missing;
    if (!missing) {
        for (const glm::vec3& normal : primitive.normals) {
            if (!finite(normal) || glm::dot(normal, normal) == 0.0f) {
                any_bad = true;
                break;
            }
        }
    }
    if (!any_bad) {
        return;
    }
    std::vector<glm::vec3> computed =
        angle_weighted_normals(primitive.positions, primitive.indices);
    for (glm::vec3& normal : computed) {
        if (glm::dot(normal, normal) == 0.0f) {
            normal = glm::vec3(0.0f, 1.0f, 0.0f);  // on no triangle of non-zero area
        }
    }
    if (missing) {
        primitive.normals = std::move(computed);
        return;
    }
    for (std::size_t i = 0; i < primitive.normals.size(); ++i) {
        glm::vec3& normal = primitive.normals[i];
        if (!finite(normal) || glm::dot(normal, normal) == 0.0f) {
            normal = computed[i];
            ++repairs.normals_replaced;
        }
    }
}

}  // namespace

std::vector<glm::vec3> angle_weighted_normals(std::span<const glm::vec3> positions,
                                              std::span<const std::uint32_t> indices) {
    std::vector<glm::vec3> sums(positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const std::uint32_t corner[3] = {indices[t], indices[t + 1], indices[t + 2]};
        const glm::vec3& a = positions[corner[0]];
        const glm::vec3& b = positions[corner[1]];
        const glm::vec3& c = positions[corner[2]];
        const glm::vec3 cross = glm::cross(b - a, c - a);
        const float length = glm::length(cross);
        if (!(length > 0.0f) || !std::isfinite(length)) {
            continue;  // zero area: no direction to contribute
        }
        const glm::vec3 unit = cross / length;
        sums[corner[0]] += angle_between(b - a, c - a) * unit;
        sums[corner[1]] += angle_between(c - b, a - b) * unit;
        sums[corner[2]] += angle_between(a - c, b - c) * unit;
    }
    for (glm::vec3& sum : sums) {
        const float length = glm::length(sum);
        sum = length > 0.0f && std::isfinite(length) ? sum / length : glm::vec3(0.0f);
    }
    return sums;
}

std::uint64_t normalise_file_normals(std::vector<glm::vec3>& normals) {
    std::uint64_t renormalised = 0;
    for (glm::vec3& normal : normals) {
        if (!finite(normal)) {
            normal = glm::vec3(0.0f);
            continue;
        }
        const float length = glm::length(normal);
        if (!(length > 1e-6f) || !std::isfinite(length)) {
            normal = glm::vec3(0.0f);
        } else if (std::abs(length - 1.0f) > 1e-3f) {
            normal /= length;
            ++renormalised;
        }
    }
    return renormalised;
}

void finish_mesh(Mesh& mesh, const std::string& asset, const MeshLimits& limits) {
    if (mesh.materials.empty()) {
        fail(ErrorKind::Internal, asset, "the mesh has no material");
    }
    std::erase_if(mesh.primitives, [](const Primitive& p) { return p.indices.empty(); });
    if (mesh.primitives.empty()) {
        fail(ErrorKind::InvalidInput, asset, "the asset has no triangles");
    }
    if (mesh.primitives.size() > limits.max_primitives) {
        fail(ErrorKind::LimitExceeded, asset,
             std::to_string(mesh.primitives.size()) + " primitives, more than the limit of " +
                 std::to_string(limits.max_primitives));
    }
    for (const Material& material : mesh.materials) {
        for (const auto& [property, reference] : material.texture_references()) {
            if (reference->texture < -1 || reference->texture >= int(mesh.textures.size())) {
                fail(ErrorKind::Internal, asset,
                     "material '" + material.name + "': its " + property + " " +
                         std::to_string(reference->texture) + " does not exist");
            }
        }
    }
    glm::vec3 low(std::numeric_limits<float>::infinity());
    glm::vec3 high(-std::numeric_limits<float>::infinity());
    for (Primitive& primitive : mesh.primitives) {
        check_primitive(primitive, mesh.materials.size(), mesh.variants.size(), asset);
        complete_normals(primitive, mesh.repairs);
        if (any_material_drawn(mesh, primitive,
                               [](const Material& material) { return material.uses_textures(); }) &&
            primitive.texcoords.empty()) {
            primitive.texcoords.assign(primitive.positions.size(), glm::vec2(0.0f));
        }
        if (any_material_drawn(mesh, primitive, reads_uv_set_1) && primitive.texcoords1.empty()) {
            primitive.texcoords1.assign(primitive.positions.size(), glm::vec2(0.0f));
        }
        for (const glm::vec3& position : primitive.positions) {
            low = glm::min(low, position);
            high = glm::max(high, position);
        }
    }
    // Midpoints lie within their ends' bounds, so the bounds hold for the refined mesh too.
    mesh.bounds = Bounds{low, high};
    // Every attribute is complete, so that midpoints interpolate them all; before tangents are
    // generated, so that MikkTSpace sees the final triangles.
    if (limits.max_refined_vertices > 0) {
        refine_mesh(mesh, transfer_edge_length(mesh.bounds), limits);
    }
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;
    std::uint64_t split_for_tangents = 0;
    for (Primitive& primitive : mesh.primitives) {
        // After baking (the loaders' transforms are applied) and before any level of detail.
        if (any_material_drawn(
                mesh, primitive,
                [](const Material& material) { return material.needs_tangents(); }) &&
            primitive.tangents.empty()) {
            split_for_tangents += generate_tangents(primitive, asset);
        }
        triangles += primitive.indices.size() / 3;
        vertices += primitive.positions.size();
    }
    if (triangles > limits.max_triangles) {
        fail(ErrorKind::LimitExceeded, asset,
             std::to_string(triangles) + " triangles, more than the limit of " +
                 std::to_string(limits.max_triangles));
    }
    if (vertices > limits.max_vertices) {
        fail(ErrorKind::LimitExceeded, asset,
             std::to_string(vertices) + " vertices, more than the limit of " +
                 std::to_string(limits.max_vertices) +
                 (split_for_tangents == 0 ? ""
                                          : " (" + std::to_string(split_for_tangents) +
                                                " of them copies made for their tangents)"));
    }
    mesh.triangle_count = triangles;
    mesh.vertex_count = vertices;
}

}  // namespace mesh_detail

MeshFormat mesh_format_from_name(const std::string& name) {
    std::string extension = std::filesystem::path(name).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (extension == ".glb") {
        return MeshFormat::Glb;
    }
    if (extension == ".gltf") {
        return MeshFormat::Gltf;
    }
    if (extension == ".obj") {
        return MeshFormat::Obj;
    }
    throw Error(ErrorKind::Unsupported,
                name + ": unsupported mesh format " +
                    (extension.empty() ? std::string("(no extension)") : "'" + extension + "'") +
                    ": expected .glb, .gltf (with data: URIs) or .obj");
}

namespace {

Mesh load_bytes(std::span<const std::byte> bytes, const std::string& name, MeshFormat format,
                const MeshLimits& limits, const std::optional<std::filesystem::path>& folder) {
    if (bytes.size() > limits.max_bytes) {
        mesh_detail::fail(ErrorKind::LimitExceeded, name,
                          std::to_string(bytes.size()) + " bytes, more than the limit of " +
                              std::to_string(limits.max_bytes));
    }
    if (bytes.empty()) {
        mesh_detail::fail(ErrorKind::InvalidInput, name, "the file is empty");
    }
    switch (format) {
        case MeshFormat::Glb:
            return mesh_detail::load_gltf(bytes, name, true, limits, folder);
        case MeshFormat::Gltf:
            return mesh_detail::load_gltf(bytes, name, false, limits, folder);
        case MeshFormat::Obj:
            return mesh_detail::load_obj(bytes, name, limits);
    }
    mesh_detail::fail(ErrorKind::Internal, name, "unknown mesh format");
}

}  // namespace

Mesh load_mesh_memory(std::span<const std::byte> bytes, const std::string& name, MeshFormat format,
                      const MeshLimits& limits) {
    return load_bytes(bytes, name, format, limits, std::nullopt);
}

Mesh load_mesh_file(const std::string& path, const MeshLimits& limits) {
    const MeshFormat format = mesh_format_from_name(path);
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (error) {
        mesh_detail::fail(ErrorKind::Io, path, "cannot read the file: " + error.message());
    }
    if (size > limits.max_bytes) {
        mesh_detail::fail(ErrorKind::LimitExceeded, path,
                          std::to_string(size) + " bytes, more than the limit of " +
                              std::to_string(limits.max_bytes));
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        mesh_detail::fail(ErrorKind::Io, path, "cannot open the file");
    }
    std::vector<std::byte> bytes(static_cast<std::size_t>(size));
    file.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    if (file.gcount() != std::streamsize(bytes.size())) {
        mesh_detail::fail(ErrorKind::Io, path, "the file could not be read whole");
    }
    // A local .gltf may name files beside it; the folder is resolved once, links followed, so
    // that every URI is judged against where its files really are.
    std::optional<std::filesystem::path> folder;
    if (format == MeshFormat::Gltf) {
        folder = std::filesystem::canonical(std::filesystem::absolute(path).parent_path(), error);
        if (error) {
            mesh_detail::fail(ErrorKind::Io, path, "cannot resolve its folder: " + error.message());
        }
    }
    return load_bytes(bytes, path, format, limits, folder);
}

}  // namespace oer
