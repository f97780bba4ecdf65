#pragma once
// glTF assets for the mesh tests: helpers to load bytes and to expect errors, the invariants
// every oer::Mesh keeps, a builder of glTF assets in memory (one buffer, embedded as a data: URI
// or as a .glb's BIN chunk), tiny PNGs, and the samples of Debian's assimp-testmodels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "base64.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_testing {

namespace fs = std::filesystem;
using nlohmann::json;
using oer::testing::base64;

// ---------------------------------------------------------------------------------------------
// Helpers

inline std::vector<std::uint8_t> read_bytes(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(file), {});
}

inline std::span<const std::byte> as_bytes(const std::string& text) {
    return {reinterpret_cast<const std::byte*>(text.data()), text.size()};
}

inline std::span<const std::byte> as_bytes(const std::vector<std::uint8_t>& data) {
    return {reinterpret_cast<const std::byte*>(data.data()), data.size()};
}

// The default limits with refinement off (mesh_refinement.hpp): the triangles as the loader
// assembles them, for the tests of that assembly; every other load is refined, and
// mesh_refinement_test.cpp tests the refinement.
inline const MeshLimits kUnrefined{.max_refined_vertices = 0};

inline Mesh load_gltf_text(const std::string& text, const MeshLimits& limits = {}) {
    return load_mesh_memory(as_bytes(text), "test.gltf", MeshFormat::Gltf, limits);
}

inline Mesh load_obj_text(const std::string& text, const MeshLimits& limits = {}) {
    return load_mesh_memory(as_bytes(text), "test.obj", MeshFormat::Obj, limits);
}

// Runs `load`, expecting an oer::Error of `kind` whose message contains every one of `parts`.
inline void expect_error(const std::function<void()>& load, ErrorKind kind,
                         const std::vector<std::string>& parts) {
    try {
        load();
        ADD_FAILURE() << "no error; expected one containing '" << parts.front() << "'";
    } catch (const Error& error) {
        const std::string message = error.what();
        EXPECT_EQ(int(error.kind()), int(kind)) << message;
        for (const std::string& part : parts) {
            EXPECT_NE(message.find(part), std::string::npos)
                << "message '" << message << "' lacks '" << part << "'";
        }
    }
}

inline glm::vec3 geometric_normal(const Primitive& p, std::size_t triangle) {
    const glm::vec3& a = p.positions[p.indices[3 * triangle]];
    const glm::vec3& b = p.positions[p.indices[3 * triangle + 1]];
    const glm::vec3& c = p.positions[p.indices[3 * triangle + 2]];
    return glm::cross(b - a, c - a);
}

// Every invariant oer::Mesh promises, and bounds and counts equal to a recomputation.
inline void expect_valid(const Mesh& mesh) {
    ASSERT_FALSE(mesh.primitives.empty());
    ASSERT_FALSE(mesh.materials.empty());
    glm::vec3 low(std::numeric_limits<float>::infinity());
    glm::vec3 high(-std::numeric_limits<float>::infinity());
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;
    for (const Primitive& p : mesh.primitives) {
        ASSERT_EQ(p.normals.size(), p.positions.size()) << p.name;
        ASSERT_TRUE(p.texcoords.empty() || p.texcoords.size() == p.positions.size()) << p.name;
        ASSERT_TRUE(p.texcoords1.empty() || p.texcoords1.size() == p.positions.size()) << p.name;
        ASSERT_TRUE(p.colors.empty() || p.colors.size() == p.positions.size()) << p.name;
        ASSERT_EQ(p.indices.size() % 3, 0u) << p.name;
        ASSERT_GE(p.material, 0);
        ASSERT_LT(std::size_t(p.material), mesh.materials.size());
        for (std::uint32_t index : p.indices) {
            ASSERT_LT(index, p.positions.size()) << p.name;
        }
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            ASSERT_TRUE(std::isfinite(p.positions[i].x) && std::isfinite(p.positions[i].y) &&
                        std::isfinite(p.positions[i].z));
            ASSERT_NEAR(glm::length(p.normals[i]), 1.0f, 1e-4f) << p.name << " vertex " << i;
            low = glm::min(low, p.positions[i]);
            high = glm::max(high, p.positions[i]);
        }
        triangles += p.indices.size() / 3;
        vertices += p.positions.size();
    }
    EXPECT_EQ(mesh.triangle_count, triangles);
    EXPECT_EQ(mesh.vertex_count, vertices);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(mesh.bounds.min[k], low[k]);
        EXPECT_EQ(mesh.bounds.max[k], high[k]);
    }
}

