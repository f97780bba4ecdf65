#pragma once
// Private to the glTF loader: accessors read with every index, offset, stride, count, type
// and component type checked against the glTF 2.0 specification and the buffers' sizes, before
// anything is allocated. Integer components are converted as the specification's
// "Animations" / "Accessors" sections say (normalized: c / (2^n - 1), signed ones clamped to
// -1); the component types KHR_mesh_quantization adds are accepted where the asset declares
// that extension. Sparse accessors (glTF 2.0, 3.6.2.3 "Sparse Accessors") are read as their
// base (the bufferView's elements, or zeros) with the sparse elements substituted.
#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace oer::mesh_detail {

// The bytes of one component of `component_type` (TINYGLTF_COMPONENT_TYPE_FLOAT, ...) and the
// components of one element of `type` (TINYGLTF_TYPE_VEC3, ...); 0 for unknown ones.
std::size_t component_size(int component_type);
std::size_t component_count(int type);

// The located elements of one accessor: element i starts at first + i * stride (first is null
// for a sparse accessor without a bufferView, whose base elements are zeros).
struct AccessorData {
    const unsigned char* first = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
    bool normalized = false;
};

// The component types an attribute may have: glTF 2.0's own (its integer types normalized),
// and those KHR_mesh_quantization adds ("Extending Mesh Attributes"), normalized or not as
// `quantized_normalized` says.
struct AttributeFormat {
    int type = 0;  // TINYGLTF_TYPE_VEC3, ...
    std::vector<int> core;
    std::vector<int> quantized;
    bool quantized_normalized = false;
};

// POSITION, NORMAL, TANGENT, TEXCOORD_n, COLOR_n; the instancing extension's TRANSLATION, ROTATION
// and SCALE (EXT_mesh_gpu_instancing, with KHR_mesh_quantization's types).
extern const AttributeFormat kPositionFormat;
extern const AttributeFormat kNormalFormat;
extern const AttributeFormat kTangentFormat;
extern const AttributeFormat kTexcoordFormat;
extern const AttributeFormat kColor3Format;  // COLOR_n as RGB
extern const AttributeFormat kColor4Format;  // COLOR_n as RGBA
extern const AttributeFormat kTranslationFormat;
extern const AttributeFormat kRotationFormat;
extern const AttributeFormat kScaleFormat;

// Reads the accessors of one model; every failure is an oer::Error naming `asset`.
class AccessorReader {
  public:
    AccessorReader(const tinygltf::Model& model, const std::string& asset);

    // `what` names the use ("mesh 'Box' primitive 0: POSITION"); more than `max_count`
    // elements: LimitExceeded, `limit_name` naming the limit.

    // An attribute in `format` as floats (integers converted, normalized or not).
    std::vector<glm::vec2> vec2(int index, const std::string& what, const AttributeFormat& format,
                                std::uint64_t max_count, const char* limit_name) const;
    std::vector<glm::vec3> vec3(int index, const std::string& what, const AttributeFormat& format,
                                std::uint64_t max_count, const char* limit_name) const;
    std::vector<glm::vec4> vec4(int index, const std::string& what, const AttributeFormat& format,
                                std::uint64_t max_count, const char* limit_name) const;

    // Whether accessor `index` (which exists) holds integers: KHR_mesh_quantization's.
    bool quantized(int index) const;

    // Indices: SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT.
    std::vector<std::uint32_t> indices(int index, const std::string& what, std::uint64_t max_count,
                                       const char* limit_name) const;

  private:
    // `accepted` lists the component types allowed with `type`.
    AccessorData locate(int index, const std::string& what, int type,
                        const std::vector<int>& accepted, std::uint64_t max_count,
                        const char* limit_name) const;
    // The accessor's components as floats, count x components, sparse elements substituted.
    std::vector<float> floats(int index, const std::string& what, const AttributeFormat& format,
                              std::uint64_t max_count, const char* limit_name) const;
    // The elements the sparse accessor replaces: their indices, each checked, in order.
    std::vector<std::uint32_t> sparse_indices(const tinygltf::Accessor& accessor,
                                              const std::string& name) const;
    // The sparse values: `count` elements of `element` bytes in the values' bufferView.
    const unsigned char* sparse_values(const tinygltf::Accessor& accessor, const std::string& name,
                                       std::size_t element) const;
    // The bytes [offset, offset + bytes) of bufferView `view`, checked within its buffer.
    const unsigned char* view_bytes(int view, std::size_t offset, std::uint64_t bytes,
                                    const std::string& name) const;

    const tinygltf::Model& model_;
    const std::string& asset_;
    bool quantization_ = false;  // the asset uses KHR_mesh_quantization
};

}  // namespace oer::mesh_detail
