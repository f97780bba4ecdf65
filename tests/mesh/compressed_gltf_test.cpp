// Compressed and instanced glTF geometry, crafted here: KHR_mesh_quantization, sparse
// accessors, EXT_meshopt_compression (encoded by meshoptimizer's own encoders),
// KHR_draco_mesh_compression (assimp-testmodels' Draco sample and streams made from it) and
// EXT_mesh_gpu_instancing; then hostile forms of each, every one refused with its ErrorKind and
// a message naming the accessor, bufferView or extension, within milliseconds and a bounded
// resident growth (before anything its counts claim is allocated). The files the real tools
// make are in compressed_gltf_tools_test.cpp.
#include <gtest/gtest.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <meshoptimizer.h>
#include <glm/geometric.hpp>

#include "gltf_test_assets.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

constexpr int kByte = 5120;
constexpr int kShort = 5122;

// Runs `load`, which must fail as `expect_error` says, in under 0.5 s and, where the resident
// set is the program's own, with under 16 MiB of resident growth: the claimed counts were
// refused before what they claim was allocated.
void expect_refused_cheaply(const std::function<void()>& load, ErrorKind kind,
                            const std::vector<std::string>& parts) {
    malloc_trim(0);
    oer::testing::reset_peak_resident();
    const long before = oer::testing::resident_kib();
    const auto start = std::chrono::steady_clock::now();
    expect_error(load, kind, parts);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long growth = oer::testing::peak_resident_kib() - before;
    std::cout << "[          ] refused '" << parts.front() << "' in " << seconds * 1e3
              << " ms, resident +" << growth << " KiB\n";
    EXPECT_LT(seconds, 0.5) << parts.front();
    if (oer::testing::kResidentMemoryIsTheProgramsOwn) {
        EXPECT_LT(growth, 16 << 10) << parts.front();
    }
}

Mesh load_glb(const std::vector<std::uint8_t>& bytes, const MeshLimits& limits = kUnrefined) {
    return load_mesh_memory(as_bytes(bytes), "test.glb", MeshFormat::Glb, limits);
}

// A 4 x 4 grid of quads in the xy plane, z = x * y, as positions and triangle indices.
struct Grid {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<std::uint32_t> indices;
};

Grid make_grid() {
    Grid grid;
    constexpr int n = 5;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const float fx = float(x) / (n - 1);
            const float fy = float(y) / (n - 1);
            grid.positions.emplace_back(fx, fy, fx * fy);
            grid.normals.push_back(glm::normalize(glm::vec3(-fy, -fx, 1.0f)));
        }
    }
    for (int y = 0; y + 1 < n; ++y) {
        for (int x = 0; x + 1 < n; ++x) {
            const std::uint32_t a = std::uint32_t(y * n + x);
            grid.indices.insert(grid.indices.end(), {a, a + 1, a + n + 1, a, a + n + 1, a + n});
        }
    }
    return grid;
}

// ---------------------------------------------------------------------------------------------
// EXT_meshopt_compression: a builder of compressed views in buffer 0, decoded into buffer 1,
// the fallback buffer (no data).

struct MeshoptAsset {
    GltfBuilder b;
    std::uint64_t fallback_bytes = 0;

    MeshoptAsset() {
        b.doc["extensionsUsed"] = {"EXT_meshopt_compression"};
        b.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    }

    // A view of `decoded_bytes` in the fallback buffer whose data is `compressed`.
    int view(const std::vector<unsigned char>& compressed, std::uint64_t count,
             std::uint64_t stride, const std::string& mode, const std::string& filter = "NONE",
             bool attribute_stride = true) {
        const int index = b.view(compressed.data(), compressed.size());
        json& v = b.doc["bufferViews"][std::size_t(index)];
        json extension = {{"buffer", 0},
                          {"byteOffset", v["byteOffset"]},
                          {"byteLength", compressed.size()},
                          {"byteStride", stride},
                          {"count", count},
                          {"mode", mode}};
        if (filter != "NONE") {
            extension["filter"] = filter;
        }
        v = {{"buffer", 1},
             {"byteOffset", fallback_bytes},
             {"byteLength", count * stride},
             {"extensions", {{"EXT_meshopt_compression", extension}}}};
        if (mode == "ATTRIBUTES" && attribute_stride) {
            v["byteStride"] = stride;
        }
        fallback_bytes += (count * stride + 3) / 4 * 4;
        return index;
    }

