// Accessors read safely (see gltf_accessors.hpp).
#include "gltf_accessors.hpp"

#include <algorithm>
#include <cstring>

#include "gltf_meshopt.hpp"
#include "gltf_parsing.hpp"
#include "mesh_errors.hpp"
#include "oer/core/error.hpp"

namespace oer::mesh_detail {

namespace {

const char* type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "an unknown type";
    }
}

const char* component_name(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "BYTE";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "UNSIGNED_BYTE";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "UNSIGNED_SHORT";
        case TINYGLTF_COMPONENT_TYPE_INT:
            return "INT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "UNSIGNED_INT";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "FLOAT";
        default:
            return "an unknown component type";
    }
}

constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;
constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

bool contains(const std::vector<int>& list, int value) {
    return std::find(list.begin(), list.end(), value) != list.end();
}

// One component as a float: glTF 2.0 3.11 ("Animations", the normalization table that
// KHR_mesh_quantization refers to): a normalized unsigned integer is c / (2^n - 1), a signed
// one max(c / (2^(n-1) - 1), -1); an integer that is not normalized is its value.
float component_value(const unsigned char* at, int component_type, bool normalized) {
    switch (component_type) {
        case kByte: {
            const auto value = static_cast<std::int8_t>(*at);
            return normalized ? std::max(float(value) / 127.0f, -1.0f) : float(value);
        }
        case kUnsignedByte:
            return normalized ? float(*at) / 255.0f : float(*at);
        case kShort: {
            std::int16_t value = 0;
            std::memcpy(&value, at, sizeof(value));
            return normalized ? std::max(float(value) / 32767.0f, -1.0f) : float(value);
        }
        case kUnsignedShort: {
            std::uint16_t value = 0;
            std::memcpy(&value, at, sizeof(value));
            return normalized ? float(value) / 65535.0f : float(value);
        }
        default: {
            float value = 0.0f;
            std::memcpy(&value, at, sizeof(value));
            return value;
        }
    }
}

std::uint32_t index_value(const unsigned char* at, int component_type) {
    if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        return at[0];
    }
    if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        std::uint16_t value = 0;
        std::memcpy(&value, at, sizeof(value));
        return value;
    }
    std::uint32_t value = 0;
    std::memcpy(&value, at, sizeof(value));
    return value;
}

const std::vector<int> kIndexTypes{TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
const std::vector<int> kQuantizedAny{kByte, kUnsignedByte, kShort, kUnsignedShort};

// count x N floats as count vectors of N.
template <typename Vector>
std::vector<Vector> as_vectors(const std::vector<float>& values) {
    constexpr std::size_t n = sizeof(Vector) / sizeof(float);
    std::vector<Vector> vectors(values.size() / n);
    std::memcpy(vectors.data(), values.data(), vectors.size() * sizeof(Vector));
    return vectors;
}

}  // namespace

std::size_t component_size(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

std::size_t component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
        case TINYGLTF_TYPE_MAT2:
            return 4;
        case TINYGLTF_TYPE_MAT3:
            return 9;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
    }
}

// KHR_mesh_quantization, "Extending Mesh Attributes"; EXT_mesh_gpu_instancing, "Extending
// Nodes" (its quantized types need KHR_mesh_quantization).
const AttributeFormat kPositionFormat{TINYGLTF_TYPE_VEC3, {kFloat}, kQuantizedAny, false};
const AttributeFormat kNormalFormat{TINYGLTF_TYPE_VEC3, {kFloat}, {kByte, kShort}, true};
const AttributeFormat kTangentFormat{TINYGLTF_TYPE_VEC4, {kFloat}, {kByte, kShort}, true};
const AttributeFormat kTexcoordFormat{
    TINYGLTF_TYPE_VEC2, {kFloat, kUnsignedByte, kUnsignedShort}, kQuantizedAny, false};
// glTF 2.0 section 3.7.2.1: COLOR_n is RGB or RGBA, float or normalized unsigned byte or short;
// KHR_mesh_quantization adds none.
const AttributeFormat kColor3Format{
    TINYGLTF_TYPE_VEC3, {kFloat, kUnsignedByte, kUnsignedShort}, {}, false};
