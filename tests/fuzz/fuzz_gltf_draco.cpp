// KHR_draco_mesh_compression (renderer/mesh/src/gltf_draco.cpp, Debian's libdraco): the input
// is one Draco stream, the accessors' counts first (compressed_gltf.hpp wraps it in a .glb):
//   bytes 0-3: the POSITION and NORMAL accessors' count (little-endian)
//   bytes 4-7: the indices accessor's count
//   byte 8: the extension's attribute ids (even: POSITION 0 and NORMAL 1; odd: the reverse, as
//           assimp-testmodels' sample has them)
//   the rest: the stream.
// Seeds: seeds/gltf_draco (make_compressed_seeds.py: the streams of assimp-testmodels' Draco
// sample and of glTF-Transform's draco command, with their counts).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "compressed_gltf.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    constexpr std::size_t kHeader = 9;
    if (size < kHeader) {
        return 0;
    }
    const std::span<const std::uint8_t> input(data, size);
    const std::uint64_t points = oer::fuzz::little_endian(input, 0, 4);
    const std::uint64_t indices = oer::fuzz::little_endian(input, 4, 4);
    const bool reversed = data[8] % 2 == 1;
    const std::span<const std::uint8_t> stream = input.subspan(kHeader);

    using nlohmann::json;
    json document;
    document["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    document["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    document["bufferViews"] = {{{"buffer", 0}, {"byteLength", stream.size()}}};
    document["accessors"] = {{{"componentType", 5125}, {"count", indices}, {"type", "SCALAR"}},
                             {{"componentType", 5126}, {"count", points}, {"type", "VEC3"}},
                             {{"componentType", 5126}, {"count", points}, {"type", "VEC3"}}};
    const json ids =
        reversed ? json{{"NORMAL", 0}, {"POSITION", 1}} : json{{"POSITION", 0}, {"NORMAL", 1}};
    document["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", 1}, {"NORMAL", 2}}},
            {"indices", 0},
            {"extensions",
             {{"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", ids}}}}}}}}}};
    document["nodes"] = {{{"mesh", 0}}};
    document["scenes"] = {{{"nodes", {0}}}};
    const std::vector<std::byte> glb =
        oer::fuzz::make_glb(document, stream, nlohmann::json::array());
    oer::fuzz::parse_or_refuse([&] { oer::fuzz::load_uploaded_mesh(glb, oer::MeshFormat::Glb); });
    return 0;
}