    std::vector<std::uint8_t> glb() {
        b.extra_buffers = {{{"byteLength", std::max<std::uint64_t>(fallback_bytes, 1)},
                            {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
        return b.glb();
    }
};

std::vector<unsigned char> encode_vertices(const void* data, std::size_t count,
                                           std::size_t stride) {
    std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(count, stride));
    out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride));
    return out;
}

std::vector<unsigned char> encode_triangles(const std::vector<std::uint32_t>& indices,
                                            std::size_t vertices) {
    std::vector<unsigned char> out(meshopt_encodeIndexBufferBound(indices.size(), vertices));
    out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), indices.size()));
    return out;
}

// The grid: positions by the EXPONENTIAL filter (floats, stride 12), normals by OCTAHEDRAL
// (normalized BYTEs, stride 4), indices by TRIANGLES, or by INDICES when `sequence`.
std::vector<std::uint8_t> meshopt_grid(const Grid& grid, bool sequence = false) {
    MeshoptAsset a;
    a.b.doc["extensionsUsed"].push_back("KHR_mesh_quantization");
    const std::size_t n = grid.positions.size();
    std::vector<std::uint32_t> exponential(n * 3);
    meshopt_encodeFilterExp(exponential.data(), n, 12, 24,
                            reinterpret_cast<const float*>(grid.positions.data()));
    const int positions =
        a.view(encode_vertices(exponential.data(), n, 12), n, 12, "ATTRIBUTES", "EXPONENTIAL");
    std::vector<float> normals4;
    for (const glm::vec3& normal : grid.normals) {
        normals4.insert(normals4.end(), {normal.x, normal.y, normal.z, 0.0f});
    }
    std::vector<std::int8_t> octahedral(n * 4);
    meshopt_encodeFilterOct(octahedral.data(), n, 4, 8, normals4.data());
    const int normals =
        a.view(encode_vertices(octahedral.data(), n, 4), n, 4, "ATTRIBUTES", "OCTAHEDRAL");
    int indices = 0;
    if (sequence) {
        std::vector<unsigned char> out(meshopt_encodeIndexSequenceBound(grid.indices.size(), n));
        out.resize(meshopt_encodeIndexSequence(out.data(), out.size(), grid.indices.data(),
                                               grid.indices.size()));
        indices = a.view(out, grid.indices.size(), 4, "INDICES");
    } else {
        indices = a.view(encode_triangles(grid.indices, n), grid.indices.size(), 4, "TRIANGLES");
    }
    const int p = a.b.accessor(positions, kFloat, n, "VEC3");
    const int nrm = a.b.accessor(normals, kByte, n, "VEC3");
    a.b.doc["accessors"][std::size_t(nrm)]["normalized"] = true;
    const int i = a.b.accessor(indices, kUnsignedInt, grid.indices.size(), "SCALAR");
    a.b.mesh(json::array({{{"attributes", {{"POSITION", p}, {"NORMAL", nrm}}}, {"indices", i}}}),
             "Grid");
    a.b.node({{"mesh", 0}});
    return a.glb();
}

// The triangles of `indices`, each rotated to start at its smallest index: meshopt's TRIANGLES
// codec keeps each triangle's winding, not its first vertex (meshoptimizer.h).
std::vector<std::uint32_t> rotated(std::vector<std::uint32_t> indices) {
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        while (indices[t] > indices[t + 1] || indices[t] > indices[t + 2]) {
            std::rotate(indices.begin() + std::ptrdiff_t(t),
                        indices.begin() + std::ptrdiff_t(t + 1),
                        indices.begin() + std::ptrdiff_t(t + 3));
        }
    }
    return indices;
}

void expect_grid(const Mesh& mesh, const Grid& grid, float normal_tolerance) {
    ASSERT_EQ(mesh.primitives.size(), 1u);
    const Primitive& p = mesh.primitives[0];
    ASSERT_EQ(p.positions.size(), grid.positions.size());
    EXPECT_EQ(rotated(p.indices), rotated(grid.indices));
    for (std::size_t i = 0; i < grid.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(p.positions[i] - grid.positions[i]), 0.0f, 1e-6f) << i;
        EXPECT_NEAR(glm::length(p.normals[i] - grid.normals[i]), 0.0f, normal_tolerance) << i;
    }
}

