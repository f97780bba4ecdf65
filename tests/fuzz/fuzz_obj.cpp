// OBJ uploads: oer::load_mesh_memory with MeshFormat::Obj
// (renderer/mesh/include/oer/mesh/mesh_loading.hpp: the project's counting of triangles and
// 'v' lines before tinyobjloader parses, then finishing) and oer::api::mesh_to_json, as
// server/src/mesh_registry.cpp reads an upload (mesh_upload.hpp).
#include <cstddef>
#include <cstdint>

#include "mesh_upload.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::load_uploaded_mesh(oer::fuzz::as_bytes(data, size), oer::MeshFormat::Obj);
    });
    return 0;
}
