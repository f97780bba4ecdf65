// KHR_draco_mesh_compression decoded by Draco (see gltf_draco.hpp).
#include "gltf_draco.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include <draco/compression/decode.h>

#include "gltf_accessors.hpp"
#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";

// What the Draco bitstream (version 2.2, "Draco Bitstream Specification": the header, then the
// connectivity of the sequential or the edgebreaker method) says before any data.
struct DracoHeader {
    bool edgebreaker = false;
    std::uint64_t faces = 0;
    std::uint64_t points = 0;  // sequential: the points; edgebreaker: the encoded vertices
};

class StreamReader {
  public:
    explicit StreamReader(std::span<const unsigned char> bytes) : bytes_(bytes) {}

    bool byte(std::uint8_t& out) {
        if (at_ >= bytes_.size()) {
            return false;
        }
        out = bytes_[at_++];
        return true;
    }

    // LEB128, as Draco's DecodeVarint: at most 5 bytes for 32 bits.
    bool varint(std::uint64_t& out) {
        out = 0;
        for (int shift = 0; shift < 35; shift += 7) {
            std::uint8_t b = 0;
            if (!byte(b)) {
                return false;
            }
            out |= std::uint64_t(b & 0x7f) << shift;
            if ((b & 0x80) == 0) {
                return out <= 0xffffffffu;
            }
        }
        return false;
    }

    bool skip(std::size_t n) {
        if (n > bytes_.size() - at_) {
            return false;
        }
        at_ += n;
        return true;
    }

  private:
    std::span<const unsigned char> bytes_;
    std::size_t at_ = 0;
};

class DracoDecoder {
  public:
    DracoDecoder(tinygltf::Model& model, const std::string& asset, const MeshLimits& limits)
        : model_(model), asset_(asset), limits_(limits) {}

    void run() {
        for (std::size_t m = 0; m < model_.meshes.size(); ++m) {
            auto& primitives = model_.meshes[m].primitives;
            for (std::size_t p = 0; p < primitives.size(); ++p) {
                const auto found = primitives[p].extensions.find(kDracoExtension);
                if (found == primitives[p].extensions.end()) {
                    continue;
                }
                const std::string& mesh_name = model_.meshes[m].name;
                const std::string name =
                    (mesh_name.empty() ? "mesh " + std::to_string(m)
                                       : "mesh '" + one_line(mesh_name, 80) + "'") +
                    " primitive " + std::to_string(p) + ": " + kDracoExtension;
                const tinygltf::Value extension = found->second;
                decode(primitives[p], extension, name);
                primitives[p].extensions.erase(kDracoExtension);
            }
        }
    }

