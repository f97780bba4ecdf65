// EXT_meshopt_compression decoded by meshoptimizer (see gltf_meshopt.hpp).
#include "gltf_meshopt.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <meshoptimizer.h>

#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

constexpr const char* kMeshoptExtension = "EXT_meshopt_compression";

// One compressed view's extension object, as the specification names its members.
struct CompressedView {
    std::uint64_t buffer = 0;
    std::uint64_t byte_offset = 0;
    std::uint64_t byte_length = 0;
    std::uint64_t byte_stride = 0;
    std::uint64_t count = 0;
    std::string mode;
    std::string filter;
};

class MeshoptDecoder {
  public:
    MeshoptDecoder(tinygltf::Model& model, const std::string& asset, const MeshLimits& limits)
        : model_(model), asset_(asset), limits_(limits) {}

    void run() {
        for (std::size_t v = 0; v < model_.bufferViews.size(); ++v) {
            const auto found = model_.bufferViews[v].extensions.find(kMeshoptExtension);
            if (found != model_.bufferViews[v].extensions.end()) {
                decode(v, found->second);
            }
        }
    }

  private:
    void decode(std::size_t index, const tinygltf::Value& extension) {
        const std::string name = "bufferView " + std::to_string(index) + ": " + kMeshoptExtension;
        const CompressedView c = read(extension, name);
        check_mode(c, name);
        const std::vector<unsigned char>& source = compressed_bytes(c, name);
        tinygltf::BufferView& view = model_.bufferViews[index];
        // count <= 3 * max_triangles + 2 or max_vertices (a few million), stride <= 256.
        const std::uint64_t decoded_size = c.count * c.byte_stride;
        if (decoded_size > view.byteLength) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": count " + std::to_string(c.count) + " x byteStride " +
                     std::to_string(c.byte_stride) + " = " + std::to_string(decoded_size) +
                     " bytes, more than the view's byteLength " + std::to_string(view.byteLength));
        }
        if (c.mode == "ATTRIBUTES" && view.byteStride != 0 && view.byteStride != c.byte_stride) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": byteStride " + std::to_string(c.byte_stride) +
                     " differs from the view's own byteStride " + std::to_string(view.byteStride));
        }
        if (decoded_size > limits_.max_bytes - decoded_) {
            fail(ErrorKind::LimitExceeded, asset_,
                 name + ": decoding " + std::to_string(decoded_size) +
                     " bytes would take the asset's decoded views past the limit of " +
                     std::to_string(limits_.max_bytes) + " bytes");
        }
        decoded_ += decoded_size;
        compressed_ += c.byte_length;
        if (!within_decoding_ratio(decoded_, compressed_, kMeshoptDecodingRatio)) {
            fail(ErrorKind::LimitExceeded, asset_,
                 name + ": the compressed views would decode to " + std::to_string(decoded_) +
                     " bytes from " + std::to_string(compressed_) + ", more than " +
                     std::to_string(kMeshoptDecodingRatio) +
                     " times (a decompression bomb; real files decode to a few times theirs)");
        }
        const unsigned char* compressed = source.data() + c.byte_offset;
        tinygltf::Buffer decoded;
        decoded.data.resize(std::size_t(decoded_size));
        int result = 0;
        if (c.mode == "ATTRIBUTES") {
            result = meshopt_decodeVertexBuffer(decoded.data.data(), c.count, c.byte_stride,
                                                compressed, c.byte_length);
        } else if (c.mode == "TRIANGLES") {
            result = meshopt_decodeIndexBuffer(decoded.data.data(), c.count, c.byte_stride,
                                               compressed, c.byte_length);
        } else {
            result = meshopt_decodeIndexSequence(decoded.data.data(), c.count, c.byte_stride,
                                                 compressed, c.byte_length);
        }
        if (result != 0) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the compressed " + c.mode + " data is malformed (meshoptimizer " +
                     "says " + std::to_string(result) + ")");
        }
        if (c.filter == "OCTAHEDRAL") {
            meshopt_decodeFilterOct(decoded.data.data(), c.count, c.byte_stride);
        } else if (c.filter == "QUATERNION") {
            meshopt_decodeFilterQuat(decoded.data.data(), c.count, c.byte_stride);
        } else if (c.filter == "EXPONENTIAL") {
            meshopt_decodeFilterExp(decoded.data.data(), c.count, c.byte_stride);
        }
        model_.buffers.push_back(std::move(decoded));
        view.buffer = int(model_.buffers.size() - 1);
        view.byteOffset = 0;
        view.byteLength = std::size_t(decoded_size);
        view.extensions.erase(kMeshoptExtension);
    }

    CompressedView read(const tinygltf::Value& extension, const std::string& name) const {
        CompressedView c;
        c.buffer = integer_member(asset_, extension, "buffer", name);
        c.byte_offset = integer_member(asset_, extension, "byteOffset", name, 0);
        c.byte_length = integer_member(asset_, extension, "byteLength", name);
        c.byte_stride = integer_member(asset_, extension, "byteStride", name);
        c.count = integer_member(asset_, extension, "count", name);
        c.mode = string_member(asset_, extension, "mode", name);
        c.filter = string_member(asset_, extension, "filter", name, "NONE");
        return c;
    }

    // The specification's constraints ("Compressing bufferViews": modes, strides, filters),
    // which are also meshoptimizer's preconditions (its decoders assert them), and the limits
    // on what the count may make.
    void check_mode(const CompressedView& c, const std::string& name) const {
        const std::string stride = "byteStride " + std::to_string(c.byte_stride);
        if (c.mode == "ATTRIBUTES") {
            if (c.byte_stride == 0 || c.byte_stride > 256 || c.byte_stride % 4 != 0) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": " + stride +
                         " for mode ATTRIBUTES, which needs a multiple of 4 "
                         "up to 256");
            }
        } else if (c.mode == "TRIANGLES" || c.mode == "INDICES") {
            if (c.byte_stride != 2 && c.byte_stride != 4) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": " + stride + " for mode " + c.mode + ", which needs 2 or 4");
            }
            if (c.mode == "TRIANGLES" && c.count % 3 != 0) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": count " + std::to_string(c.count) +
                         " is not a multiple of 3 (mode TRIANGLES)");
            }
        } else {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": unknown mode '" + one_line(c.mode, 40) +
                     "' (ATTRIBUTES, TRIANGLES or INDICES)");
        }
        check_filter(c, name, stride);
        const bool attributes = c.mode == "ATTRIBUTES";
        const std::uint64_t max_count =
            attributes ? limits_.max_vertices : 3 * limits_.max_triangles + 2;
        if (c.count == 0 || c.count > max_count) {
            fail(c.count == 0 ? ErrorKind::InvalidInput : ErrorKind::LimitExceeded, asset_,
                 name + ": count " + std::to_string(c.count) +
                     (c.count == 0 ? " (no elements)"
                                   : std::string(", more than the limit of ") +
                                         (attributes ? "vertices" : "indices") + " allows"));
        }
    }

    void check_filter(const CompressedView& c, const std::string& name,
                      const std::string& stride) const {
        if (c.filter == "NONE") {
            return;
        }
        if (c.mode != "ATTRIBUTES") {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": filter " + one_line(c.filter, 40) + " with mode " + c.mode +
                     " (filters apply to ATTRIBUTES only)");
        }
        if (c.filter == "OCTAHEDRAL") {
            if (c.byte_stride != 4 && c.byte_stride != 8) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": " + stride + " for filter OCTAHEDRAL, which needs 4 or 8");
            }
        } else if (c.filter == "QUATERNION") {
            if (c.byte_stride != 8) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": " + stride + " for filter QUATERNION, which needs 8");
            }
        } else if (c.filter != "EXPONENTIAL") {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": unknown filter '" + one_line(c.filter, 40) +
                     "' (NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)");
        }
    }

    // The compressed bytes' buffer, checked to hold them.
    const std::vector<unsigned char>& compressed_bytes(const CompressedView& c,
                                                       const std::string& name) const {
        if (c.buffer >= model_.buffers.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": buffer " + std::to_string(c.buffer) + " does not exist");
        }
        if (is_fallback_buffer(model_, int(c.buffer))) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": buffer " + std::to_string(c.buffer) +
                     " is a fallback buffer, which holds no compressed data");
        }
        const std::vector<unsigned char>& data = model_.buffers[std::size_t(c.buffer)].data;
        if (c.byte_offset > data.size() || c.byte_length > data.size() - c.byte_offset) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": bytes " + std::to_string(c.byte_offset) + " to " +
                     std::to_string(c.byte_offset + c.byte_length) +
                     " run past the end of buffer " + std::to_string(c.buffer) + " (" +
                     std::to_string(data.size()) + " bytes)");
        }
        return data;
    }

    tinygltf::Model& model_;
    const std::string& asset_;
    const MeshLimits& limits_;
    std::uint64_t decoded_ = 0;     // bytes of every view decoded so far
    std::uint64_t compressed_ = 0;  // the compressed bytes they were decoded from
};

}  // namespace

bool is_fallback_buffer(const tinygltf::Model& model, int buffer) {
    if (buffer < 0 || std::size_t(buffer) >= model.buffers.size()) {
        return false;
    }
    const auto& extensions = model.buffers[std::size_t(buffer)].extensions;
    const auto found = extensions.find(kMeshoptExtension);
    return found != extensions.end() && found->second.IsObject() && found->second.Has("fallback") &&
           found->second.Get("fallback").IsBool() && found->second.Get("fallback").Get<bool>();
}

void decode_meshopt_views(tinygltf::Model& model, const std::string& asset,
                          const MeshLimits& limits) {
    MeshoptDecoder(model, asset, limits).run();
}

}  // namespace oer::mesh_detail
