// glTF 2.0 (see oer/mesh_loading.hpp): the model parsed by tinygltf (gltf_parsing.hpp)
// becomes an oer::Mesh. The scene's node graph is walked (cycles, shared nodes and excessive
// depth refused), every node's transform baked into positions, normals and tangents (a
// mirroring one flips the winding back), strips and fans become lists, lines and points are
// refused, and the materials used are converted to the glTF 2.0 metallic-roughness model
// (specification, section 3.9): factors, the five textures (each image decoded once per
// encoding it is used with, within the limits), their samplers (section 5.26) and
// KHR_texture_transform, KHR_materials_emissive_strength, alpha modes and double-sidedness.
// TANGENT is read only where a normal texture needs it; finish_mesh generates it where the
// file has none.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gltf_accessors.hpp"
#include "gltf_parsing.hpp"
#include "mesh_errors.hpp"
#include "mesh_finishing.hpp"
#include "mesh_loaders.hpp"
#include "oer/core/error.hpp"
#include "texture_decoding.hpp"

namespace oer::mesh_detail {

namespace {

// ---------------------------------------------------------------------------------------------
// Primitive modes.

const char* mode_name(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS:
            return "POINTS";
        case TINYGLTF_MODE_LINE:
            return "LINES";
        case TINYGLTF_MODE_LINE_LOOP:
            return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP:
            return "LINE_STRIP";
        case TINYGLTF_MODE_TRIANGLES:
            return "TRIANGLES";
        case TINYGLTF_MODE_TRIANGLE_STRIP:
            return "TRIANGLE_STRIP";
        case TINYGLTF_MODE_TRIANGLE_FAN:
            return "TRIANGLE_FAN";
        default:
            return nullptr;
    }
}

// How many triangles `count` vertices (or indices) make in `mode`.
std::uint64_t triangles_of(int mode, std::uint64_t count) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        return count / 3;
    }
    return count >= 3 ? count - 2 : 0;
}

// A strip or a fan as a list, in the order of the glTF 2.0 specification (Meshes), which keeps
// every triangle's winding: strip triangle i is (i, i + 1 + i % 2, i + 2 - i % 2), fan
// triangle i is (i + 1, i + 2, 0).
std::vector<std::uint32_t> to_triangle_list(int mode, const std::vector<std::uint32_t>& in) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        return in;
    }
    std::vector<std::uint32_t> out;
    if (in.size() < 3) {
        return out;
    }
    out.reserve((in.size() - 2) * 3);
    for (std::size_t i = 0; i + 2 < in.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            const std::size_t odd = i % 2;
            out.insert(out.end(), {in[i], in[i + 1 + odd], in[i + 2 - odd]});
        } else {
            out.insert(out.end(), {in[i + 1], in[i + 2], in[0]});
        }
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// The conversion.

// A number as its shortest decimal text, for messages.
std::string number_text(double value) {
    std::array<char, 32> buffer{};
    const auto written = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), written.ptr);
}

bool finite_matrix(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) {
                return false;
            }
        }
    }
    return true;
}

class GltfConverter {
  public:
    GltfConverter(const tinygltf::Model& model, ParseContext& context, const MeshLimits& limits)
        : model_(model),
          context_(context),
          limits_(limits),
          asset_(context.asset),
          reader_(model, context.asset),
          material_slot_(model.materials.size(), -1),
          material_without_normal_slot_(model.materials.size(), -1),
          image_slot_(model.images.size(), {-1, -1}) {}

    Mesh convert() {
        std::vector<int> roots = root_nodes();
        marks_.assign(model_.nodes.size(), Mark::None);
        for (int root : roots) {
            traverse(root);
        }
        if (mesh_.materials.empty()) {
            mesh_.materials.push_back(default_material());
        }
        for (const std::string& extension : model_.extensionsUsed) {
            if (!supported_extension(extension)) {
                mesh_.warnings.push_back("the asset uses the extension " + one_line(extension, 80) +
                                         ", which is not supported: ignored");
            }
        }
        if (!context_.warnings.empty()) {
            mesh_.warnings.push_back("tinygltf: " + one_line(context_.warnings));
        }
        return std::move(mesh_);
    }

  private:
    enum class Mark : unsigned char { None, Active, Done };