// ---------------------------------------------------------------------------------------------
// KHR_draco_mesh_compression: assimp-testmodels' sample, and streams made from its first one.

const fs::path kDracoSample = kAssimpGltf / "draco" / "2CylinderEngine.gltf";

// A one-primitive .gltf whose Draco stream is `stream`, its accessors claiming `points` points
// and `indices` indices.
std::string draco_asset(const std::vector<std::uint8_t>& stream, std::uint64_t points,
                        std::uint64_t indices) {
    GltfBuilder b;
    const int view = b.view(stream.data(), stream.size());
    b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    b.doc["accessors"] = {
        {{"componentType", kUnsignedShort}, {"count", indices}, {"type", "SCALAR"}},
        {{"componentType", kFloat}, {"count", points}, {"type", "VEC3"}},
        {{"componentType", kFloat}, {"count", points}, {"type", "VEC3"}}};
    b.mesh(json::array(
               {{{"attributes", {{"NORMAL", 1}, {"POSITION", 2}}},
                 {"indices", 0},
                 {"extensions",
                  {{"KHR_draco_mesh_compression",
                    {{"bufferView", view}, {"attributes", {{"NORMAL", 0}, {"POSITION", 1}}}}}}}}}),
           "Engine");
    b.node({{"mesh", 0}});
    return b.gltf();
}

// The sample's first stream, with its accessors' counts.
struct DracoStream {
    std::vector<std::uint8_t> bytes;
    std::uint64_t points = 0;
    std::uint64_t indices = 0;
};

DracoStream sample_stream() {
    const json d = json::parse(std::ifstream(kDracoSample));
    const std::vector<std::uint8_t> bin =
        read_bytes(kDracoSample.parent_path() / "2CylinderEngine.bin");
    const json& primitive = d["meshes"][0]["primitives"][0];
    const json& view =
        d["bufferViews"]
         [primitive["extensions"]["KHR_draco_mesh_compression"]["bufferView"].get<std::size_t>()];
    const std::size_t offset = view.value("byteOffset", std::size_t(0));
    DracoStream stream;
    stream.bytes.assign(
        bin.begin() + std::ptrdiff_t(offset),
        bin.begin() + std::ptrdiff_t(offset + view["byteLength"].get<std::size_t>()));
    stream.points = d["accessors"][primitive["attributes"]["POSITION"].get<std::size_t>()]["count"];
    stream.indices = d["accessors"][primitive["indices"].get<std::size_t>()]["count"];
    return stream;
}

// A stream header: version 2.2, a triangle mesh, `method` (0 sequential, 1 edgebreaker), no
// flags, then the connectivity's counts as varints.
std::vector<std::uint8_t> draco_header(std::uint8_t method, std::vector<std::uint64_t> counts) {
    std::vector<std::uint8_t> out{'D', 'R', 'A', 'C', 'O', 2, 2, 1, method, 0, 0};
    if (method == 1) {
        out.push_back(0);  // standard edgebreaker traversal
    }
    for (std::uint64_t value : counts) {
        do {
            out.push_back(std::uint8_t((value & 0x7f) | (value > 0x7f ? 0x80 : 0)));
            value >>= 7;
        } while (value != 0);
    }
    out.resize(out.size() + 64, 0);
    return out;
}

// ---------------------------------------------------------------------------------------------
// EXT_mesh_gpu_instancing

// The triangle as mesh 0 of node 0, instanced at `translations`.
GltfBuilder instanced_triangle(const std::vector<glm::vec3>& translations) {
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    const int p = b.positions(kTriangle);
    const int t = b.accessor(b.view(translations.data(), translations.size() * 12), kFloat,
                             translations.size(), "VEC3");
    b.mesh(json::array({{{"attributes", {{"POSITION", p}}}}}), "Tri");
    b.node({{"mesh", 0},
            {"translation", {0, 0, 5}},
            {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}}}}}}}});
    return b;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// KHR_mesh_quantization