const AttributeFormat kColor4Format{
    TINYGLTF_TYPE_VEC4, {kFloat, kUnsignedByte, kUnsignedShort}, {}, false};
const AttributeFormat kTranslationFormat{TINYGLTF_TYPE_VEC3, {kFloat}, {kByte, kShort}, true};
const AttributeFormat kRotationFormat{TINYGLTF_TYPE_VEC4, {kFloat, kByte, kShort}, {}, true};
const AttributeFormat kScaleFormat{TINYGLTF_TYPE_VEC3, {kFloat}, {kByte, kShort}, true};

AccessorReader::AccessorReader(const tinygltf::Model& model, const std::string& asset)
    : model_(model),
      asset_(asset),
      quantization_(std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                              "KHR_mesh_quantization") != model.extensionsUsed.end()) {}

AccessorData AccessorReader::locate(int index, const std::string& what, int type,
                                    const std::vector<int>& accepted, std::uint64_t max_count,
                                    const char* limit_name) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             what + ": accessor " + std::to_string(index) + " does not exist");
    }
    const tinygltf::Accessor& accessor = model_.accessors[std::size_t(index)];
    const std::string name = what + ": accessor " + std::to_string(index);
    if (accessor.type != type || !contains(accepted, accessor.componentType)) {
        std::string expected;
        for (int component_type : accepted) {
            expected +=
                (expected.empty() ? "" : " or ") + std::string(component_name(component_type));
        }
        fail(ErrorKind::Unsupported, asset_,
             name + " is " + type_name(accessor.type) + " of " +
                 component_name(accessor.componentType) + "; expected " + type_name(type) + " of " +
                 expected);
    }
    if (accessor.bufferView < 0 && !accessor.sparse.isSparse) {
        std::string unsupported;
        for (const std::string& extension : model_.extensionsUsed) {
            if (!supported_extension(extension)) {
                unsupported += (unsupported.empty() ? "" : ", ") + one_line(extension, 80);
            }
        }
        fail(ErrorKind::Unsupported, asset_,
             name + " has no bufferView and is not sparse" +
                 (unsupported.empty()
                      ? std::string(" (implicit zero data is not supported)")
                      : " (its data may be in an extension the asset uses that is not "
                        "supported: " +
                            unsupported + ")"));
    }
    if (accessor.count == 0) {
        fail(ErrorKind::InvalidInput, asset_, name + " has no elements");
    }
    if (accessor.count > max_count) {
        fail(ErrorKind::LimitExceeded, asset_,
             name + " has " + std::to_string(accessor.count) + " elements: more than the " +
                 "limit of " + limit_name);
    }
    const std::size_t element = component_size(accessor.componentType) * component_count(type);
    AccessorData data;
    data.stride = element;
    data.count = accessor.count;
    data.component_type = accessor.componentType;
    data.normalized = accessor.normalized;
    if (accessor.bufferView < 0) {
        return data;  // sparse on zeros
    }
    if (std::size_t(accessor.bufferView) >= model_.bufferViews.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": bufferView " + std::to_string(accessor.bufferView) + " does not exist");
    }
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(accessor.bufferView)];
    const std::string view_name = "bufferView " + std::to_string(accessor.bufferView);
    if (view.byteStride != 0) {
        if (view.byteStride < element || view.byteStride > 252) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": " + view_name + " has byteStride " + std::to_string(view.byteStride) +
                     ", invalid for elements of " + std::to_string(element) + " bytes");
        }
        data.stride = view.byteStride;
    }
    // count <= max_count (a few million) and stride <= 252: no overflow.
    const std::uint64_t span = std::uint64_t(accessor.count - 1) * data.stride + element;
    if (accessor.byteOffset > view.byteLength || span > view.byteLength - accessor.byteOffset) {
        fail(ErrorKind::InvalidInput, asset_,
             name + " (" + std::to_string(accessor.count) + " elements of " +
                 std::to_string(element) + " bytes, stride " + std::to_string(data.stride) +
                 ", offset " + std::to_string(accessor.byteOffset) + ") runs past the end of " +
                 view_name + " (" + std::to_string(view.byteLength) + " bytes)");
    }
    data.first = view_bytes(accessor.bufferView, accessor.byteOffset, span, name);
    return data;
}

