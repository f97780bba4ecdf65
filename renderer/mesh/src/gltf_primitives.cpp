// One glTF primitive's geometry, read and checked (see gltf_primitives.hpp).
#include "gltf_primitives.hpp"

#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

const char* mode_name(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS:
            return "POINTS";
        case TINYGLTF_MODE_LINE:
            return "LINES";
        case TINYGLTF_MODE_LINE_LOOP:
            return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP:
            return "LINE_STRIP";
        case TINYGLTF_MODE_TRIANGLES:
            return "TRIANGLES";
        case TINYGLTF_MODE_TRIANGLE_STRIP:
            return "TRIANGLE_STRIP";
        case TINYGLTF_MODE_TRIANGLE_FAN:
            return "TRIANGLE_FAN";
        default:
            return nullptr;
    }
}

void check_triangle_mode(int mode, const std::string& name, const std::string& asset) {
    const char* text = mode_name(mode);
    if (text == nullptr) {
        fail(ErrorKind::InvalidInput, asset, name + ": unknown mode " + std::to_string(mode));
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        fail(ErrorKind::Unsupported, asset,
             name + ": mode " + text + " is not supported (only triangles)");
    }
}

// A strip or a fan as a list, in the order of the glTF 2.0 specification (Meshes), which keeps
// every triangle's winding: strip triangle i is (i, i + 1 + i % 2, i + 2 - i % 2), fan
// triangle i is (i + 1, i + 2, 0).
std::vector<std::uint32_t> to_triangle_list(int mode, const std::vector<std::uint32_t>& in) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        return in;
    }
    std::vector<std::uint32_t> out;
    if (in.size() < 3) {
        return out;
    }
    out.reserve((in.size() - 2) * 3);
    for (std::size_t i = 0; i + 2 < in.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            const std::size_t odd = i % 2;
            out.insert(out.end(), {in[i], in[i + 1 + odd], in[i + 2 - odd]});
        } else {
            out.insert(out.end(), {in[i + 1], in[i + 2], in[0]});
        }
    }
    return out;
}

// The most indices `triangle_budget` triangles can take: a strip of t triangles has t + 2
// indices; no overflow for any budget.
std::uint64_t index_budget_of(std::uint64_t triangle_budget) {
    return triangle_budget > (std::numeric_limits<std::uint64_t>::max() - 2) / 3
               ? std::numeric_limits<std::uint64_t>::max()
               : triangle_budget * 3 + 2;
}

}  // namespace

std::uint64_t triangles_of(int mode, std::uint64_t count) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        return count / 3;
    }
    return count >= 3 ? count - 2 : 0;
}

Primitive PrimitiveReader::read(const tinygltf::Primitive& source, const std::string& name,
                                std::uint64_t vertex_budget) {
    check_triangle_mode(source.mode, name, asset_);
    Primitive primitive;
    primitive.name = name;
    read_attributes(source, name, vertex_budget, primitive);
    const std::size_t n = primitive.positions.size();
    const std::vector<std::uint32_t> indices = read_indices(source, name, n);
    const std::uint64_t triangles = triangles_of(source.mode, indices.size());
    check_positions_finite(primitive, name);
    primitive.indices = to_triangle_list(source.mode, indices);
    triangles_ += triangles;
    vertices_ += n;
    return primitive;
}

void PrimitiveReader::read_attributes(const tinygltf::Primitive& source, const std::string& name,
                                      std::uint64_t vertex_budget, Primitive& primitive) const {
    const auto position = source.attributes.find("POSITION");
    if (position == source.attributes.end()) {
        fail(ErrorKind::InvalidInput, asset_, name + ": no POSITION attribute");
    }
    primitive.positions = accessors_.vec3(position->second, name + ": POSITION", kPositionFormat,
                                          vertex_budget, "vertices");
    const std::size_t n = primitive.positions.size();
    const auto check_count = [&](std::size_t count, const char* attribute) {
        if (count != n) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": " + attribute + " has " + std::to_string(count) +
                     " elements, POSITION " + std::to_string(n));
        }
    };
    if (const auto normal = source.attributes.find("NORMAL"); normal != source.attributes.end()) {
        primitive.normals = accessors_.vec3(normal->second, name + ": NORMAL", kNormalFormat,
                                            vertex_budget, "vertices");
        check_count(primitive.normals.size(), "NORMAL");
        if (accessors_.quantized(normal->second)) {
            // Quantized normals are unit only to their precision (KHR_mesh_quantization):
            // made unit here, not counted as the file's repairs.
            for (glm::vec3& n : primitive.normals) {
                const float length = glm::length(n);
                n = length > 0.0f ? n / length : n;
            }
        }
    }
    if (const auto texcoord = source.attributes.find("TEXCOORD_0");
        texcoord != source.attributes.end()) {
        primitive.texcoords = accessors_.vec2(texcoord->second, name + ": TEXCOORD_0",
                                              kTexcoordFormat, vertex_budget, "vertices");
        check_count(primitive.texcoords.size(), "TEXCOORD_0");
    }
    if (const auto color = source.attributes.find("COLOR_0"); color != source.attributes.end()) {
        primitive.colors = read_colors(color->second, name, vertex_budget);
        check_count(primitive.colors.size(), "COLOR_0");
    }
}