  private:
    void decode(tinygltf::Primitive& primitive, const tinygltf::Value& extension,
                const std::string& name) {
        if (primitive.mode != TINYGLTF_MODE_TRIANGLES) {
            fail(ErrorKind::Unsupported, asset_,
                 name + ": mode " + std::to_string(primitive.mode) +
                     " (only TRIANGLES is supported with Draco)");
        }
        const std::map<std::string, std::uint32_t> ids = attribute_ids(primitive, extension, name);
        const std::span<const unsigned char> stream = stream_bytes(extension, name);
        const DracoHeader header = read_header(stream, name);
        check_counts(primitive, header, stream.size(), name);

        draco::DecoderBuffer buffer;
        buffer.Init(reinterpret_cast<const char*>(stream.data()), stream.size());
        draco::Decoder decoder;
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok()) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the Draco stream does not decode (" +
                     one_line(decoded.status().error_msg_string(), 200) + ")");
        }
        const draco::Mesh& mesh = *decoded.value();
        const std::uint64_t points = mesh.num_points();
        const std::uint64_t faces = mesh.num_faces();
        if (faces != header.faces || points > limits_.max_vertices - vertices_) {
            fail(ErrorKind::LimitExceeded, asset_,
                 name + ": the stream decodes to " + std::to_string(points) + " points and " +
                     std::to_string(faces) + " faces, more than the limits allow");
        }
        vertices_ += points;
        triangles_ += faces;
        for (const auto& [attribute, id] : ids) {
            const int accessor = primitive.attributes.at(attribute);
            primitive.attributes[attribute] =
                attribute_accessor(mesh, accessor, id, name + ": " + attribute);
        }
        primitive.indices = index_accessor(mesh, name);
    }

    // The extension's "attributes": each an attribute the primitive has, with the id of
    // Draco's attribute holding it.
    std::map<std::string, std::uint32_t> attribute_ids(const tinygltf::Primitive& primitive,
                                                       const tinygltf::Value& extension,
                                                       const std::string& name) const {
        if (!extension.IsObject() || !extension.Has("attributes") ||
            !extension.Get("attributes").IsObject()) {
            fail(ErrorKind::InvalidInput, asset_, name + ": attributes must be an object");
        }
        const tinygltf::Value& attributes = extension.Get("attributes");
        std::map<std::string, std::uint32_t> ids;
        for (const std::string& key : attributes.Keys()) {
            if (primitive.attributes.find(key) == primitive.attributes.end()) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": attribute " + one_line(key, 40) +
                         " is not one of the primitive's attributes");
            }
            const std::uint64_t id =
                integer_member(asset_, attributes, key.c_str(), name + ".attributes");
            if (id > 0xffffffffu) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": attribute " + one_line(key, 40) + " has id " + std::to_string(id));
            }
            ids[key] = std::uint32_t(id);
        }
        if (ids.find("POSITION") == ids.end()) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the stream has no POSITION (its attributes must name it)");
        }
        return ids;
    }

    std::span<const unsigned char> stream_bytes(const tinygltf::Value& extension,
                                                const std::string& name) const {
        const std::uint64_t index = integer_member(asset_, extension, "bufferView", name);
        if (index >= model_.bufferViews.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": bufferView " + std::to_string(index) + " does not exist");
        }
        const tinygltf::BufferView& view = model_.bufferViews[std::size_t(index)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": bufferView " + std::to_string(index) + " refers to buffer " +
                     std::to_string(view.buffer) + ", which does not exist");
        }
        const std::vector<unsigned char>& data = model_.buffers[std::size_t(view.buffer)].data;
        if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": bufferView " + std::to_string(index) + " runs past the end of buffer " +
                     std::to_string(view.buffer) + " (" + std::to_string(data.size()) + " bytes)");
        }
        return {data.data() + view.byteOffset, view.byteLength};
    }

    // The header and the connectivity's counts (Draco 1.5's MeshSequentialDecoder and
    // MeshEdgebreakerDecoderImpl::DecodeConnectivity read them in this order).
    DracoHeader read_header(std::span<const unsigned char> stream, const std::string& name) const {
        const auto malformed = [&](const std::string& why) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": not a valid Draco stream (" + why + ")");
        };
        if (stream.size() < 11 || std::memcmp(stream.data(), "DRACO", 5) != 0) {
            malformed("no DRACO header");
        }
        const unsigned major = stream[5];
        const unsigned minor = stream[6];
        if (major != 2 || minor != 2) {
            fail(ErrorKind::Unsupported, asset_,
                 name + ": Draco bitstream version " + std::to_string(major) + "." +
                     std::to_string(minor) +
                     " is not supported (only 2.2, which Draco 1.3 and later write)");
        }
        if (stream[7] != 1) {
            malformed("a point cloud, not a triangle mesh");
        }
        const std::uint16_t flags = std::uint16_t(stream[9] | (stream[10] << 8));
        if ((flags & 0x8000) != 0) {
            fail(ErrorKind::Unsupported, asset_,
                 name + ": Draco streams with metadata are not supported");
        }
        StreamReader reader(stream.subspan(11));
        DracoHeader header;
        header.edgebreaker = stream[8] == 1;
        if (stream[8] > 1) {
            malformed("unknown encoding method " + std::to_string(stream[8]));
        }
        bool ok = true;
        if (header.edgebreaker) {
            std::uint8_t traversal = 0;
            ok = reader.byte(traversal) && reader.varint(header.points) &&
                 reader.varint(header.faces);
        } else {
            ok = reader.varint(header.faces) && reader.varint(header.points);
        }
        if (!ok) {
            malformed("its connectivity header is truncated");
        }
        return header;
    }

    // The stream's counts against the accessors and the limits, and what it decodes to against
    // its size (with every stream before it), before decoding.
    void check_counts(const tinygltf::Primitive& primitive, const DracoHeader& header,
                      std::uint64_t stream_size, const std::string& name) {
        const std::uint64_t triangle_budget = limits_.max_triangles - triangles_;
        const std::uint64_t vertex_budget = limits_.max_vertices - vertices_;
        if (header.faces > triangle_budget || header.points > vertex_budget) {
            fail(ErrorKind::LimitExceeded, asset_,
                 name + ": the stream declares " + std::to_string(header.faces) + " faces and " +
                     std::to_string(header.points) + " points, more than the limits of " +
                     std::to_string(limits_.max_triangles) + " triangles and " +
                     std::to_string(limits_.max_vertices) + " vertices allow");
        }
        // What the decoded primitive holds: its indices, and each attribute per point.
        std::uint64_t point_bytes = 0;
        for (const auto& [attribute, index] : primitive.attributes) {
            const tinygltf::Accessor& described = accessor(index, name);
            point_bytes +=
                component_size(described.componentType) * component_count(described.type);
        }
        decoded_ += header.faces * 12 + header.points * point_bytes;
        compressed_ += stream_size;
        if (!within_decoding_ratio(decoded_, compressed_, kDracoDecodingRatio)) {
            fail(ErrorKind::LimitExceeded, asset_,
                 name + ": the Draco streams would decode to " + std::to_string(decoded_) +
                     " bytes from " + std::to_string(compressed_) + ", more than " +
                     std::to_string(kDracoDecodingRatio) +
                     " times (a decompression bomb; real files decode to a few times theirs)");
        }
        if (primitive.indices >= 0) {
            const std::uint64_t indices = accessor(primitive.indices, name).count;
            if (indices != 3 * header.faces) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": the stream declares " + std::to_string(header.faces) +
                         " faces, the indices accessor " + std::to_string(primitive.indices) +
                         " has " + std::to_string(indices) + " indices");
            }
        }
        const int position = primitive.attributes.at("POSITION");
        const std::uint64_t positions = accessor(position, name).count;
        if (header.edgebreaker ? header.points > positions : header.points != positions) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the stream declares " + std::to_string(header.points) +
                     (header.edgebreaker ? " encoded vertices" : " points") +
                     ", the POSITION accessor " + std::to_string(position) + " has " +
                     std::to_string(positions));
        }
    }

    const tinygltf::Accessor& accessor(int index, const std::string& name) const {
        if (index < 0 || std::size_t(index) >= model_.accessors.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": accessor " + std::to_string(index) + " does not exist");
        }
        return model_.accessors[std::size_t(index)];
    }

    // A new accessor for the decoded attribute `id`, of the type and component type of the
    // primitive's accessor `index` (the extension keeps those: "the accessor ... defines the
    // decoded data"), with the decoded count; returns its index.
    int attribute_accessor(const draco::Mesh& mesh, int index, std::uint32_t id,
                           const std::string& name) {
        tinygltf::Accessor described = accessor(index, name);
        const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(id);
        if (attribute == nullptr) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the stream has no attribute " + std::to_string(id));
        }
        const std::size_t components = component_count(described.type);
        const std::size_t size = component_size(described.componentType);
        if (components == 0 || size == 0 || attribute->num_components() != components) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the stream's attribute " + std::to_string(id) + " has " +
                     std::to_string(attribute->num_components()) + " components, its accessor " +
                     std::to_string(index) + " " + std::to_string(components));
        }
        const std::size_t points = mesh.num_points();
        std::vector<unsigned char> data(points * components * size);
        bool converted = true;
        for (std::size_t i = 0; i < points && converted; ++i) {
            const draco::AttributeValueIndex value =
                attribute->mapped_index(draco::PointIndex(std::uint32_t(i)));
            unsigned char* out = data.data() + i * components * size;
            converted =
                convert(*attribute, value, std::int8_t(components), described.componentType, out);
        }
        if (!converted) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": the stream's attribute " + std::to_string(id) +
                     " does not convert to its accessor's component type");
        }
        described.bufferView = add_view(std::move(data));
        described.byteOffset = 0;
        described.count = points;
        described.sparse.isSparse = false;
        model_.accessors.push_back(std::move(described));
        return int(model_.accessors.size() - 1);
    }

    static bool convert(const draco::PointAttribute& attribute, draco::AttributeValueIndex value,
                        std::int8_t components, int component_type, unsigned char* out) {
        switch (component_type) {
            case TINYGLTF_COMPONENT_TYPE_BYTE:
                return attribute.ConvertValue(value, components,
                                              reinterpret_cast<std::int8_t*>(out));
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return attribute.ConvertValue(value, components,
                                              reinterpret_cast<std::uint8_t*>(out));
            case TINYGLTF_COMPONENT_TYPE_SHORT:
                return attribute.ConvertValue(value, components,
                                              reinterpret_cast<std::int16_t*>(out));
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                return attribute.ConvertValue(value, components,
                                              reinterpret_cast<std::uint16_t*>(out));
            case TINYGLTF_COMPONENT_TYPE_FLOAT:
                return attribute.ConvertValue(value, components, reinterpret_cast<float*>(out));
            default:
                return false;
        }
    }

    // Draco's faces as a new accessor of UNSIGNED_INT; returns its index.
    int index_accessor(const draco::Mesh& mesh, const std::string& name) {
        const std::size_t faces = mesh.num_faces();
        if (faces == 0) {
            fail(ErrorKind::InvalidInput, asset_, name + ": the stream has no faces");
        }
        std::vector<unsigned char> data(faces * 3 * sizeof(std::uint32_t));
        for (std::size_t f = 0; f < faces; ++f) {
            const draco::Mesh::Face& face = mesh.face(draco::FaceIndex(std::uint32_t(f)));
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t index = face[k].value();
                std::memcpy(data.data() + (3 * f + std::size_t(k)) * sizeof(index), &index,
                            sizeof(index));
            }
        }
        tinygltf::Accessor indices;
        indices.bufferView = add_view(std::move(data));
        indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        indices.type = TINYGLTF_TYPE_SCALAR;
        indices.count = faces * 3;
        model_.accessors.push_back(std::move(indices));
        return int(model_.accessors.size() - 1);
    }

    // `data` as a new buffer and a view of all of it; returns the view's index.
    int add_view(std::vector<unsigned char> data) {
        tinygltf::BufferView view;
        view.byteLength = data.size();
        tinygltf::Buffer buffer;
        buffer.data = std::move(data);
        model_.buffers.push_back(std::move(buffer));
        view.buffer = int(model_.buffers.size() - 1);
        model_.bufferViews.push_back(std::move(view));
        return int(model_.bufferViews.size() - 1);
    }

    tinygltf::Model& model_;
    const std::string& asset_;
    const MeshLimits& limits_;
    std::uint64_t vertices_ = 0;    // decoded by every primitive so far
    std::uint64_t triangles_ = 0;   // likewise
    std::uint64_t decoded_ = 0;     // the bytes they decode to, from their header's counts
    std::uint64_t compressed_ = 0;  // the bytes of their streams
};

}  // namespace

void decode_draco_primitives(tinygltf::Model& model, const std::string& asset,
                             const MeshLimits& limits) {
    DracoDecoder(model, asset, limits).run();
}

}  // namespace oer::mesh_detail