TEST(CompressedGltf, QuantizedPositionsAreDequantizedByTheNodeAndNormalsByNormalization) {
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    // SHORT positions (not normalized), 4-byte aligned elements: stride 8.
    const std::vector<std::int16_t> positions{0, 0, 0, 0, 1000, 0, 0, 0, 0, 1000, 0, 0};
    const int p = b.accessor(b.view(positions.data(), 24, 8), kShort, 3, "VEC3");
    const std::vector<std::int8_t> normals{0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -128, 0};
    const int n = b.accessor(b.view(normals.data(), 12, 4), kByte, 3, "VEC3");
    b.doc["accessors"][std::size_t(n)]["normalized"] = true;
    const std::vector<std::uint8_t> uv{0, 0, 255, 0, 0, 255};
    const int t = b.accessor(b.view(uv.data(), uv.size()), kUnsignedByte, 3, "VEC2");
    b.mesh(json::array({{{"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}}}}}));
    b.node({{"mesh", 0}, {"scale", {0.001, 0.001, 0.001}}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);
    const Primitive& prim = mesh.primitives[0];
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(glm::length(prim.positions[i] - kTriangle[i]), 0.0f, 1e-6f) << i;
        EXPECT_NEAR(glm::length(prim.normals[i] - glm::vec3(0, 0, i == 2 ? -1 : 1)), 0.0f, 1e-6f);
    }
    // Not normalized: the integers themselves (KHR_mesh_quantization allows it for TEXCOORD).
    EXPECT_EQ(prim.texcoords[1], glm::vec2(255, 0));

    // The same types without the extension are refused, naming what glTF 2.0 allows.
    b.doc.erase("extensionsUsed");
    b.doc.erase("extensionsRequired");
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::Unsupported,
                 {"POSITION: accessor 0 is VEC3 of SHORT; expected VEC3 of FLOAT"});
    // A quantized NORMAL must be normalized.
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["accessors"][std::size_t(n)]["normalized"] = false;
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::InvalidInput,
                 {"NORMAL: accessor 1 is of BYTE and must be normalized (KHR_mesh_quantization)"});
}

// ---------------------------------------------------------------------------------------------
// Sparse accessors

TEST(CompressedGltf, SparseAccessorsSubstituteTheirElementsOnTheViewOrOnZeros) {
    GltfBuilder b;
    const int p = b.positions({{0, 0, 0}, {9, 9, 9}, {0, 1, 0}});
    const std::vector<std::uint16_t> targets{1};
    const std::vector<glm::vec3> values{{1, 0, 0}};
    const int target_view = b.view(targets.data(), 2);
    const int value_view = b.view(values.data(), 12);
    b.doc["accessors"][std::size_t(p)]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", target_view}, {"componentType", kUnsignedShort}}},
        {"values", {{"bufferView", value_view}}}};
    b.mesh(json::array({{{"attributes", {{"POSITION", p}}}}}));
    b.node({{"mesh", 0}});
    Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    EXPECT_EQ(mesh.primitives[0].positions, kTriangle);

    // On zeros: no bufferView, two of the three elements substituted.
    const std::vector<std::uint8_t> two{1, 2};
    const std::vector<glm::vec3> corners{{1, 0, 0}, {0, 1, 0}};
    b.doc["accessors"][std::size_t(p)].erase("bufferView");
    b.doc["accessors"][std::size_t(p)]["sparse"] = {
        {"count", 2},
        {"indices", {{"bufferView", b.view(two.data(), 2)}, {"componentType", kUnsignedByte}}},
        {"values", {{"bufferView", b.view(corners.data(), 24)}}}};
    mesh = load_gltf_text(b.gltf(), kUnrefined);
    EXPECT_EQ(mesh.primitives[0].positions, kTriangle);
}

TEST(CompressedGltfHostile, SparseCountsIndicesAndValuesAreCheckedBeforeUse) {
    GltfBuilder b;
    const int p = b.positions(kTriangle);
    const std::vector<std::uint32_t> increasing{1, 2};
    const std::vector<std::uint32_t> decreasing{2, 1};
    const int increasing_view = b.view(increasing.data(), 8);
    const int decreasing_view = b.view(decreasing.data(), 8);
    const int value_view = b.view(kTriangle.data(), 24);
    const auto sparse = [&](std::int64_t count, int target_view) {
        b.doc["accessors"][std::size_t(p)]["sparse"] = {
            {"count", count},
            {"indices", {{"bufferView", target_view}, {"componentType", kUnsignedInt}}},
            {"values", {{"bufferView", value_view}}}};
        return b.gltf();
    };
    b.mesh(json::array({{{"attributes", {{"POSITION", p}}}}}));
    b.node({{"mesh", 0}});
    expect_refused_cheaply([&] { load_gltf_text(sparse(2000000000, increasing_view)); },
                           ErrorKind::InvalidInput,
                           {"POSITION: accessor 0: sparse.count is 2000000000, not within 1 to "
                            "the accessor's count 3"});
    expect_error([&] { load_gltf_text(sparse(2, decreasing_view)); }, ErrorKind::InvalidInput,
                 {"accessor 0: sparse.indices[1] is 1: sparse indices must increase strictly "
                  "and stay below the count 3"});
    b.doc["accessors"][std::size_t(p)]["count"] = 2;
    expect_error([&] { load_gltf_text(sparse(2, increasing_view)); }, ErrorKind::InvalidInput,
                 {"sparse.indices[1] is 2"});
    b.doc["accessors"][std::size_t(p)]["count"] = 3;
    b.doc["bufferViews"][std::size_t(value_view)]["byteLength"] = 12;
    expect_error([&] { load_gltf_text(sparse(2, increasing_view)); }, ErrorKind::InvalidInput,
                 {"accessor 0: sparse.values: bytes 0 to 24 run past the end of bufferView " +
                  std::to_string(value_view) + " (12 bytes)"});
}

// ---------------------------------------------------------------------------------------------
// EXT_meshopt_compression

TEST(CompressedGltf, MeshoptViewsDecodeWithEveryModeAndTheirFilters) {
    const Grid grid = make_grid();
    // 8-bit octahedral normals: within 2 / 127 of the originals.
    expect_grid(load_glb(meshopt_grid(grid)), grid, 0.02f);
    expect_grid(load_glb(meshopt_grid(grid, true)), grid, 0.02f);
}

TEST(CompressedGltf, MeshoptUsedButNotRequiredStillDecodesOverTheFallbackData) {
    const Grid grid = make_grid();
    MeshoptAsset a;
    a.b.doc.erase("extensionsRequired");
    const std::size_t n = grid.positions.size();
    const int p = a.view(encode_vertices(grid.positions.data(), n, 12), n, 12, "ATTRIBUTES");
    const int i = a.view(encode_triangles(grid.indices, n), grid.indices.size(), 4, "TRIANGLES");
    a.b.accessor(p, kFloat, n, "VEC3");
    a.b.accessor(i, kUnsignedInt, grid.indices.size(), "SCALAR");
    a.b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}));
    a.b.node({{"mesh", 0}});
    // Fallback data for other readers, here zeros: the loader must decode the compressed views.
    const std::vector<std::uint8_t> zeros(a.fallback_bytes, 0);
    a.b.extra_buffers = {{{"byteLength", zeros.size()},
                          {"uri", "data:application/octet-stream;base64," + base64(zeros)}}};
    const Mesh mesh = load_gltf_text(a.b.gltf(), kUnrefined);
    EXPECT_EQ(mesh.primitives[0].positions, grid.positions);
    EXPECT_EQ(rotated(mesh.primitives[0].indices), rotated(grid.indices));
}