// ---------------------------------------------------------------------------------------------
// A glTF asset built in memory: one buffer (embedded as a data: URI, or as a .glb BIN chunk),
// bufferViews, accessors, meshes and nodes appended by the test.

constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;

class GltfBuilder {
  public:
    GltfBuilder() {
        doc["asset"] = {{"version", "2.0"}};
        doc["bufferViews"] = json::array();
        doc["accessors"] = json::array();
        doc["meshes"] = json::array();
        doc["nodes"] = json::array();
    }

    int view(const void* data, std::size_t bytes, int stride = 0) {
        while (bin.size() % 4 != 0) {
            bin.push_back(0);
        }
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride != 0) {
            v["byteStride"] = stride;
        }
        const auto* p = static_cast<const std::uint8_t*>(data);
        bin.insert(bin.end(), p, p + bytes);
        doc["bufferViews"].push_back(v);
        return int(doc["bufferViews"].size()) - 1;
    }

    int accessor(int view, int component_type, std::size_t count, const std::string& type,
                 std::size_t byte_offset = 0) {
        doc["accessors"].push_back({{"bufferView", view},
                                    {"componentType", component_type},
                                    {"count", count},
                                    {"type", type},
                                    {"byteOffset", byte_offset}});
        return int(doc["accessors"].size()) - 1;
    }

    int positions(const std::vector<glm::vec3>& p) {
        return accessor(view(p.data(), p.size() * sizeof(glm::vec3)), kFloat, p.size(), "VEC3");
    }

    template <typename T>
    int indices(const std::vector<T>& i, int component_type) {
        return accessor(view(i.data(), i.size() * sizeof(T)), component_type, i.size(), "SCALAR");
    }

    int mesh(const json& primitives, const std::string& name = "") {
        json m = {{"primitives", primitives}};
        if (!name.empty()) {
            m["name"] = name;
        }
        doc["meshes"].push_back(m);
        return int(doc["meshes"].size()) - 1;
    }

    int node(const json& n) {
        doc["nodes"].push_back(n);
        return int(doc["nodes"].size()) - 1;
    }

    // The .gltf text, with the buffer as a data: URI; scene 0 lists `roots` (default: node 0).
    std::string gltf(std::vector<int> roots = {0}) {
        json d = with_scene(roots);
        d["buffers"] = {{{"byteLength", bin.size()},
                         {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
        for (const json& buffer : extra_buffers) {
            d["buffers"].push_back(buffer);
        }
        return d.dump();
    }

    // The same asset as a .glb.
    std::vector<std::uint8_t> glb(std::vector<int> roots = {0}) {
        json d = with_scene(roots);
        d["buffers"] = {{{"byteLength", bin.size()}}};
        for (const json& buffer : extra_buffers) {
            d["buffers"].push_back(buffer);
        }
        std::string text = d.dump();
        while (text.size() % 4 != 0) {
            text += ' ';
        }
        std::vector<std::uint8_t> body = bin;
        while (body.size() % 4 != 0) {
            body.push_back(0);
        }
        std::vector<std::uint8_t> out;
        auto u32 = [&out](std::uint32_t v) {
            for (int i = 0; i < 4; ++i) {
                out.push_back(std::uint8_t(v >> (8 * i)));
            }
        };
        out.insert(out.end(), {'g', 'l', 'T', 'F'});
        u32(2);
        u32(std::uint32_t(12 + 8 + text.size() + 8 + body.size()));
        u32(std::uint32_t(text.size()));
        out.insert(out.end(), {'J', 'S', 'O', 'N'});
        out.insert(out.end(), text.begin(), text.end());
        u32(std::uint32_t(body.size()));
        out.insert(out.end(), {'B', 'I', 'N', 0});
        out.insert(out.end(), body.begin(), body.end());
        return out;
    }

    json doc;
    std::vector<std::uint8_t> bin;
    // Buffers after buffer 0 (the one `bin` fills), as JSON: EXT_meshopt_compression's fallback
    // buffers, for example.
    std::vector<json> extra_buffers;

  private:
    json with_scene(const std::vector<int>& roots) const {
        json d = doc;
        if (!d.contains("scenes")) {
            d["scenes"] = {{{"nodes", roots}}};
            d["scene"] = 0;
        }
        return d;
    }
};

// One triangle in the xy plane, counter-clockwise seen from +z.
inline const std::vector<glm::vec3> kTriangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// A single-primitive asset: `primitive` is completed with POSITION `positions`.
inline std::string single_primitive(const std::vector<glm::vec3>& positions, json primitive,
                                    const std::string& mesh_name = "M") {
    GltfBuilder b;
    primitive["attributes"]["POSITION"] = b.positions(positions);
    b.mesh(json::array({primitive}), mesh_name);
    b.node({{"mesh", 0}});
    return b.gltf();
}

// A product of two parts with KHR_materials_variants: a body (a box over x in [-0.9, -0.1]) and
// a stand (a box over x in [0.1, 0.9]), both on y = 0, in materials "Stand" (0, grey) and
// "Body" (1, white); variants "Red" and "Blue" draw the body in materials 2 (red) and 3
// (blue), "Unchanged" maps nothing. With `baked_body` the same asset without variants, its body
// drawn in that material: what a variant must look like. Primitive 0 is the body's.
inline GltfBuilder variants_product(std::optional<int> baked_body = std::nullopt) {
    GltfBuilder b;
    const auto box = [&b](float x0, float x1, float height) {
        const glm::vec3 low(x0, 0.0f, -0.4f), high(x1, height, 0.4f);
        std::vector<glm::vec3> positions, normals;
        std::vector<std::uint32_t> indices;
        for (int axis = 0; axis < 3; ++axis) {
            for (const float side : {-1.0f, 1.0f}) {
                glm::vec3 normal(0.0f);
                normal[axis] = side;
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                const auto first = std::uint32_t(positions.size());
                for (const auto& [du, dv] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
                    glm::vec3 corner;
                    corner[axis] = side < 0.0f ? low[axis] : high[axis];
                    corner[u] = du == 0 ? low[u] : high[u];
                    corner[v] = dv == 0 ? low[v] : high[v];
                    positions.push_back(corner);
                    normals.push_back(normal);
                }
                // Counter-clockwise seen from outside: u x v is +axis.
                if (side > 0.0f) {
                    indices.insert(indices.end(),
                                   {first, first + 1, first + 2, first, first + 2, first + 3});
                } else {
                    indices.insert(indices.end(),
                                   {first, first + 2, first + 1, first, first + 3, first + 2});
                }
            }
        }
        return json{{"attributes",
                     {{"POSITION", b.positions(positions)},
                      {"NORMAL", b.accessor(b.view(normals.data(), normals.size() * 12), kFloat,
                                            normals.size(), "VEC3")}}},
                    {"indices", b.indices(indices, kUnsignedInt)}};
    };
    json body = box(-0.9f, -0.1f, 0.8f);
    json stand = box(0.1f, 0.9f, 0.5f);
    stand["material"] = 0;
    body["material"] = baked_body.value_or(1);
    const auto material = [](const std::string& name, float r, float g, float b_) {
        return json{{"name", name},
                    {"pbrMetallicRoughness",
                     {{"baseColorFactor", {r, g, b_, 1.0}},
                      {"metallicFactor", 0.0},
                      {"roughnessFactor", 1.0}}}};
    };
    b.doc["materials"] = {material("Stand", 0.5f, 0.5f, 0.5f), material("Body", 0.8f, 0.8f, 0.8f),
                          material("Red", 0.8f, 0.05f, 0.05f), material("Blue", 0.05f, 0.1f, 0.8f)};
    if (!baked_body) {
        b.doc["extensionsUsed"] = {"KHR_materials_variants"};
        b.doc["extensions"]["KHR_materials_variants"]["variants"] = {
            {{"name", "Red"}}, {{"name", "Blue"}}, {{"name", "Unchanged"}}};
        body["extensions"]["KHR_materials_variants"]["mappings"] = {
            {{"material", 2}, {"variants", {0}}}, {{"material", 3}, {"variants", {1}}}};
    }
    b.mesh(json::array({body, stand}), "Product");
    b.node({{"mesh", 0}});
    return b;
}

// A 2x2 RGBA PNG: red, green / blue, white at alpha 128.
inline const char* kTinyPng =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAE0lEQVR4nGP4z8DwHwyBNAg0AABJSQl4KKDbdwAAAAB"
    "JRU5ErkJggg==";

// The start of a PNG whose header claims width x height pixels (no pixel data at all).
inline std::vector<std::uint8_t> png_header(std::uint32_t width, std::uint32_t height) {
    std::vector<std::uint8_t> png{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n',
                                  0,    0,   0,   13,  'I',  'H',  'D',  'R'};
    for (std::uint32_t v : {width, height}) {
        for (int shift = 24; shift >= 0; shift -= 8) {
            png.push_back(std::uint8_t(v >> shift));
        }
    }
    png.insert(png.end(), {8, 6, 0, 0, 0, 0, 0, 0, 0});  // depth, RGBA, ..., a CRC
    return png;
}

// ---------------------------------------------------------------------------------------------
// glTF samples of assimp-testmodels

inline const fs::path kAssimpGltf = "/usr/share/assimp/models/glTF2";

#define REQUIRE_ASSIMP_SAMPLES()                                                         \
    if (!fs::is_directory(kAssimpGltf)) {                                                \
        GTEST_SKIP() << "*** assimp-testmodels is not installed: no glTF samples under " \
                     << kAssimpGltf << "; real-file glTF loading is NOT tested ***";     \
    }

inline Mesh load_sample(const std::string& relative, const MeshLimits& limits = {}) {
    return load_mesh_file((kAssimpGltf / relative).string(), limits);
}

// The .gltf with every external buffer and image replaced by a data: URI of the file found
// in one of `dirs` (what a user would do before uploading), so that the asset's own flaw is
// what the loader meets.
inline std::string embedded(const std::string& relative, const std::vector<std::string>& dirs) {
    const fs::path path = kAssimpGltf / relative;
    json d = json::parse(std::ifstream(path));
    for (const char* section : {"buffers", "images"}) {
        if (!d.contains(section)) {
            continue;
        }
        for (json& item : d[section]) {
            if (!item.contains("uri") || item["uri"].get<std::string>().rfind("data:", 0) == 0) {
                continue;
            }
            const std::string uri = item["uri"];
            std::vector<std::uint8_t> bytes;
            for (const std::string& dir : dirs) {
                if (fs::exists(kAssimpGltf / dir / uri)) {
                    bytes = read_bytes(kAssimpGltf / dir / uri);
                    break;
                }
            }
            EXPECT_FALSE(bytes.empty()) << uri << " not found for " << relative;
            const std::string mime = std::string(section) == "buffers"
                                         ? "application/octet-stream"
                                         : (uri.ends_with(".png") ? "image/png" : "image/jpeg");
            item["uri"] = "data:" + mime + ";base64," + base64(bytes);
        }
    }
    return d.dump();
}

}  // namespace oer::mesh_testing
