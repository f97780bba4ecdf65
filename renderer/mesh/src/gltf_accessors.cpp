// Accessors read safely (see gltf_accessors.hpp).
#include "gltf_accessors.hpp"

#include <algorithm>
#include <cstring>

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

}  // namespace

AccessorData AccessorReader::locate(int index, const std::string& what, int type,
                                    std::initializer_list<int> accepted, std::uint64_t max_count,
                                    const char* limit_name) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             what + ": accessor " + std::to_string(index) + " does not exist");
    }
    const tinygltf::Accessor& accessor = model_.accessors[std::size_t(index)];
    const std::string name = what + ": accessor " + std::to_string(index);
    if (accessor.sparse.isSparse) {
        fail(ErrorKind::Unsupported, asset_, name + " is sparse, which is not supported");
    }
    if (accessor.type != type ||
        std::find(accepted.begin(), accepted.end(), accessor.componentType) == accepted.end()) {
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
    if (accessor.bufferView < 0) {
        fail(ErrorKind::Unsupported, asset_,
             name + " has no bufferView (compressed or implicit zero data is not supported)");
    }
    if (accessor.count == 0) {
        fail(ErrorKind::InvalidInput, asset_, name + " has no elements");
    }
    if (accessor.count > max_count) {
        fail(ErrorKind::LimitExceeded, asset_,
             name + " has " + std::to_string(accessor.count) + " elements: more than the " +
                 "limit of " + limit_name);
    }
    if (std::size_t(accessor.bufferView) >= model_.bufferViews.size()) {
        fail(ErrorKind::InvalidInput, asset_,
             name + ": bufferView " + std::to_string(accessor.bufferView) + " does not exist");
    }
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(accessor.bufferView)];
    const std::string view_name = "bufferView " + std::to_string(accessor.bufferView);
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
                 std::to_string(buffer.size()) + " bytes)");
    }
    const std::size_t element = component_size(accessor.componentType) * component_count(type);
    std::size_t stride = element;
    if (view.byteStride != 0) {
        if (view.byteStride < element || view.byteStride > 252) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": " + view_name + " has byteStride " + std::to_string(view.byteStride) +
                     ", invalid for elements of " + std::to_string(element) + " bytes");
        }
        stride = view.byteStride;
    }
    // count <= max_count (a few million) and stride <= 252: no overflow.
    const std::uint64_t span = std::uint64_t(accessor.count - 1) * stride + element;
    if (accessor.byteOffset > view.byteLength || span > view.byteLength - accessor.byteOffset) {
        fail(ErrorKind::InvalidInput, asset_,
             name + " (" + std::to_string(accessor.count) + " elements of " +
                 std::to_string(element) + " bytes, stride " + std::to_string(stride) +
                 ", offset " + std::to_string(accessor.byteOffset) + ") runs past the end of " +
                 view_name + " (" + std::to_string(view.byteLength) + " bytes)");
    }
    AccessorData data;
    data.first = buffer.data() + view.byteOffset + accessor.byteOffset;
    data.stride = stride;
    data.count = accessor.count;
    data.component_type = accessor.componentType;
    data.normalized = accessor.normalized;
    return data;
}

std::vector<glm::vec3> AccessorReader::vec3(int index, const std::string& what,
                                            std::uint64_t max_count, const char* limit_name) const {
    const AccessorData data = locate(index, what, TINYGLTF_TYPE_VEC3,
                                     {TINYGLTF_COMPONENT_TYPE_FLOAT}, max_count, limit_name);
    std::vector<glm::vec3> values(data.count);
    for (std::size_t i = 0; i < data.count; ++i) {
        std::memcpy(&values[i], data.first + i * data.stride, sizeof(glm::vec3));
    }
    return values;
}

std::vector<glm::vec4> AccessorReader::vec4(int index, const std::string& what,
                                            std::uint64_t max_count, const char* limit_name) const {
    const AccessorData data = locate(index, what, TINYGLTF_TYPE_VEC4,
                                     {TINYGLTF_COMPONENT_TYPE_FLOAT}, max_count, limit_name);
    std::vector<glm::vec4> values(data.count);
    for (std::size_t i = 0; i < data.count; ++i) {
        std::memcpy(&values[i], data.first + i * data.stride, sizeof(glm::vec4));
    }
    return values;
}

std::vector<glm::vec2> AccessorReader::texcoords(int index, const std::string& what,
                                                 std::uint64_t max_count,
                                                 const char* limit_name) const {
    const AccessorData data =
        locate(index, what, TINYGLTF_TYPE_VEC2,
               {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
               max_count, limit_name);
    if (data.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && !data.normalized) {
        fail(ErrorKind::InvalidInput, asset_,
             what + ": integer texture coordinates must be normalized");
    }
    std::vector<glm::vec2> values(data.count);
    for (std::size_t i = 0; i < data.count; ++i) {
        const unsigned char* element = data.first + i * data.stride;
        if (data.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
            std::memcpy(&values[i], element, sizeof(glm::vec2));
        } else if (data.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            values[i] = glm::vec2(element[0], element[1]) / 255.0f;
        } else {
            std::uint16_t uv[2];
            std::memcpy(uv, element, sizeof(uv));
            values[i] = glm::vec2(uv[0], uv[1]) / 65535.0f;
        }
    }
    return values;
}

std::vector<std::uint32_t> AccessorReader::indices(int index, const std::string& what,
                                                   std::uint64_t max_count,
                                                   const char* limit_name) const {
    const AccessorData data =
        locate(index, what, TINYGLTF_TYPE_SCALAR,
               {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
               max_count, limit_name);
    std::vector<std::uint32_t> values(data.count);
    for (std::size_t i = 0; i < data.count; ++i) {
        const unsigned char* element = data.first + i * data.stride;
        if (data.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            values[i] = element[0];
        } else if (data.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            std::uint16_t value = 0;
            std::memcpy(&value, element, sizeof(value));
            values[i] = value;
        } else {
            std::memcpy(&values[i], element, sizeof(std::uint32_t));
        }
    }
    return values;
}

}  // namespace oer::mesh_detail