const unsigned char* AccessorReader::view_bytes(int view_index, std::size_t offset,
                                                std::uint64_t bytes,
                                                const std::string& name) const {
    if (view_index < 0 || std::size_t(view_index) >= model_.bufferViews.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": bufferView " + std::to_string(view_index) + " does not exist");
    }
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(view_index)];
    const std::string view_name = "bufferView " + std::to_string(view_index);
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": " + view_name + " refers to buffer " + std::to_string(view.buffer) +
                 ", which does not exist");
    }
    const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": " + view_name + " (bytes " + std::to_string(view.byteOffset) + " to " +
                 std::to_string(view.byteOffset + view.byteLength) +
                 ") runs past the end of buffer " + std::to_string(view.buffer) + " (" +
                 std::to_string(buffer.size()) + " bytes" +
                 (is_fallback_buffer(model_, view.buffer)
                      ? ": an EXT_meshopt_compression fallback buffer, which has no data"
                      : "") +
                 ")");
    }
    if (offset > view.byteLength || bytes > view.byteLength - offset) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": bytes " + std::to_string(offset) + " to " + std::to_string(offset + bytes) +
                 " run past the end of " + view_name + " (" + std::to_string(view.byteLength) +
                 " bytes)");
    }
    return buffer.data() + view.byteOffset + offset;
}

std::vector<std::uint32_t> AccessorReader::sparse_indices(const tinygltf::Accessor& accessor,
                                                          const std::string& name) const {
    const auto& sparse = accessor.sparse;
    const std::string sparse_name = name + ": sparse";
    // count >= 1 and at most the accessor's count (glTF 2.0, accessor.sparse.count): checked
    // before the indices are read, so that it bounds what is allocated.
    if (sparse.count < 1 || std::size_t(sparse.count) > accessor.count) {
        fail(ErrorKind::InvalidInput, asset_,
             sparse_name + ".count is " + std::to_string(sparse.count) +
                 ", not within 1 to the accessor's count " + std::to_string(accessor.count));
    }
    if (!contains(kIndexTypes, sparse.indices.componentType)) {
        fail(ErrorKind::InvalidInput, asset_,
             sparse_name + ".indices.componentType " +
                 component_name(sparse.indices.componentType) +
                 " is not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    }
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
        fail(ErrorKind::InvalidInput, asset_, sparse_name + ": a byteOffset is negative");
    }
    const std::size_t size = component_size(sparse.indices.componentType);
    const std::size_t count = std::size_t(sparse.count);
    const unsigned char* first =
        view_bytes(sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset),
                   std::uint64_t(count) * size, sparse_name + ".indices");
    std::vector<std::uint32_t> indices(count);
    for (std::size_t i = 0; i < count; ++i) {
        indices[i] = index_value(first + i * size, sparse.indices.componentType);
        // Strictly increasing, each an element of the accessor (accessor.sparse.indices).
        if (indices[i] >= accessor.count || (i > 0 && indices[i] <= indices[i - 1])) {
            fail(ErrorKind::InvalidInput, asset_,
                 sparse_name + ".indices[" + std::to_string(i) + "] is " +
                     std::to_string(indices[i]) +
                     ": sparse indices must increase strictly and stay below the count " +
                     std::to_string(accessor.count));
        }
    }
    return indices;
}

const unsigned char* AccessorReader::sparse_values(const tinygltf::Accessor& accessor,
                                                   const std::string& name,
                                                   std::size_t element) const {
    return view_bytes(accessor.sparse.values.bufferView,
                      std::size_t(accessor.sparse.values.byteOffset),
                      std::uint64_t(accessor.sparse.count) * element, name + ": sparse.values");
}

