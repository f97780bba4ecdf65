// glTF uploads, binary (.glb) and JSON (.gltf with data: URIs): oer::load_mesh_memory
// (renderer/mesh/include/oer/mesh/mesh_loading.hpp: tinygltf behind the project's own schema
// and accessor checks, textures decoded by stb, libwebp and libavif) and
// oer::api::mesh_to_json, as server/src/mesh_registry.cpp reads an upload (mesh_upload.hpp).
// Bytes that start with the binary container's magic are read as .glb, others as .gltf, so one
// corpus covers both.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "mesh_upload.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::load_uploaded_mesh(oer::fuzz::as_bytes(data, size),
                                      binary ? oer::MeshFormat::Glb : oer::MeshFormat::Gltf);
    });
    return 0;
}
