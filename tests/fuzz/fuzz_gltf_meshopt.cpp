// EXT_meshopt_compression (renderer/mesh/src/gltf_meshopt.cpp): the input is one compressed
// bufferView, its parameters first (compressed_gltf.hpp wraps it in a .glb):
//   byte 0: mode (ATTRIBUTES, TRIANGLES, INDICES, by value % 3)
//   byte 1: filter (NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL, by value % 4)
//   byte 2: byteStride
//   bytes 3-6: count (little-endian)
//   the rest: the compressed bytes.
// ATTRIBUTES feed POSITION (FLOAT from a stride of 12, else normalized SHORT or BYTE under
// KHR_mesh_quantization); TRIANGLES and INDICES feed the indices of 256 fixed vertices. The
// view's fallback buffer has no data. Seeds: seeds/gltf_meshopt (make_compressed_seeds.py,
// from gltfpack's and glTF-Transform's files).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "compressed_gltf.hpp"

namespace {

constexpr std::size_t kHeader = 7;
constexpr std::uint64_t kFixedVertices = 256;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < kHeader) {
        return 0;
    }
    const std::span<const std::uint8_t> input(data, size);
    const char* modes[] = {"ATTRIBUTES", "TRIANGLES", "INDICES"};
    const char* filters[] = {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"};
    const std::string mode = modes[data[0] % 3];
    const std::string filter = filters[data[1] % 4];
    const std::uint64_t stride = data[2];
    const std::uint64_t count = oer::fuzz::little_endian(input, 3, 4);
    const std::span<const std::uint8_t> compressed = input.subspan(kHeader);

    using nlohmann::json;
    json extension = {{"buffer", 0},          {"byteOffset", 0}, {"byteLength", compressed.size()},
                      {"byteStride", stride}, {"count", count},  {"mode", mode},
                      {"filter", filter}};
    json decoded_view = {{"buffer", 1},
                         {"byteLength", count * stride},
                         {"extensions", {{"EXT_meshopt_compression", extension}}}};
    json document;
    document["extensionsUsed"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
    document["extensionsRequired"] = {"EXT_meshopt_compression"};
    json primitive;
    std::vector<std::uint8_t> bin(compressed.begin(), compressed.end());
    if (mode == "ATTRIBUTES") {
        decoded_view["byteStride"] = stride;
        const int component_type = stride >= 12 ? 5126 : stride >= 6 ? 5122 : 5120;
        document["accessors"] = {{{"bufferView", 0},
                                  {"componentType", component_type},
                                  {"normalized", component_type != 5126},
                                  {"count", count},
                                  {"type", "VEC3"}}};
        primitive = {{"attributes", {{"POSITION", 0}}}};
    } else {
        // A fixed fan of vertices in buffer 0, after the compressed bytes (4-byte aligned).
        bin.resize((bin.size() + 3) / 4 * 4, 0);
        const std::size_t offset = bin.size();
        for (std::uint64_t v = 0; v < kFixedVertices; ++v) {
            const float p[3] = {float(v % 16), float(v / 16), float(v % 7)};
            const auto* bytes = reinterpret_cast<const std::uint8_t*>(p);
            bin.insert(bin.end(), bytes, bytes + sizeof(p));
        }
        document["accessors"] = {{{"bufferView", 0},
                                  {"componentType", stride == 2 ? 5123 : 5125},
                                  {"count", count},
                                  {"type", "SCALAR"}},
                                 {{"bufferView", 1},
                                  {"componentType", 5126},
                                  {"count", kFixedVertices},
                                  {"type", "VEC3"}}};
        document["bufferViews"] = {
            decoded_view,
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", kFixedVertices * 12}}};
        primitive = {{"attributes", {{"POSITION", 1}}}, {"indices", 0}};
    }
    if (!document.contains("bufferViews")) {
        document["bufferViews"] = {decoded_view};
    }
    document["meshes"] = {{{"primitives", {primitive}}}};
    document["nodes"] = {{{"mesh", 0}}};
    document["scenes"] = {{{"nodes", {0}}}};
    const json fallback = {{{"byteLength", count * stride},
                            {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    const std::vector<std::byte> glb = oer::fuzz::make_glb(document, bin, fallback);
    oer::fuzz::parse_or_refuse([&] { oer::fuzz::load_uploaded_mesh(glb, oer::MeshFormat::Glb); });
    return 0;
}
