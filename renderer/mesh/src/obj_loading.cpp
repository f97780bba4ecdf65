// Wavefront OBJ through tinyobjloader (see oer/mesh_loading.hpp), from memory only: the
// material reader refuses every mtllib, so an OBJ is always drawn with the default Lambertian
// material (docs/design.md section 3). Faces are triangulated by tinyobjloader; one vertex is made
// per distinct (position, normal, texcoord) triple.
#include <tiny_obj_loader.h>

#include <cstdint>
#include <cstring>
#include <istream>
#include <limits>
#include <streambuf>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "mesh_errors.hpp"
#include "mesh_finishing.hpp"
#include "mesh_loaders.hpp"
#include "oer/core/error.hpp"

namespace oer::mesh_detail {

namespace {

constexpr std::size_t max_face_vertices = 255;

// An std::istream over the bytes, without a copy.
class MemoryBuffer : public std::streambuf {
  public:
    explicit MemoryBuffer(std::span<const std::byte> bytes) {
        char* begin = const_cast<char*>(reinterpret_cast<const char*>(bytes.data()));
        setg(begin, begin, begin + bytes.size());
    }
};

// Uploaded OBJ files cannot refer to other files: every mtllib is refused, and remembered.
class RefusingMaterialReader : public tinyobj::MaterialReader {
  public:
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>*,
                    std::map<std::string, int>*, std::string*, std::string*) override {
        refused.push_back(name);
        return false;
    }
    std::vector<std::string> refused;
};

bool is_command(std::string_view line, char command) {
    return line.size() >= 2 && line[0] == command && (line[1] == ' ' || line[1] == '\t');
}

// tinyobjloader reads a face's indices into an int without checking for overflow, so that
// "f 1 2 4294967297" would refer to vertex 1: every index (position, texture coordinate or
// normal, relative or not) must fit in 31 bits before it reads them.
void check_face_indices(std::string_view line, std::uint64_t line_number,
                        const std::string& asset) {
    constexpr std::uint64_t kLargestIndex = std::numeric_limits<std::int32_t>::max();
    std::uint64_t value = 0;
    bool in_number = false;
    for (const char c : line.substr(1)) {
        if (c >= '0' && c <= '9') {
            value = in_number ? value * 10 + std::uint64_t(c - '0') : std::uint64_t(c - '0');
            in_number = true;
            if (value > kLargestIndex) {
                fail(ErrorKind::InvalidInput, asset,
                     "line " + std::to_string(line_number) +
                         ": a face index beyond the largest an OBJ index may be (" +
                         std::to_string(kLargestIndex) + ")");
            }
        } else {
            in_number = false;
        }
    }
}

// Before tinyobjloader allocates anything: the number of positions and of triangles (a face
// of k vertices makes k - 2), against the limits, and the size of every face (its ear
// clipping is quadratic in it). Words are counted up to the end of the line, past a NUL that
// would end tinyobjloader's reading of it: an overestimate at worst.
void check_counts(std::span<const std::byte> bytes, const std::string& asset,
                  const MeshLimits& limits) {
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    std::uint64_t positions = 0;
    std::uint64_t triangles = 0;
    std::uint64_t line_number = 0;
    std::size_t start = 0;
    while (start < text.size()) {
        // Lines end as tinyobjloader ends them: at "\n", "\r" or "\r\n".
        std::size_t end = text.find_first_of("\r\n", start);
        if (end == std::string_view::npos) {
            end = text.size();
        }
        ++line_number;
        std::string_view line = text.substr(start, end - start);
        start = end + 1;
        if (end < text.size() && text[end] == '\r' && start < text.size() && text[start] == '\n') {
            ++start;
        }
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos) {
            continue;
        }
        line.remove_prefix(first);
        if (is_command(line, 'v')) {
            ++positions;
        } else if (is_command(line, 'f')) {
            std::uint64_t vertices = 0;
            bool in_token = false;
            for (char c : line.substr(1)) {
                const bool space = c == ' ' || c == '\t' || c == '\r' || c == '\0';
                if (!space && !in_token) {
                    ++vertices;
                }
                in_token = !space;
            }
            if (vertices > max_face_vertices) {
                fail(ErrorKind::Unsupported, asset,
                     "line " + std::to_string(line_number) + ": a face of " +
                         std::to_string(vertices) + " vertices (at most " +
                         std::to_string(max_face_vertices) + " are supported)");
            }
            triangles += vertices >= 3 ? vertices - 2 : 0;
            check_face_indices(line, line_number, asset);
        }
    }
    if (triangles > limits.max_triangles) {
        fail(ErrorKind::LimitExceeded, asset,
             std::to_string(triangles) + " triangles, more than the limit of " +
                 std::to_string(limits.max_triangles));
    }
    if (positions > limits.max_vertices) {
        fail(ErrorKind::LimitExceeded, asset,
             std::to_string(positions) + " vertex positions, more than the limit of " +
                 std::to_string(limits.max_vertices) + " vertices");
    }
}