// COLOR_0 (glTF 2.0 section 3.7.2.1): linear RGB (alpha 1) or RGBA, each component finite and
// clamped to [0, 1] (a float colour may stray; normalized integers cannot).
std::vector<glm::vec4> PrimitiveReader::read_colors(int accessor, const std::string& name,
                                                    std::uint64_t vertex_budget) const {
    const std::string what = name + ": COLOR_0";
    std::vector<glm::vec4> colors;
    if (accessor >= 0 && std::size_t(accessor) < model_.accessors.size() &&
        model_.accessors[std::size_t(accessor)].type == TINYGLTF_TYPE_VEC3) {
        for (const glm::vec3& rgb :
             accessors_.vec3(accessor, what, kColor3Format, vertex_budget, "vertices")) {
            colors.emplace_back(rgb, 1.0f);
        }
    } else {
        colors = accessors_.vec4(accessor, what, kColor4Format, vertex_budget, "vertices");
    }
    for (std::size_t i = 0; i < colors.size(); ++i) {
        glm::vec4& c = colors[i];
        if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b) ||
            !std::isfinite(c.a)) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": vertex " + std::to_string(i) + " has a non-finite COLOR_0");
        }
        c = glm::clamp(c, glm::vec4(0.0f), glm::vec4(1.0f));
    }
    return colors;
}

// The file's indices (or 0 to n - 1 where it has none), a multiple of 3 for TRIANGLES, each
// below `vertex_count`, within the limit on triangles.
std::vector<std::uint32_t> PrimitiveReader::read_indices(const tinygltf::Primitive& source,
                                                         const std::string& name,
                                                         std::size_t vertex_count) const {
    const std::uint64_t triangle_budget = limits_.max_triangles - triangles_;
    std::vector<std::uint32_t> indices;
    if (source.indices >= 0) {
        indices = accessors_.indices(source.indices, name + ": indices",
                                     index_budget_of(triangle_budget), "triangles");
    } else {
        indices.resize(vertex_count);
        for (std::size_t i = 0; i < vertex_count; ++i) {
            indices[i] = std::uint32_t(i);
        }
    }
    if (source.mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": " + (source.indices >= 0 ? "index" : "vertex") + " count " +
                 std::to_string(indices.size()) + " is not a multiple of 3 (mode TRIANGLES)");
    }
    if (triangles_of(source.mode, indices.size()) > triangle_budget) {
        fail(ErrorKind::LimitExceeded, asset_,
             name + ": more than the limit of " + std::to_string(limits_.max_triangles) +
                 " triangles");
    }
    for (std::uint32_t index : indices) {
        if (index >= vertex_count) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": index " + std::to_string(index) + " out of range (" +
                     std::to_string(vertex_count) + " vertices)");
        }
    }
    return indices;
}

void PrimitiveReader::check_positions_finite(const Primitive& primitive,
                                             const std::string& name) const {
    for (std::size_t i = 0; i < primitive.positions.size(); ++i) {
        const glm::vec3& p = primitive.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": vertex " + std::to_string(i) + " has a non-finite position (" +
                     std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                     ")");
        }
    }
}

std::vector<glm::vec2> PrimitiveReader::texcoords1(const tinygltf::Primitive& source,
                                                   const std::string& name,
                                                   std::size_t vertex_count,
                                                   std::uint64_t vertex_budget) const {
    const auto texcoord = source.attributes.find("TEXCOORD_1");
    if (texcoord == source.attributes.end()) {
        return {};
    }
    std::vector<glm::vec2> texcoords = accessors_.vec2(texcoord->second, name + ": TEXCOORD_1",
                                                       kTexcoordFormat, vertex_budget, "vertices");
    if (texcoords.size() != vertex_count) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": TEXCOORD_1 has " + std::to_string(texcoords.size()) +
                 " elements, POSITION " + std::to_string(vertex_count));
    }
    return texcoords;
}

std::vector<glm::vec4> PrimitiveReader::tangents(int accessor, const std::string& name,
                                                 std::size_t vertex_count,
                                                 std::uint64_t vertex_budget) const {
    std::vector<glm::vec4> tangents =
        accessors_.vec4(accessor, name + ": TANGENT", kTangentFormat, vertex_budget, "vertices");
    if (tangents.size() != vertex_count) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": TANGENT has " + std::to_string(tangents.size()) + " elements, POSITION " +
                 std::to_string(vertex_count));
    }
    for (std::size_t i = 0; i < vertex_count; ++i) {
        glm::vec4& t = tangents[i];
        const std::string vertex = name + ": vertex " + std::to_string(i);
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) ||
            !std::isfinite(t.w)) {
            fail(ErrorKind::InvalidInput, asset_, vertex + " has a non-finite TANGENT");
        }
        const float length = glm::length(glm::vec3(t));
        if (!(length > 1e-6f) || !std::isfinite(length)) {
            fail(ErrorKind::InvalidInput, asset_, vertex + " has a zero-length TANGENT");
        }
        if (std::abs(std::abs(t.w) - 1.0f) > 1e-3f) {
            fail(ErrorKind::InvalidInput, asset_,
                 vertex + " has TANGENT w = " + number_text(t.w) +
                     ", not +1 or -1 (the bitangent's sign)");
        }
        t = glm::vec4(glm::vec3(t) / length, t.w < 0.0f ? -1.0f : 1.0f);
    }
    return tangents;
}

}  // namespace oer::mesh_detail
