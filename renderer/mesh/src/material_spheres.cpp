#include "oer/mesh/material_spheres.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "oer/core/error.hpp"

namespace oer {

namespace {

// One UV sphere about the origin: positions, unit normals and uv (u around +Y from +X, v from
// the north pole), indices of its triangles.
struct SphereGeometry {
    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<float> texcoords;
    std::vector<std::uint32_t> indices;
};

SphereGeometry uv_sphere(float radius, int rings) {
    SphereGeometry sphere;
    const int segments = 2 * rings;
    for (int i = 0; i <= rings; ++i) {
        const double theta = std::numbers::pi * i / rings;
        for (int j = 0; j <= segments; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / segments;
            const double n[3] = {std::sin(theta) * std::cos(phi), std::cos(theta),
                                 -std::sin(theta) * std::sin(phi)};
            for (const double c : n) {
                sphere.normals.push_back(float(c));
                sphere.positions.push_back(float(c * radius));
            }
            sphere.texcoords.push_back(float(j) / float(segments));
            sphere.texcoords.push_back(float(i) / float(rings));
        }
    }
    const auto vertex = [segments](int i, int j) { return std::uint32_t(i * (segments + 1) + j); };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < segments; ++j) {
            // Counter-clockwise seen from outside (glTF's front faces).
            if (i > 0) {
                sphere.indices.insert(sphere.indices.end(),
                                      {vertex(i, j), vertex(i + 1, j), vertex(i, j + 1)});
            }
            if (i + 1 < rings) {
                sphere.indices.insert(sphere.indices.end(),
                                      {vertex(i, j + 1), vertex(i + 1, j), vertex(i + 1, j + 1)});
            }
        }
    }
    return sphere;
}

template <typename T>
void append_bytes(std::vector<std::byte>& out, const std::vector<T>& values) {
    const std::size_t offset = out.size();
    out.resize(offset + values.size() * sizeof(T));
    std::memcpy(out.data() + offset, values.data(), values.size() * sizeof(T));
}

void append_u32(std::vector<std::byte>& out, std::uint32_t value) {
    append_bytes(out, std::vector<std::uint32_t>{value});
}

std::string roughness_label(double roughness) {
    std::string text = std::to_string(roughness);
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') {
        text.pop_back();
    }
    return text;
}

}  // namespace