struct Corner {
    int position;
    int normal;
    int texcoord;
    bool operator==(const Corner&) const = default;
};

struct CornerHash {
    std::size_t operator()(const Corner& c) const {
        std::uint64_t h = std::uint64_t(std::uint32_t(c.position));
        h = h * 0x9e3779b97f4a7c15ull ^ std::uint64_t(std::uint32_t(c.normal));
        h = h * 0x9e3779b97f4a7c15ull ^ std::uint64_t(std::uint32_t(c.texcoord));
        return std::size_t(h ^ (h >> 29));
    }
};

std::string index_problem(const char* what, int index, std::size_t count) {
    if (index < 0) {
        return std::string("refers to a ") + what +
               " before the first one (a relative index reaching too far back)";
    }
    return std::string("refers to ") + what + " " + std::to_string(std::int64_t(index) + 1) +
           ", out of range: the file has " + std::to_string(count) + " (OBJ counts from 1)";
}

Primitive build(const tinyobj::attrib_t& attrib, const tinyobj::shape_t& shape,
                const std::string& name, const std::string& asset, Mesh& mesh) {
    const std::size_t positions = attrib.vertices.size() / 3;
    const std::size_t normals = attrib.normals.size() / 3;
    const std::size_t texcoords = attrib.texcoords.size() / 2;
    const std::vector<tinyobj::index_t>& corners = shape.mesh.indices;
    if (corners.size() % 3 != 0) {
        fail(ErrorKind::Internal, asset, name + ": the faces were not triangulated");
    }
    bool all_normals = true;
    bool all_texcoords = true;
    bool any_texcoords = false;
    for (const tinyobj::index_t& corner : corners) {
        all_normals = all_normals && corner.normal_index >= 0;
        all_texcoords = all_texcoords && corner.texcoord_index >= 0;
        any_texcoords = any_texcoords || corner.texcoord_index >= 0;
    }
    if (any_texcoords && !all_texcoords) {
        mesh.warnings.push_back(name + ": texture coordinates on some corners only: all ignored");
    }
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const tinyobj::index_t& corner = corners[i];
        const std::string where = name + " triangle " + std::to_string(i / 3) + ": ";
        if (corner.vertex_index < 0 || std::size_t(corner.vertex_index) >= positions) {
            fail(ErrorKind::InvalidInput, asset,
                 where + index_problem("vertex", corner.vertex_index, positions));
        }
        if (all_normals && std::size_t(corner.normal_index) >= normals) {
            fail(ErrorKind::InvalidInput, asset,
                 where + index_problem("normal", corner.normal_index, normals));
        }
        if (all_texcoords && std::size_t(corner.texcoord_index) >= texcoords) {
            fail(ErrorKind::InvalidInput, asset,
                 where + index_problem("texture coordinate", corner.texcoord_index, texcoords));
        }
    }

    Primitive primitive;
    primitive.name = name;
    primitive.material = 0;
    std::unordered_map<Corner, std::uint32_t, CornerHash> vertex_of;
    vertex_of.reserve(corners.size());
    primitive.indices.reserve(corners.size());
    for (const tinyobj::index_t& c : corners) {
        const Corner key{c.vertex_index, all_normals ? c.normal_index : -1,
                         all_texcoords ? c.texcoord_index : -1};
        const auto [found, inserted] =
            vertex_of.try_emplace(key, std::uint32_t(primitive.positions.size()));
        if (inserted) {
            const auto p = std::size_t(key.position) * 3;
            primitive.positions.emplace_back(attrib.vertices[p], attrib.vertices[p + 1],
                                             attrib.vertices[p + 2]);
            if (all_normals) {
                const auto n = std::size_t(key.normal) * 3;
                primitive.normals.emplace_back(attrib.normals[n], attrib.normals[n + 1],
                                               attrib.normals[n + 2]);
            }
            if (all_texcoords) {
                const auto t = std::size_t(key.texcoord) * 2;
                primitive.texcoords.emplace_back(attrib.texcoords[t], attrib.texcoords[t + 1]);
            }
        }
        primitive.indices.push_back(found->second);
    }
    mesh.repairs.normals_renormalised += normalise_file_normals(primitive.normals);
    return primitive;
}

