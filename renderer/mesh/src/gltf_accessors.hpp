#pragma once
// Private to the glTF loader: accessors read with every index, offset, stride, count, type
// and component type checked against the glTF 2.0 specification and the buffers' sizes.
#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace oer::mesh_detail {

// The located elements of one accessor: element i starts at first + i * stride.
struct AccessorData {
    const unsigned char* first = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
    bool normalized = false;
};

// Reads the accessors of one model; every failure is an oer::Error naming `asset`.
class AccessorReader {
  public:
    AccessorReader(const tinygltf::Model& model, const std::string& asset)
        : model_(model), asset_(asset) {}

    // `what` names the use ("mesh 'Box' primitive 0: POSITION"); `accepted` lists the
    // component types allowed with `type`; more than `max_count` elements: LimitExceeded.
    AccessorData locate(int index, const std::string& what, int type,
                        std::initializer_list<int> accepted, std::uint64_t max_count,
                        const char* limit_name) const;

    // POSITION, NORMAL: VEC3 of FLOAT.
    std::vector<glm::vec3> vec3(int index, const std::string& what, std::uint64_t max_count,
                                const char* limit_name) const;

    // TANGENT: VEC4 of FLOAT.
    std::vector<glm::vec4> vec4(int index, const std::string& what, std::uint64_t max_count,
                                const char* limit_name) const;

    // TEXCOORD_0: VEC2 of FLOAT, or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT.
    std::vector<glm::vec2> texcoords(int index, const std::string& what, std::uint64_t max_count,
                                     const char* limit_name) const;

    // Indices: SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT.
    std::vector<std::uint32_t> indices(int index, const std::string& what, std::uint64_t max_count,
                                       const char* limit_name) const;

  private:
    const tinygltf::Model& model_;
    const std::string& asset_;
};

}  // namespace oer::mesh_detail