TEST(CompressedGltfHostile, MeshoptCountsStridesAndDataAreCheckedBeforeDecoding) {
    const Grid grid = make_grid();
    const std::size_t n = grid.positions.size();
    const std::vector<unsigned char> vertices = encode_vertices(grid.positions.data(), n, 12);
    // tinygltf refuses a view's own byteStride that is not a multiple of 4: the view has none.
    const auto asset = [&](std::uint64_t count, std::uint64_t stride, const std::string& mode,
                           const std::string& filter = "NONE") {
        MeshoptAsset a;
        const int view = a.view(vertices, count, stride, mode, filter, stride % 4 == 0);
        a.b.accessor(view, kFloat, n, "VEC3");
        a.b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
        a.b.node({{"mesh", 0}});
        return a;
    };
    expect_refused_cheaply([&] { load_glb(asset(1000000000, 12, "ATTRIBUTES").glb()); },
                           ErrorKind::LimitExceeded,
                           {"bufferView 0: EXT_meshopt_compression: count 1000000000, more than "
                            "the limit of vertices allows"});
    expect_refused_cheaply([&] { load_glb(asset(n, 6, "ATTRIBUTES").glb()); },
                           ErrorKind::InvalidInput,
                           {"bufferView 0: EXT_meshopt_compression: byteStride 6 for mode "
                            "ATTRIBUTES, which needs a multiple of 4 up to 256"});
    expect_error([&] { load_glb(asset(n, 12, "TRIANGLES").glb()); }, ErrorKind::InvalidInput,
                 {"byteStride 12 for mode TRIANGLES, which needs 2 or 4"});
    expect_error([&] { load_glb(asset(n, 12, "ATTRIBUTES", "QUATERNION").glb()); },
                 ErrorKind::InvalidInput, {"byteStride 12 for filter QUATERNION, which needs 8"});
    expect_error([&] { load_glb(asset(n, 12, "ATTRIBUTES", "ZIGZAG").glb()); },
                 ErrorKind::InvalidInput, {"unknown filter 'ZIGZAG'"});
    // A run of zeros: 32 MiB in 1/64 of that, past the ratio real files decode to.
    const std::vector<std::uint8_t> zeros(std::size_t(32) << 20, 0);
    const std::vector<unsigned char> run = encode_vertices(zeros.data(), zeros.size() / 32, 32);
    MeshoptAsset bomb;
    bomb.view(run, zeros.size() / 32, 32, "ATTRIBUTES");
    bomb.b.accessor(0, kFloat, zeros.size() / 32, "VEC3");
    bomb.b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    bomb.b.node({{"mesh", 0}});
    const std::vector<std::uint8_t> bomb_glb = bomb.glb();
    expect_refused_cheaply([&] { load_glb(bomb_glb); }, ErrorKind::LimitExceeded,
                           {"bufferView 0: EXT_meshopt_compression: the compressed views would "
                            "decode to 33554432 bytes from",
                            "more than 32 times"});
    // The view's own byteStride and its byteLength disagree with the extension's.
    MeshoptAsset stride = asset(n, 12, "ATTRIBUTES");
    stride.b.doc["bufferViews"][0]["byteStride"] = 16;
    expect_error([&] { load_glb(stride.glb()); }, ErrorKind::InvalidInput,
                 {"bufferView 0: EXT_meshopt_compression: byteStride 12 differs from the view's "
                  "own byteStride 16"});
    MeshoptAsset length = asset(n, 12, "ATTRIBUTES");
    length.b.doc["bufferViews"][0]["byteLength"] = 12;
    expect_error([&] { load_glb(length.glb()); }, ErrorKind::InvalidInput,
                 {"count 25 x byteStride 12 = 300 bytes, more than the view's byteLength 12"});
    // Data that is not what it claims: too few vertices' worth, or garbage.
    MeshoptAsset garbage = asset(n, 12, "ATTRIBUTES");
    for (std::size_t i = 1; i < garbage.b.bin.size(); ++i) {
        garbage.b.bin[i] = std::uint8_t(i * 37);
    }
    expect_error([&] { load_glb(garbage.glb()); }, ErrorKind::InvalidInput,
                 {"bufferView 0: EXT_meshopt_compression: the compressed ATTRIBUTES data is "
                  "malformed"});
    expect_error([&] { load_glb(asset(n * 40, 12, "ATTRIBUTES").glb()); }, ErrorKind::InvalidInput,
                 {"bufferView 0: EXT_meshopt_compression: the compressed ATTRIBUTES data is "
                  "malformed"});
    // The compressed bytes past their buffer; a plain view into the fallback buffer.
    MeshoptAsset past = asset(n, 12, "ATTRIBUTES");
    past.b.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 4096;
    expect_error([&] { load_glb(past.glb()); }, ErrorKind::InvalidInput,
                 {"bufferView 0: EXT_meshopt_compression: bytes 4096 to"});
    MeshoptAsset plain = asset(n, 12, "ATTRIBUTES");
    plain.b.doc["bufferViews"][0].erase("extensions");
    expect_error([&] { load_glb(plain.glb()); }, ErrorKind::InvalidInput,
                 {"an EXT_meshopt_compression fallback buffer, which has no data"});
}

