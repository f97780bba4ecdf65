// EXT_mesh_gpu_instancing (see gltf_instancing.hpp).
#include "gltf_instancing.hpp"

#include <cmath>
#include <cstddef>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gltf_accessors.hpp"
#include "gltf_primitives.hpp"
#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

constexpr const char* kInstancingExtension = "EXT_mesh_gpu_instancing";

// The triangles and vertices one copy of `mesh` declares (from its accessors' counts; a count
// the primitive reader will refuse counts as none here).
struct MeshSize {
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;
};

MeshSize declared_size(const tinygltf::Model& model, const tinygltf::Mesh& mesh) {
    const auto count_of = [&](int accessor) -> std::uint64_t {
        return accessor >= 0 && std::size_t(accessor) < model.accessors.size()
                   ? model.accessors[std::size_t(accessor)].count
                   : 0;
    };
    MeshSize size;
    for (const tinygltf::Primitive& primitive : mesh.primitives) {
        const auto position = primitive.attributes.find("POSITION");
        const std::uint64_t vertices =
            position == primitive.attributes.end() ? 0 : count_of(position->second);
        const std::uint64_t corners =
            primitive.indices >= 0 ? count_of(primitive.indices) : vertices;
        size.vertices += vertices;
        size.triangles += triangles_of(primitive.mode, corners);
    }
    return size;
}

// A * n would pass `budget`: no overflow.
bool exceeds(std::uint64_t n, std::uint64_t each, std::uint64_t budget) {
    return each != 0 && n > budget / each;
}

}  // namespace

std::vector<glm::dmat4> instance_transforms(const tinygltf::Model& model, int node,
                                            const tinygltf::Mesh& mesh,
                                            const std::string& mesh_name, const std::string& asset,
                                            const InstanceBudget& budget) {
    const auto& extensions = model.nodes[std::size_t(node)].extensions;
    const auto found = extensions.find(kInstancingExtension);
    if (found == extensions.end()) {
        return {glm::dmat4(1.0)};
    }
    const std::string name = "node " + std::to_string(node) + ": " + kInstancingExtension;
    const tinygltf::Value& extension = found->second;
    if (!extension.IsObject() || !extension.Has("attributes") ||
        !extension.Get("attributes").IsObject()) {
        fail(ErrorKind::InvalidInput, asset, name + ": attributes must be an object");
    }
    const tinygltf::Value& attributes = extension.Get("attributes");
    const std::string attributes_name = name + ".attributes";
    std::optional<std::uint64_t> count;
    const auto accessor_of = [&](const char* key) -> int {
        if (!attributes.Has(key)) {
            return -1;
        }
        const std::uint64_t index = integer_member(asset, attributes, key, attributes_name);
        if (index >= model.accessors.size()) {
            fail(ErrorKind::InvalidInput, asset,
                 attributes_name + "." + key + ": accessor " + std::to_string(index) +
                     " does not exist");
        }
        const std::uint64_t n = model.accessors[std::size_t(index)].count;
        if (count && *count != n) {
            fail(ErrorKind::InvalidInput, asset,
                 attributes_name + "." + key + " has " + std::to_string(n) +
                     " elements, the others " + std::to_string(*count));
        }
        count = n;
        return int(index);
    };
    const int translation = accessor_of("TRANSLATION");
    const int rotation = accessor_of("ROTATION");
    const int scale = accessor_of("SCALE");
    if (!count) {
        fail(ErrorKind::InvalidInput, asset,
             name + ": no TRANSLATION, ROTATION or SCALE (at least one is required)");
    }
    // Every instance is a copy: checked from the declared counts before anything is read.
    const MeshSize size = declared_size(model, mesh);
    const std::uint64_t instances = *count;
    if (exceeds(instances, mesh.primitives.size(), budget.primitives) ||
        exceeds(instances, size.triangles, budget.triangles) ||
        exceeds(instances, size.vertices, budget.vertices)) {
        fail(ErrorKind::LimitExceeded, asset,
             name + ": " + std::to_string(instances) + " instances of " + mesh_name + " (" +
                 std::to_string(mesh.primitives.size()) + " primitives, " +
                 std::to_string(size.triangles) + " triangles, " + std::to_string(size.vertices) +
                 " vertices each) would pass the limits on primitives, triangles or vertices");
    }
    const AccessorReader reader(model, asset);
    const std::uint64_t max_count = budget.primitives;  // each instance adds a primitive or more
    const auto read3 = [&](int accessor, const char* key, const AttributeFormat& format) {
        return accessor < 0 ? std::vector<glm::vec3>()
                            : reader.vec3(accessor, attributes_name + "." + key, format, max_count,
                                          "primitives");
    };
    const std::vector<glm::vec3> translations =
        read3(translation, "TRANSLATION", kTranslationFormat);
    const std::vector<glm::vec3> scales = read3(scale, "SCALE", kScaleFormat);
    const std::vector<glm::vec4> rotations =
        rotation < 0 ? std::vector<glm::vec4>()
                     : reader.vec4(rotation, attributes_name + ".ROTATION", kRotationFormat,
                                   max_count, "primitives");
    std::vector<glm::dmat4> transforms(std::size_t(instances), glm::dmat4(1.0));
    for (std::size_t i = 0; i < transforms.size(); ++i) {
        glm::dmat4 t(1.0);
        if (!translations.empty()) {
            t[3] = glm::dvec4(glm::dvec3(translations[i]), 1.0);
        }
        glm::dmat4 r(1.0);
        if (!rotations.empty()) {
            // (x, y, z, w) as glTF stores it; glm's constructor takes (w, x, y, z).
            const glm::dquat q(rotations[i].w, rotations[i].x, rotations[i].y, rotations[i].z);
            const double length = glm::length(q);
            if (!(length > 0.0) || !std::isfinite(length)) {
                fail(ErrorKind::InvalidInput, asset,
                     name + ": instance " + std::to_string(i) +
                         " has a rotation that is not a valid quaternion");
            }
            r = glm::mat4_cast(q / length);
        }
        glm::dmat4 s(1.0);
        if (!scales.empty()) {
            s[0][0] = scales[i].x;
            s[1][1] = scales[i].y;
            s[2][2] = scales[i].z;
        }
        transforms[i] = t * r * s;
        for (int c = 0; c < 4; ++c) {
            for (int row = 0; row < 4; ++row) {
                if (!std::isfinite(transforms[i][c][row])) {
                    fail(ErrorKind::InvalidInput, asset,
                         name + ": instance " + std::to_string(i) +
                             " has a transform that is "
                             "not finite");
                }
            }
        }
    }
    return transforms;
}

}  // namespace oer::mesh_detail