std::vector<float> AccessorReader::floats(int index, const std::string& what,
                                          const AttributeFormat& format, std::uint64_t max_count,
                                          const char* limit_name) const {
    std::vector<int> accepted = format.core;
    if (quantization_) {
        for (int component_type : format.quantized) {
            if (!contains(accepted, component_type)) {
                accepted.push_back(component_type);
            }
        }
    }
    const AccessorData data = locate(index, what, format.type, accepted, max_count, limit_name);
    if (data.component_type != kFloat && !data.normalized) {
        const bool quantized = quantization_ && contains(format.quantized, data.component_type);
        if (!quantized || format.quantized_normalized) {
            fail(ErrorKind::InvalidInput, asset_,
                 what + ": accessor " + std::to_string(index) + " is of " +
                     component_name(data.component_type) + " and must be normalized" +
                     (quantized ? " (KHR_mesh_quantization)" : ""));
        }
    }
    const std::size_t components = component_count(format.type);
    const std::size_t size = component_size(data.component_type);
    std::vector<float> values(data.count * components, 0.0f);
    if (data.first != nullptr) {
        for (std::size_t i = 0; i < data.count; ++i) {
            for (std::size_t c = 0; c < components; ++c) {
                values[i * components + c] = component_value(
                    data.first + i * data.stride + c * size, data.component_type, data.normalized);
            }
        }
    }
    const tinygltf::Accessor& accessor = model_.accessors[std::size_t(index)];
    if (accessor.sparse.isSparse) {
        const std::string name = what + ": accessor " + std::to_string(index);
        const std::vector<std::uint32_t> targets = sparse_indices(accessor, name);
        const unsigned char* first = sparse_values(accessor, name, components * size);
        for (std::size_t i = 0; i < targets.size(); ++i) {
            for (std::size_t c = 0; c < components; ++c) {
                values[targets[i] * components + c] = component_value(
                    first + (i * components + c) * size, data.component_type, data.normalized);
            }
        }
    }
    return values;
}

std::vector<glm::vec2> AccessorReader::vec2(int index, const std::string& what,
                                            const AttributeFormat& format, std::uint64_t max_count,
                                            const char* limit_name) const {
    return as_vectors<glm::vec2>(floats(index, what, format, max_count, limit_name));
}

std::vector<glm::vec3> AccessorReader::vec3(int index, const std::string& what,
                                            const AttributeFormat& format, std::uint64_t max_count,
                                            const char* limit_name) const {
    return as_vectors<glm::vec3>(floats(index, what, format, max_count, limit_name));
}

std::vector<glm::vec4> AccessorReader::vec4(int index, const std::string& what,
                                            const AttributeFormat& format, std::uint64_t max_count,
                                            const char* limit_name) const {
    return as_vectors<glm::vec4>(floats(index, what, format, max_count, limit_name));
}

bool AccessorReader::quantized(int index) const {
    return model_.accessors[std::size_t(index)].componentType != kFloat;
}

std::vector<std::uint32_t> AccessorReader::indices(int index, const std::string& what,
                                                   std::uint64_t max_count,
                                                   const char* limit_name) const {
    const AccessorData data =
        locate(index, what, TINYGLTF_TYPE_SCALAR, kIndexTypes, max_count, limit_name);
    std::vector<std::uint32_t> values(data.count, 0);
    if (data.first != nullptr) {
        for (std::size_t i = 0; i < data.count; ++i) {
            values[i] = index_value(data.first + i * data.stride, data.component_type);
        }
    }
    const tinygltf::Accessor& accessor = model_.accessors[std::size_t(index)];
    if (accessor.sparse.isSparse) {
        const std::string name = what + ": accessor " + std::to_string(index);
        const std::vector<std::uint32_t> targets = sparse_indices(accessor, name);
        const std::size_t size = component_size(data.component_type);
        const unsigned char* first = sparse_values(accessor, name, size);
        for (std::size_t i = 0; i < targets.size(); ++i) {
            values[targets[i]] = index_value(first + i * size, data.component_type);
        }
    }
    return values;
}

}  // namespace oer::mesh_detail