// ---------------------------------------------------------------------------------------------
// KHR_draco_mesh_compression

TEST(CompressedGltf, DracoSampleMatchesTheSameModelUncompressed) {
    REQUIRE_ASSIMP_SAMPLES();
    const Mesh draco = load_mesh_file(kDracoSample.string(), kUnrefined);
    const Mesh plain = load_sample("2CylinderEngine-glTF-Binary/2CylinderEngine.glb", kUnrefined);
    expect_valid(draco);
    EXPECT_EQ(draco.primitives.size(), plain.primitives.size());
    // Its own tessellation (65311 triangles in its meshes, 75730 in the .glb's): every node's
    // instance of every mesh, with the triangles its accessors declare.
    const json d = json::parse(std::ifstream(kDracoSample));
    std::uint64_t declared = 0;
    for (const json& node : d["nodes"]) {
        if (node.contains("mesh")) {
            for (const json& primitive :
                 d["meshes"][node["mesh"].get<std::size_t>()]["primitives"]) {
                declared += d["accessors"][primitive["indices"].get<std::size_t>()]["count"]
                                .get<std::uint64_t>() /
                            3;
            }
        }
    }
    EXPECT_EQ(draco.triangle_count, declared);
    // Draco's default 14-bit positions over a model about 150 units across.
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(draco.bounds.min[k], plain.bounds.min[k], 0.05f);
        EXPECT_NEAR(draco.bounds.max[k], plain.bounds.max[k], 0.05f);
    }
}