Material default_obj_material() {
    Material material;
    material.name = "default (OBJ)";
    material.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    material.metallic = 0.0f;
    material.roughness = 1.0f;
    material.model = ShadingModel::Lambertian;
    // OBJ has no face orientation to trust: both sides are seen and lit.
    material.double_sided = true;
    return material;
}

}  // namespace

Mesh load_obj(std::span<const std::byte> bytes, const std::string& name, const MeshLimits& limits) {
    check_counts(bytes, name, limits);

    MemoryBuffer buffer(bytes);
    std::istream stream(&buffer);
    RefusingMaterialReader materials_reader;
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn;
    std::string err;
    bool ok = false;
    try {
        ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, &materials_reader,
                              /*triangulate=*/true,
                              /*default_vcols_fallback=*/false);
    } catch (const std::bad_alloc&) {
        fail(ErrorKind::LimitExceeded, name, "out of memory while parsing the OBJ");
    } catch (const std::exception& error) {
        fail(ErrorKind::InvalidInput, name, std::string("not a valid OBJ file: ") + error.what());
    }
    if (!ok) {
        fail(ErrorKind::InvalidInput, name,
             "not a valid OBJ file: " +
                 (err.empty() ? std::string("(no reason given)") : one_line(err)));
    }
    if (warn.find("invalid vertex index") != std::string::npos) {
        // tinyobjloader drops such a quad or polygon instead of failing.
        fail(
            ErrorKind::InvalidInput, name,
            "a face refers to a vertex index out of range (tinyobjloader: " + one_line(warn) + ")");
    }

    Mesh mesh;
    mesh.materials.push_back(default_obj_material());
    for (const std::string& refused : materials_reader.refused) {
        mesh.warnings.push_back("mtllib '" + one_line(refused, 200) +
                                "' ignored: an uploaded OBJ cannot refer to other files; the "
                                "default material is used");
    }
    for (std::size_t s = 0; s < shapes.size(); ++s) {
        const tinyobj::shape_t& shape = shapes[s];
        const std::string shape_name = shape.name.empty()
                                           ? "shape " + std::to_string(s)
                                           : "shape '" + one_line(shape.name, 80) + "'";
        if (!shape.lines.indices.empty() || !shape.points.indices.empty()) {
            mesh.warnings.push_back(shape_name + ": lines and points ignored");
        }
        if (!shape.mesh.indices.empty()) {
            mesh.primitives.push_back(build(attrib, shape, shape_name, name, mesh));
        }
    }
    finish_mesh(mesh, name, limits);
    return mesh;
}

}  // namespace oer::mesh_detail