    struct Frame {
        int node;
        glm::dmat4 world;
        int depth;
        std::size_t next_child;
    };

    std::vector<int> root_nodes() const {
        if (!model_.scenes.empty()) {
            const int scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (std::size_t(scene) >= model_.scenes.size()) {
                fail(ErrorKind::InvalidInput, asset_,
                     "the default scene " + std::to_string(scene) + " does not exist");
            }
            return model_.scenes[std::size_t(scene)].nodes;
        }
        // No scene: every node that is nobody's child.
        std::vector<bool> is_child(model_.nodes.size(), false);
        for (std::size_t n = 0; n < model_.nodes.size(); ++n) {
            for (int child : model_.nodes[n].children) {
                check_node_exists(child, "node " + std::to_string(n) + " has child");
                is_child[std::size_t(child)] = true;
            }
        }
        std::vector<int> roots;
        for (std::size_t n = 0; n < model_.nodes.size(); ++n) {
            if (!is_child[n]) {
                roots.push_back(int(n));
            }
        }
        if (roots.empty() && !model_.nodes.empty()) {
            roots.push_back(0);  // every node has a parent: there is a cycle, found from here
        }
        return roots;
    }

    void check_node_exists(int node, const std::string& referrer) const {
        if (node < 0 || std::size_t(node) >= model_.nodes.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 referrer + " " + std::to_string(node) + ", which does not exist");
        }
    }

    // Depth-first, with an explicit stack: a node met again while on the stack is a cycle,
    // met again after it was done, a node with two parents (both invalid glTF).
    void traverse(int root) {
        std::vector<Frame> stack;
        enter(root, glm::dmat4(1.0), 0, "the scene lists node", stack);
        while (!stack.empty()) {
            Frame& top = stack.back();
            const std::vector<int>& children = model_.nodes[std::size_t(top.node)].children;
            if (top.next_child < children.size()) {
                const int child = children[top.next_child++];
                const glm::dmat4 world = top.world;
                const int depth = top.depth + 1;
                enter(child, world, depth, "node " + std::to_string(top.node) + " has child",
                      stack);
            } else {
                marks_[std::size_t(top.node)] = Mark::Done;
                stack.pop_back();
            }
        }
    }

    void enter(int node, const glm::dmat4& parent, int depth, const std::string& referrer,
               std::vector<Frame>& stack) {
        check_node_exists(node, referrer);
        const Mark mark = marks_[std::size_t(node)];
        if (mark == Mark::Active) {
            fail(ErrorKind::InvalidInput, asset_,
                 "node graph has a cycle at node " + std::to_string(node));
        }
        if (mark == Mark::Done) {
            fail(ErrorKind::InvalidInput, asset_,
                 "node " + std::to_string(node) +
                     " is reached twice (it has two parents, or is a root and a child)");
        }
        if (depth > limits_.max_node_depth) {
            fail(ErrorKind::LimitExceeded, asset_,
                 "node graph deeper than " + std::to_string(limits_.max_node_depth) +
                     " levels at node " + std::to_string(node));
        }
        marks_[std::size_t(node)] = Mark::Active;
        const glm::dmat4 world = parent * local_transform(node);
        const int mesh = model_.nodes[std::size_t(node)].mesh;
        if (mesh >= 0) {
            instantiate(mesh, node, world);
        }
        stack.push_back(Frame{node, world, depth, 0});
    }

    glm::dmat4 local_transform(int index) const {
        const tinygltf::Node& node = model_.nodes[std::size_t(index)];
        const std::string name = "node " + std::to_string(index);
        glm::dmat4 local(1.0);
        if (!node.matrix.empty()) {
            if (node.matrix.size() != 16) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": matrix has " + std::to_string(node.matrix.size()) +
                         " numbers, not 16");
            }
            local = glm::make_mat4(node.matrix.data());  // column-major, as glTF
        } else {
            glm::dmat4 translation(1.0);
            glm::dmat4 rotation(1.0);
            glm::dmat4 scale(1.0);
            if (!node.translation.empty()) {
                if (node.translation.size() != 3) {
                    fail(ErrorKind::InvalidInput, asset_, name + ": translation needs 3 numbers");
                }
                translation[3] =
                    glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
            }
            if (!node.rotation.empty()) {
                if (node.rotation.size() != 4) {
                    fail(ErrorKind::InvalidInput, asset_, name + ": rotation needs 4 numbers");
                }
                // glTF stores (x, y, z, w); glm's constructor takes (w, x, y, z).
                const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1],
                                   node.rotation[2]);
                const double length = glm::length(q);
                if (!(length > 0.0) || !std::isfinite(length)) {
                    fail(ErrorKind::InvalidInput, asset_,
                         name + ": rotation is not a valid quaternion");
                }
                rotation = glm::mat4_cast(q / length);
            }
            if (!node.scale.empty()) {
                if (node.scale.size() != 3) {
                    fail(ErrorKind::InvalidInput, asset_, name + ": scale needs 3 numbers");
                }
                scale[0][0] = node.scale[0];
                scale[1][1] = node.scale[1];
                scale[2][2] = node.scale[2];
            }
            local = translation * rotation * scale;
        }
        if (!finite_matrix(local)) {
            fail(ErrorKind::InvalidInput, asset_, name + ": transform is not finite");
        }
        return local;
    }

    void instantiate(int mesh_index, int node, const glm::dmat4& world) {
        if (std::size_t(mesh_index) >= model_.meshes.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 "node " + std::to_string(node) + " refers to mesh " + std::to_string(mesh_index) +
                     ", which does not exist");
        }
        const tinygltf::Mesh& mesh = model_.meshes[std::size_t(mesh_index)];
        const std::string mesh_name = mesh.name.empty() ? "mesh " + std::to_string(mesh_index)
                                                        : "mesh '" + one_line(mesh.name, 80) + "'";
        if (mesh.primitives.empty()) {
            fail(ErrorKind::InvalidInput, asset_, mesh_name + " has no primitives");
        }
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const std::string name = mesh_name + " primitive " + std::to_string(p);
            if (mesh_.primitives.size() >= limits_.max_primitives) {
                fail(ErrorKind::LimitExceeded, asset_,
                     "more than the limit of " + std::to_string(limits_.max_primitives) +
                         " primitives (counting every node's instance)");
            }
            Primitive primitive = build(mesh.primitives[p], name, world);
            if (!primitive.indices.empty()) {
                mesh_.primitives.push_back(std::move(primitive));
            } else {
                mesh_.warnings.push_back(name + " has no triangles and was left out");
            }
        }
    }

    Primitive build(const tinygltf::Primitive& source, const std::string& name,
                    const glm::dmat4& world) {
        const char* mode = mode_name(source.mode);
        if (mode == nullptr) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": unknown mode " + std::to_string(source.mode));
        }
        if (source.mode != TINYGLTF_MODE_TRIANGLES && source.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            source.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            fail(ErrorKind::Unsupported, asset_,
                 name + ": mode " + mode + " is not supported (only triangles)");
        }
        const auto position = source.attributes.find("POSITION");
        if (position == source.attributes.end()) {
            fail(ErrorKind::InvalidInput, asset_, name + ": no POSITION attribute");
        }
        const std::uint64_t vertex_budget = limits_.max_vertices - vertices_;
        Primitive primitive;
        primitive.name = name;
        primitive.positions =
            reader_.vec3(position->second, name + ": POSITION", vertex_budget, "vertices");
        const std::size_t n = primitive.positions.size();
        const auto check_count = [&](std::size_t count, const char* attribute) {
            if (count != n) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": " + attribute + " has " + std::to_string(count) +
                         " elements, POSITION " + std::to_string(n));
            }
        };
        if (const auto normal = source.attributes.find("NORMAL");
            normal != source.attributes.end()) {
            primitive.normals =
                reader_.vec3(normal->second, name + ": NORMAL", vertex_budget, "vertices");
            check_count(primitive.normals.size(), "NORMAL");
        }
        if (const auto texcoord = source.attributes.find("TEXCOORD_0");
            texcoord != source.attributes.end()) {
            primitive.texcoords = reader_.texcoords(texcoord->second, name + ": TEXCOORD_0",
                                                    vertex_budget, "vertices");
            check_count(primitive.texcoords.size(), "TEXCOORD_0");
        }

        const std::uint64_t triangle_budget = limits_.max_triangles - triangles_;
        // A strip of t triangles has t + 2 indices; no overflow for any budget.
        const std::uint64_t index_budget =
            triangle_budget > (std::numeric_limits<std::uint64_t>::max() - 2) / 3
                ? std::numeric_limits<std::uint64_t>::max()
                : triangle_budget * 3 + 2;
        std::vector<std::uint32_t> indices;
        if (source.indices >= 0) {
            indices =
                reader_.indices(source.indices, name + ": indices", index_budget, "triangles");
        } else {
            indices.resize(n);
            for (std::size_t i = 0; i < n; ++i) {
                indices[i] = std::uint32_t(i);
            }
        }
        if (source.mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": " + (source.indices >= 0 ? "index" : "vertex") + " count " +
                     std::to_string(indices.size()) + " is not a multiple of 3 (mode TRIANGLES)");
        }
        const std::uint64_t triangles = triangles_of(source.mode, indices.size());
        if (triangles > triangle_budget) {
            fail(ErrorKind::LimitExceeded, asset_,
                 name + ": more than the limit of " + std::to_string(limits_.max_triangles) +
                     " triangles");
        }
        for (std::uint32_t index : indices) {
            if (index >= n) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": index " + std::to_string(index) + " out of range (" +
                         std::to_string(n) + " vertices)");
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec3& p = primitive.positions[i];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                fail(ErrorKind::InvalidInput, asset_,
                     name + ": vertex " + std::to_string(i) + " has a non-finite position (" +
                         std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                         std::to_string(p.z) + ")");
            }
        }
        primitive.indices = to_triangle_list(source.mode, indices);
        triangles_ += triangles;
        vertices_ += n;

        bake(primitive, world);
        primitive.material = material(source.material, name);
        if (mesh_.materials[std::size_t(primitive.material)].normal_texture.present()) {
            const auto tangent = source.attributes.find("TANGENT");
            if (primitive.texcoords.empty()) {
                primitive.material =
                    material_without_normal_texture(source.material, primitive.material, name);
            } else if (tangent != source.attributes.end()) {
                primitive.tangents = file_tangents(tangent->second, name, n, vertex_budget);
                bake_tangents(primitive.tangents, world);
            }
        }
        return primitive;
    }

    // TANGENT (read only where a normal texture needs it): VEC4 of FLOAT, one per position,
    // finite; xyz made unit; w, the bitangent's sign, must be +1 or -1 (within 1e-3, then
    // made exact).
    std::vector<glm::vec4> file_tangents(int accessor, const std::string& name, std::size_t n,
                                         std::uint64_t vertex_budget) const {
        std::vector<glm::vec4> tangents =
            reader_.vec4(accessor, name + ": TANGENT", vertex_budget, "vertices");
        if (tangents.size() != n) {
            fail(ErrorKind::InvalidInput, asset_,
                 name + ": TANGENT has " + std::to_string(tangents.size()) +
                     " elements, POSITION " + std::to_string(n));
        }
        for (std::size_t i = 0; i < n; ++i) {
            glm::vec4& t = tangents[i];
            const std::string vertex = name + ": vertex " + std::to_string(i);
            if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) ||
                !std::isfinite(t.w)) {
                fail(ErrorKind::InvalidInput, asset_, vertex + " has a non-finite TANGENT");
            }
            const float length = glm::length(glm::vec3(t));
            if (!(length > 1e-6f) || !std::isfinite(length)) {
                fail(ErrorKind::InvalidInput, asset_, vertex + " has a zero-length TANGENT");
            }
            if (std::abs(std::abs(t.w) - 1.0f) > 1e-3f) {
                fail(ErrorKind::InvalidInput, asset_,
                     vertex + " has TANGENT w = " + number_text(t.w) +
                         ", not +1 or -1 (the bitangent's sign)");
            }
            t = glm::vec4(glm::vec3(t) / length, t.w < 0.0f ? -1.0f : 1.0f);
        }
        return tangents;
    }

    // Tangents by the node's linear part (a tangent is a difference of positions, so not by
    // the inverse transpose), made unit. The frame (tangent, bitangent, normal) transformed by
    // M changes handedness with the sign of det(M) (the transformed normal stays on the side of
    // M n), so a mirroring transform flips w. A flattening transform leaves no tangent: they
    // are dropped, for finish_mesh to generate.
    static void bake_tangents(std::vector<glm::vec4>& tangents, const glm::dmat4& world) {
        const glm::dmat3 linear(world);
        const double determinant = glm::determinant(linear);
        if (determinant == 0.0 || !std::isfinite(determinant)) {
            tangents.clear();
            return;
        }
        const float sign = determinant < 0.0 ? -1.0f : 1.0f;
        for (glm::vec4& tangent : tangents) {
            const glm::dvec3 turned = linear * glm::dvec3(glm::vec3(tangent));
            const double length = glm::length(turned);
            if (!(length > 0.0) || !std::isfinite(length)) {
                tangents.clear();
                return;
            }
            tangent = glm::vec4(glm::vec3(turned / length), sign * tangent.w);
        }
    }

    // Positions by the node's world matrix, normals by its inverse transpose; a mirroring
    // transform turns the triangles inside out, so their winding is flipped back.
    void bake(Primitive& primitive, const glm::dmat4& world) {
        for (glm::vec3& p : primitive.positions) {
            p = glm::vec3(world * glm::dvec4(glm::dvec3(p), 1.0));
        }
        const glm::dmat3 linear(world);
        const double determinant = glm::determinant(linear);
        if (!primitive.normals.empty()) {
            mesh_.repairs.normals_renormalised += normalise_file_normals(primitive.normals);
            if (determinant == 0.0 || !std::isfinite(determinant)) {
                // A flattening transform: no normal survives it; finish_mesh computes them.
                std::fill(primitive.normals.begin(), primitive.normals.end(), glm::vec3(0.0f));
            } else {
                const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
                for (glm::vec3& normal : primitive.normals) {
                    if (normal == glm::vec3(0.0f)) {
                        continue;  // bad in the file: computed later
                    }
                    const glm::dvec3 turned = normal_matrix * glm::dvec3(normal);
                    const double length = glm::length(turned);
                    normal = length > 0.0 && std::isfinite(length) ? glm::vec3(turned / length)
                                                                   : glm::vec3(0.0f);
                }
            }
        }
        if (determinant < 0.0) {
            for (std::size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
                std::swap(primitive.indices[t + 1], primitive.indices[t + 2]);
            }
        }
    }

    static Material default_material() {
        Material material;
        material.name = "default (glTF)";
        return material;  // glTF defaults: white, metallic 1, roughness 1, opaque, one-sided
    }

    int material(int index, const std::string& primitive) {
        if (index < 0) {
            if (default_slot_ < 0) {
                default_slot_ = int(mesh_.materials.size());
                mesh_.materials.push_back(default_material());
            }
            return default_slot_;
        }
        if (std::size_t(index) >= model_.materials.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 primitive + ": material " + std::to_string(index) + " does not exist");
        }
        int& slot = material_slot_[std::size_t(index)];
        if (slot < 0) {
            Material converted = convert_material(index);
            slot = int(mesh_.materials.size());
            mesh_.materials.push_back(std::move(converted));
        }
        return slot;
    }

    // The glTF material `index` (already converted, at `slot`) without its normal texture, for
    // a primitive that has no TEXCOORD_0 to map it with.
    int material_without_normal_texture(int index, int slot, const std::string& primitive) {
        const Material& with = mesh_.materials[std::size_t(slot)];
        mesh_.warnings.push_back(primitive + " has no TEXCOORD_0 for the normal texture of " +
                                 "material '" + one_line(with.name, 80) +
                                 "': normal texture ignored on it");
        int& variant = material_without_normal_slot_[std::size_t(index)];
        if (variant < 0) {
            Material without = with;
            without.name += " (without its normal texture)";
            without.normal_texture = TextureReference{};
            without.normal_scale = 1.0f;
            variant = int(mesh_.materials.size());
            mesh_.materials.push_back(std::move(without));
        }
        return variant;
    }

    // A factor the specification bounds to [0, 1]: clamped, as before.
    float unit_factor(double value, const std::string& what) const {
        if (!std::isfinite(value)) {
            fail(ErrorKind::InvalidInput, asset_, what + " is not finite");
        }
        return float(std::clamp(value, 0.0, 1.0));
    }

    // Any other number: it must be finite as the float it is stored in.
    float finite_float(double value, const std::string& what) const {
        const auto stored = float(value);
        if (!std::isfinite(value) || !std::isfinite(stored)) {
            fail(ErrorKind::InvalidInput, asset_,
                 what + " " + number_text(value) + " is not finite as a 32-bit float");
        }
        return stored;
    }

    float non_negative_float(double value, const std::string& what) const {
        const float stored = finite_float(value, what);
        if (stored < 0.0f) {
            fail(ErrorKind::InvalidInput, asset_,
                 what + " " + number_text(value) + " is negative (it must be at least 0)");
        }
        return stored;
    }

    // A textureInfo of any of its three kinds (the normal and occlusion ones add a number).
    struct TextureUse {
        const char* property;  // "baseColorTexture", ...
        int index = -1;
        int tex_coord = 0;
        const tinygltf::ExtensionMap* extensions = nullptr;

        template <typename Info>
        static TextureUse of(const Info& info, const char* property) {
            return TextureUse{property, info.index, info.texCoord, &info.extensions};
        }
    };

    Material convert_material(int index) {
        const tinygltf::Material& source = model_.materials[std::size_t(index)];
        const std::string name = source.name.empty()
                                     ? "material " + std::to_string(index)
                                     : "material '" + one_line(source.name, 80) + "'";
        const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
        Material material;
        material.name = source.name.empty() ? name : source.name;
        material.model = ShadingModel::MetallicRoughness;
        if (pbr.baseColorFactor.size() != 4) {
            fail(ErrorKind::InvalidInput, asset_, name + ": baseColorFactor needs 4 numbers");
        }
        for (int c = 0; c < 4; ++c) {
            material.base_color[c] =
                unit_factor(pbr.baseColorFactor[std::size_t(c)], name + ": baseColorFactor");
        }
        material.metallic = unit_factor(pbr.metallicFactor, name + ": metallicFactor");
        material.roughness = unit_factor(pbr.roughnessFactor, name + ": roughnessFactor");
        material.base_color_texture = texture_reference(
            TextureUse::of(pbr.baseColorTexture, "baseColorTexture"), TextureEncoding::Srgb, name);
        material.metallic_roughness_texture = texture_reference(
            TextureUse::of(pbr.metallicRoughnessTexture, "metallicRoughnessTexture"),
            TextureEncoding::Linear, name);
        material.normal_texture = texture_reference(
            TextureUse::of(source.normalTexture, "normalTexture"), TextureEncoding::Linear, name);
        material.normal_scale =
            finite_float(source.normalTexture.scale, name + ": normalTexture.scale");
        material.occlusion_texture =
            texture_reference(TextureUse::of(source.occlusionTexture, "occlusionTexture"),
                              TextureEncoding::Linear, name);
        material.occlusion_strength =
            unit_factor(source.occlusionTexture.strength, name + ": occlusionTexture.strength");
        if (source.emissiveFactor.size() != 3) {
            fail(ErrorKind::InvalidInput, asset_, name + ": emissiveFactor needs 3 numbers");
        }
        for (int c = 0; c < 3; ++c) {
            material.emissive[c] =
                unit_factor(source.emissiveFactor[std::size_t(c)], name + ": emissiveFactor");
        }
        material.emissive_texture = texture_reference(
            TextureUse::of(source.emissiveTexture, "emissiveTexture"), TextureEncoding::Srgb, name);
        if (const auto strength = source.extensions.find("KHR_materials_emissive_strength");
            strength != source.extensions.end() && strength->second.Has("emissiveStrength")) {
            material.emissive_strength =
                non_negative_float(strength->second.Get("emissiveStrength").GetNumberAsDouble(),
                                   name + ": KHR_materials_emissive_strength.emissiveStrength");
        }
        material.alpha_mode = alpha_mode(source.alphaMode, name);
        material.alpha_cutoff = non_negative_float(source.alphaCutoff, name + ": alphaCutoff");
        material.double_sided = source.doubleSided;
        return material;
    }

    AlphaMode alpha_mode(const std::string& mode, const std::string& material) const {
        if (mode == "OPAQUE") {
            return AlphaMode::Opaque;
        }
        if (mode == "MASK") {
            return AlphaMode::Mask;
        }
        if (mode == "BLEND") {
            return AlphaMode::Blend;
        }
        fail(ErrorKind::InvalidInput, asset_,
             material + ": alphaMode '" + one_line(mode, 40) +
                 "' is not one of OPAQUE, MASK and BLEND");
    }

    TextureReference texture_reference(const TextureUse& use, TextureEncoding encoding,
                                       const std::string& material) {
        TextureReference reference;
        if (use.index < 0) {
            return reference;
        }
        const std::string what = material + ": " + use.property;
        if (std::size_t(use.index) >= model_.textures.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 what + " refers to texture " + std::to_string(use.index) +
                     ", which does not exist");
        }
        int tex_coord = use.tex_coord;
        std::string override_note;
        if (const auto transform = use.extensions->find("KHR_texture_transform");
            transform != use.extensions->end()) {
            const tinygltf::Value& t = transform->second;
            const std::string at = what + ".extensions.KHR_texture_transform.";
            if (t.Has("offset")) {
                reference.offset = vec2_of(t.Get("offset"), at + "offset");
            }
            if (t.Has("rotation")) {
                reference.rotation =
                    finite_float(t.Get("rotation").GetNumberAsDouble(), at + "rotation");
            }
            if (t.Has("scale")) {
                reference.scale = vec2_of(t.Get("scale"), at + "scale");
            }
            if (t.Has("texCoord")) {
                tex_coord = t.Get("texCoord").GetNumberAsInt();
                override_note = " (KHR_texture_transform's texCoord)";
            }
        }
        if (tex_coord != 0) {
            mesh_.warnings.push_back(what + " uses TEXCOORD_" + std::to_string(tex_coord) +
                                     override_note +
                                     ", only TEXCOORD_0 is supported: texture ignored");
            return TextureReference{};
        }
        const tinygltf::Texture& texture = model_.textures[std::size_t(use.index)];
        const int image = texture.source;
        if (image < 0) {
            mesh_.warnings.push_back(what + " (texture " + std::to_string(use.index) +
                                     ") has no PNG or JPEG source: texture ignored");
            return TextureReference{};
        }
        if (std::size_t(image) >= model_.images.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 what + ": texture " + std::to_string(use.index) + " refers to image " +
                     std::to_string(image) + ", which does not exist");
        }
        reference.sampler =
            sampler(texture.sampler, what + ": texture " + std::to_string(use.index));
        reference.texture = decoded_texture(image, encoding);
        return reference;
    }

    glm::vec2 vec2_of(const tinygltf::Value& value, const std::string& what) const {
        if (!value.IsArray() || value.ArrayLen() != 2) {
            fail(ErrorKind::InvalidInput, asset_, what + " needs 2 numbers");
        }
        return glm::vec2(finite_float(value.Get(0).GetNumberAsDouble(), what),
                         finite_float(value.Get(1).GetNumberAsDouble(), what));
    }

    // glTF 2.0 samplers (section 5.26): the WebGL enums; an absent filter keeps the default.
    // `texture` names the user in messages ("material 'M': normalTexture: texture 2").
    TextureSampler sampler(int index, const std::string& texture) const {
        TextureSampler result;
        if (index < 0) {
            return result;
        }
        if (std::size_t(index) >= model_.samplers.size()) {
            fail(
                ErrorKind::InvalidInput, asset_,
                texture + " refers to sampler " + std::to_string(index) + ", which does not exist");
        }
        const tinygltf::Sampler& source = model_.samplers[std::size_t(index)];
        const std::string what = "sampler " + std::to_string(index) + ": ";
        result.wrap_s = wrap(source.wrapS, what + "wrapS");
        result.wrap_t = wrap(source.wrapT, what + "wrapT");
        if (source.magFilter >= 0) {
            result.mag_filter = filter(source.magFilter, false, what + "magFilter");
        }
        if (source.minFilter >= 0) {
            result.min_filter = filter(source.minFilter, true, what + "minFilter");
        }
        return result;
    }

    TextureWrap wrap(int value, const std::string& what) const {
        switch (value) {
            case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
                return TextureWrap::ClampToEdge;
            case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
                return TextureWrap::MirroredRepeat;
            case TINYGLTF_TEXTURE_WRAP_REPEAT:
                return TextureWrap::Repeat;
            default:
                fail(ErrorKind::InvalidInput, asset_,
                     what + " " + std::to_string(value) +
                         " is not one of CLAMP_TO_EDGE (33071), MIRRORED_REPEAT (33648) and "
                         "REPEAT (10497)");
        }
    }

    TextureFilter filter(int value, bool minification, const std::string& what) const {
        switch (value) {
            case TINYGLTF_TEXTURE_FILTER_NEAREST:
                return TextureFilter::Nearest;
            case TINYGLTF_TEXTURE_FILTER_LINEAR:
                return TextureFilter::Linear;
            default:
                break;
        }
        if (minification) {
            switch (value) {
                case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
                    return TextureFilter::NearestMipmapNearest;
                case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
                    return TextureFilter::LinearMipmapNearest;
                case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
                    return TextureFilter::NearestMipmapLinear;
                case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR:
                    return TextureFilter::LinearMipmapLinear;
                default:
                    break;
            }
        }
        fail(ErrorKind::InvalidInput, asset_,
             what + " " + std::to_string(value) +
                 (minification ? " is not one of NEAREST (9728), LINEAR (9729) and the mipmap "
                                 "filters 9984 to 9987"
                               : " is not one of NEAREST (9728) and LINEAR (9729)"));
    }

    // One texture per image and encoding: an image read both as colour and as data is
    // decoded once and stored twice, and counts twice against the limit on texture pixels.
    int decoded_texture(int image, TextureEncoding encoding) {
        std::array<int, 2>& slots = image_slot_[std::size_t(image)];
        const std::size_t kind = encoding == TextureEncoding::Srgb ? 0 : 1;
        if (slots[kind] >= 0) {
            return slots[kind];
        }
        const auto encoded = context_.encoded_images.find(image);
        if (encoded == context_.encoded_images.end()) {
            fail(ErrorKind::Internal, asset_,
                 "image " + std::to_string(image) + " was not kept while parsing");
        }
        const std::string label =
            image_label(asset_, image, model_.images[std::size_t(image)].name);
        const ImageHeader header =
            check_image_header(encoded->second, limits_.max_texture_pixels, label);
        const std::uint64_t pixels = std::uint64_t(header.width) * std::uint64_t(header.height);
        if (pixels > limits_.max_total_texture_pixels - texture_pixels_) {
            fail(ErrorKind::LimitExceeded, asset_,
                 "the textures together (an image used both as colour and as data counting "
                 "twice) have more than the limit of " +
                     std::to_string(limits_.max_total_texture_pixels) + " pixels");
        }
        const int other = slots[1 - kind];
        Texture texture = other >= 0
                              ? mesh_.textures[std::size_t(other)]
                              : decode_texture(encoded->second, limits_.max_texture_pixels, label);
        texture.encoding = encoding;
        mesh_.textures.push_back(std::move(texture));
        texture_pixels_ += pixels;
        slots[kind] = int(mesh_.textures.size()) - 1;
        return slots[kind];
    }

    const tinygltf::Model& model_;
    ParseContext& context_;
    const MeshLimits& limits_;
    const std::string& asset_;
    AccessorReader reader_;
    Mesh mesh_;
    std::vector<Mark> marks_;
    std::vector<int> material_slot_;  // glTF material -> index in mesh_.materials, or -1
    // glTF material -> its copy without the normal texture in mesh_.materials, or -1
    std::vector<int> material_without_normal_slot_;
    // glTF image -> index in mesh_.textures as sRGB [0] and as linear [1], or -1
    std::vector<std::array<int, 2>> image_slot_;
    int default_slot_ = -1;
    std::uint64_t vertices_ = 0;
    std::uint64_t triangles_ = 0;
    std::uint64_t texture_pixels_ = 0;
};

}  // namespace

Mesh load_gltf(std::span<const std::byte> bytes, const std::string& name, bool binary,
               const MeshLimits& limits, const std::optional<std::filesystem::path>& folder) {
    ParseContext context;
    context.folder = folder;
    const tinygltf::Model model = parse_gltf(bytes, name, binary, limits, context);
    Mesh mesh = GltfConverter(model, context, limits).convert();
    finish_mesh(mesh, name, limits);
    return mesh;
}

}  // namespace oer::mesh_detail