TEST(CompressedGltfHostile, DracoStreamsClaimingMoreThanTheLimitsAreRefusedBeforeDecoding) {
    // 10^9 points, sequential; 10^9 faces, edgebreaker: refused from the header alone.
    expect_refused_cheaply(
        [&] {
            load_gltf_text(draco_asset(draco_header(0, {1000, 1000000000}), 1000000000, 3000));
        },
        ErrorKind::LimitExceeded,
        {"mesh 'Engine' primitive 0: KHR_draco_mesh_compression: the stream declares 1000 faces "
         "and "
         "1000000000 points, more than the limits of 5000000 triangles and 5000000 vertices "
         "allow"});
    expect_refused_cheaply(
        [&] {
            load_gltf_text(draco_asset(draco_header(1, {3, 1000000000}), 3, 3000000000));
        },
        ErrorKind::LimitExceeded, {"the stream declares 1000000000 faces and 3 points"});
    // Within the limits, but a million faces and points from 81 bytes.
    expect_refused_cheaply(
        [&] {
            load_gltf_text(draco_asset(draco_header(0, {1000000, 1000000}), 1000000, 3000000));
        },
        ErrorKind::LimitExceeded,
        {"the Draco streams would decode to 36000000 bytes from 81, more than 64 times"});
    // Counts that disagree with the accessors.
    expect_refused_cheaply(
        [&] {
            load_gltf_text(draco_asset(draco_header(0, {10, 8}), 8, 3));
        },
        ErrorKind::InvalidInput,
        {"the stream declares 10 faces, the indices accessor 0 has 3 indices"});
    expect_error(
        [&] {
            load_gltf_text(draco_asset(draco_header(0, {1, 8}), 9, 3));
        },
        ErrorKind::InvalidInput, {"the stream declares 8 points, the POSITION accessor 2 has 9"});
    // Not Draco, another version, metadata.
    std::vector<std::uint8_t> other = draco_header(0, {1, 3});
    other[5] = 1;
    expect_error([&] { load_gltf_text(draco_asset(other, 3, 3)); }, ErrorKind::Unsupported,
                 {"Draco bitstream version 1.2 is not supported"});
    other[5] = 2;
    other[10] = 0x80;
    expect_error([&] { load_gltf_text(draco_asset(other, 3, 3)); }, ErrorKind::Unsupported,
                 {"Draco streams with metadata are not supported"});
    other[0] = 'X';
    expect_error([&] { load_gltf_text(draco_asset(other, 3, 3)); }, ErrorKind::InvalidInput,
                 {"not a valid Draco stream (no DRACO header)"});
}