std::vector<std::byte> material_spheres_glb(const MaterialSpheresOptions& given) {
    MaterialSpheresOptions options = given;
    if (options.roughness.empty()) {
        if (options.columns < 2 || options.columns > 16) {
            throw Error(ErrorKind::InvalidInput,
                        "material spheres: columns must be in [2, 16], not " +
                            std::to_string(options.columns));
        }
        for (int column = 0; column < options.columns; ++column) {
            options.roughness.push_back(float(column) / float(options.columns - 1));
        }
    }
    if (options.roughness.size() < 2 || options.roughness.size() > 16) {
        throw Error(ErrorKind::InvalidInput, "material spheres: 2 to 16 roughness values, not " +
                                                 std::to_string(options.roughness.size()));
    }
    for (const float roughness : options.roughness) {
        if (!(roughness >= 0.0f && roughness <= 1.0f)) {
            throw Error(ErrorKind::InvalidInput, "material spheres: a roughness of " +
                                                     std::to_string(roughness) +
                                                     " is outside [0, 1]");
        }
    }
    options.columns = int(options.roughness.size());
    if (options.rings < 4 || options.rings > 256) {
        throw Error(ErrorKind::InvalidInput, "material spheres: rings must be in [4, 256], not " +
                                                 std::to_string(options.rings));
    }
    const SphereGeometry sphere = uv_sphere(kMaterialSphereRadius, options.rings);
    // The buffer: positions, normals, texcoords, indices (all 4-byte aligned).
    std::vector<std::byte> binary;
    append_bytes(binary, sphere.positions);
    append_bytes(binary, sphere.normals);
    append_bytes(binary, sphere.texcoords);
    append_bytes(binary, sphere.indices);
    const std::size_t vertex_count = sphere.positions.size() / 3;
    const std::size_t positions_bytes = sphere.positions.size() * sizeof(float);
    const std::size_t normals_bytes = sphere.normals.size() * sizeof(float);
    const std::size_t texcoords_bytes = sphere.texcoords.size() * sizeof(float);
    const std::size_t indices_bytes = sphere.indices.size() * sizeof(std::uint32_t);

    using Json = nlohmann::json;
    const float r = kMaterialSphereRadius;
    Json gltf = {
        {"asset", {{"version", "2.0"}, {"generator", "oer material_spheres"}}},
        {"buffers", Json::array({{{"byteLength", binary.size()}}})},
        {"bufferViews",
         Json::array({
             {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions_bytes}},
             {{"buffer", 0}, {"byteOffset", positions_bytes}, {"byteLength", normals_bytes}},
             {{"buffer", 0},
              {"byteOffset", positions_bytes + normals_bytes},
              {"byteLength", texcoords_bytes}},
             {{"buffer", 0},
              {"byteOffset", positions_bytes + normals_bytes + texcoords_bytes},
              {"byteLength", indices_bytes}},
         })},
        {"accessors", Json::array({
                          {{"bufferView", 0},
                           {"componentType", 5126},
                           {"count", vertex_count},
                           {"type", "VEC3"},
                           {"min", {-r, -r, -r}},
                           {"max", {r, r, r}}},
                          {{"bufferView", 1},
                           {"componentType", 5126},
                           {"count", vertex_count},
                           {"type", "VEC3"}},
                          {{"bufferView", 2},
                           {"componentType", 5126},
                           {"count", vertex_count},
                           {"type", "VEC2"}},
                          {{"bufferView", 3},
                           {"componentType", 5125},
                           {"count", sphere.indices.size()},
                           {"type", "SCALAR"}},
                      })},
    };
    Json materials = Json::array();
    Json meshes = Json::array();
    Json nodes = Json::array();
    Json scene_nodes = Json::array();
    for (int row = 0; row < 2; ++row) {
        const bool metal = row == 1;
        const glm::vec3 color = metal ? options.metal_color : options.dielectric_color;
        for (int column = 0; column < options.columns; ++column) {
            const double roughness = options.roughness[std::size_t(column)];
            const int index = int(materials.size());
            materials.push_back({{"name", std::string(metal ? "metal" : "dielectric") +
                                              " roughness " + roughness_label(roughness)},
                                 {"pbrMetallicRoughness",
                                  {{"baseColorFactor", {color.r, color.g, color.b, 1.0}},
                                   {"metallicFactor", metal ? 1.0 : 0.0},
                                   {"roughnessFactor", roughness}}}});
            meshes.push_back(
                {{"name", materials.back()["name"]},
                 {"primitives",
                  Json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                                {"indices", 3},
                                {"material", index}}})}});
            const double x = (column - (options.columns - 1) / 2.0) * kMaterialSphereSpacing;
            const double y = (1 - row) * kMaterialSphereSpacing + r;
            nodes.push_back({{"mesh", index}, {"translation", {x, y, 0.0}}});
            scene_nodes.push_back(index);
        }
    }
    gltf["materials"] = materials;
    gltf["meshes"] = meshes;
    gltf["nodes"] = nodes;
    gltf["scenes"] = Json::array({{{"nodes", scene_nodes}}});
    gltf["scene"] = 0;

    // GLB container (glTF 2.0 specification, section 4.4): header, JSON chunk padded with
    // spaces, BIN chunk padded with zeros, each chunk 4-byte aligned.
    std::string json_text = gltf.dump();
    json_text.append((4 - json_text.size() % 4) % 4, ' ');
    binary.resize(binary.size() + (4 - binary.size() % 4) % 4, std::byte{0});
    std::vector<std::byte> glb;
    append_u32(glb, 0x46546C67u);  // "glTF"
    append_u32(glb, 2u);
    append_u32(glb, std::uint32_t(12 + 8 + json_text.size() + 8 + binary.size()));
    append_u32(glb, std::uint32_t(json_text.size()));
    append_u32(glb, 0x4E4F534Au);  // "JSON"
    const std::size_t json_offset = glb.size();
    glb.resize(json_offset + json_text.size());
    std::memcpy(glb.data() + json_offset, json_text.data(), json_text.size());
    append_u32(glb, std::uint32_t(binary.size()));
    append_u32(glb, 0x004E4942u);  // "BIN\0"
    glb.insert(glb.end(), binary.begin(), binary.end());
    return glb;
}

}  // namespace oer