TEST(CompressedGltfHostile, DracoStreamsCutOrCorruptedFailToDecodeNamingThePrimitive) {
    REQUIRE_ASSIMP_SAMPLES();
    const DracoStream stream = sample_stream();
    // Whole, it decodes to its accessors' counts.
    const Mesh whole =
        load_gltf_text(draco_asset(stream.bytes, stream.points, stream.indices), kUnrefined);
    EXPECT_EQ(whole.triangle_count * 3, stream.indices);
    std::vector<std::uint8_t> cut(stream.bytes.begin(),
                                  stream.bytes.begin() + std::ptrdiff_t(stream.bytes.size() / 2));
    expect_refused_cheaply([&] { load_gltf_text(draco_asset(cut, stream.points, stream.indices)); },
                           ErrorKind::InvalidInput,
                           {"mesh 'Engine' primitive 0",
                            "KHR_draco_mesh_compression: the Draco stream does not "
                            "decode"});
    // The attribute ids name attributes the stream lacks.
    std::string text = draco_asset(stream.bytes, stream.points, stream.indices);
    json d = json::parse(text);
    d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]
     ["NORMAL"] = 7;
    expect_error([&] { load_gltf_text(d.dump()); }, ErrorKind::InvalidInput,
                 {"KHR_draco_mesh_compression: NORMAL: the stream has no attribute 7"});
}

// ---------------------------------------------------------------------------------------------
// EXT_mesh_gpu_instancing

TEST(CompressedGltf, InstancesAreCopiesUnderTheNodeTransformTimesTheirOwn) {
    GltfBuilder b = instanced_triangle({{0, 0, 0}, {10, 0, 0}, {0, 10, 0}});
    const Mesh mesh = load_gltf_text(b.gltf(), kUnrefined);
    expect_valid(mesh);
    ASSERT_EQ(mesh.primitives.size(), 3u);
    const std::vector<glm::vec3> offsets{{0, 0, 5}, {10, 0, 5}, {0, 10, 5}};
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(mesh.primitives[i].name,
                  "mesh 'Tri' instance " + std::to_string(i) + " primitive 0");
        for (std::size_t v = 0; v < 3; ++v) {
            EXPECT_EQ(mesh.primitives[i].positions[v], kTriangle[v] + offsets[i]);
        }
    }
}

TEST(CompressedGltfHostile, InstancingBombsAreRefusedFromTheDeclaredCounts) {
    // A billion instances whose TRANSLATION view holds one: refused before reading it.
    GltfBuilder b = instanced_triangle({{0, 0, 0}});
    b.doc["accessors"][1]["count"] = 1000000000;
    expect_refused_cheaply([&] { load_gltf_text(b.gltf()); }, ErrorKind::LimitExceeded,
                           {"node 0: EXT_mesh_gpu_instancing: 1000000000 instances of mesh 'Tri' "
                            "(1 primitives, 1 triangles, 3 vertices each) would pass the limits"});
    // Within the primitives' limit, but the copies' triangles pass the limit on triangles.
    MeshLimits limits = kUnrefined;
    limits.max_triangles = 2;
    GltfBuilder three = instanced_triangle({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    expect_error([&] { load_gltf_text(three.gltf(), limits); }, ErrorKind::LimitExceeded,
                 {"3 instances of mesh 'Tri'"});
    // Counts that disagree.
    three.doc["accessors"].push_back(three.doc["accessors"][1]);
    three.doc["accessors"][2]["count"] = 2;
    three.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] = 2;
    expect_error([&] { load_gltf_text(three.gltf()); }, ErrorKind::InvalidInput,
                 {"node 0: EXT_mesh_gpu_instancing.attributes.SCALE has 2 elements, the others 3"});
}

// ---------------------------------------------------------------------------------------------
// Extensions we do not support are named

TEST(CompressedGltf, AnUnsupportedExtensionIsNamedNotLeftToAnAccessorError) {
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"EXT_future_compression"};
    b.positions(kTriangle);  // a buffer, which no accessor uses
    b.doc["accessors"] = {{{"componentType", kFloat}, {"count", 3}, {"type", "VEC3"}}};
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"mesh", 0}});
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::Unsupported,
                 {"POSITION: accessor 0 has no bufferView and is not sparse (its data may be in "
                  "an extension the asset uses that is not supported: EXT_future_compression)"});
    b.doc["extensionsRequired"] = {"EXT_future_compression"};
    expect_error([&] { load_gltf_text(b.gltf()); }, ErrorKind::Unsupported,
                 {"the asset requires the extension EXT_future_compression, which is not "
                  "supported"});
}
