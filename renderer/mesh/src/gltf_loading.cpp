// glTF 2.0 (see oer/mesh_loading.hpp): the model parsed by tinygltf (gltf_parsing.hpp)
// becomes an oer::Mesh. The scene's node graph is walked (cycles, shared nodes and excessive
// depth refused), every node's transform baked into positions and normals (a mirroring one
// flips the winding back), strips and fans become lists, lines and points are refused, and
// the materials used are converted, decoding their base-color textures within the limits.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
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
          image_slot_(model.images.size(), -1) {}

    Mesh convert() {
        std::vector<int> roots = root_nodes();
        marks_.assign(model_.nodes.size(), Mark::None);
        for (int root : roots) {
            traverse(root);
        }
        if (mesh_.materials.empty()) {
            mesh_.materials.push_back(default_material());
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
        return primitive;
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
        return material;  // glTF defaults: white, metallic 1, roughness 1, specular
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

    float factor(double value, const std::string& what) const {
        if (!std::isfinite(value)) {
            fail(ErrorKind::InvalidInput, asset_, what + " is not finite");
        }
        return float(std::clamp(value, 0.0, 1.0));
    }

    Material convert_material(int index) {
        const tinygltf::Material& source = model_.materials[std::size_t(index)];
        const std::string name = source.name.empty()
                                     ? "material " + std::to_string(index)
                                     : "material '" + one_line(source.name, 80) + "'";
        const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
        Material material;
        material.name = source.name.empty() ? name : source.name;
        if (pbr.baseColorFactor.size() != 4) {
            fail(ErrorKind::InvalidInput, asset_, name + ": baseColorFactor needs 4 numbers");
        }
        for (int c = 0; c < 4; ++c) {
            material.base_color[c] =
                factor(pbr.baseColorFactor[std::size_t(c)], name + ": baseColorFactor");
        }
        material.metallic = factor(pbr.metallicFactor, name + ": metallicFactor");
        material.roughness = factor(pbr.roughnessFactor, name + ": roughnessFactor");
        material.base_color_texture.texture = base_color_texture(pbr.baseColorTexture, name);
        return material;
    }

    int base_color_texture(const tinygltf::TextureInfo& info, const std::string& material) {
        if (info.index < 0) {
            return -1;
        }
        if (std::size_t(info.index) >= model_.textures.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 material + ": baseColorTexture refers to texture " + std::to_string(info.index) +
                     ", which does not exist");
        }
        if (info.texCoord != 0) {
            mesh_.warnings.push_back(material + ": the base color texture uses TEXCOORD_" +
                                     std::to_string(info.texCoord) +
                                     ", only TEXCOORD_0 is supported: texture ignored");
            return -1;
        }
        const int image = model_.textures[std::size_t(info.index)].source;
        if (image < 0) {
            mesh_.warnings.push_back(material +
                                     ": the base color texture has no PNG or JPEG source: "
                                     "texture ignored");
            return -1;
        }
        if (std::size_t(image) >= model_.images.size()) {
            fail(ErrorKind::InvalidInput, asset_,
                 material + ": texture " + std::to_string(info.index) + " refers to image " +
                     std::to_string(image) + ", which does not exist");
        }
        int& slot = image_slot_[std::size_t(image)];
        if (slot >= 0) {
            return slot;
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
                 "the base color textures together have more than the limit of " +
                     std::to_string(limits_.max_total_texture_pixels) + " pixels");
        }
        mesh_.textures.push_back(
            decode_texture(encoded->second, limits_.max_texture_pixels, label));
        texture_pixels_ += pixels;
        slot = int(mesh_.textures.size()) - 1;
        return slot;
    }

    const tinygltf::Model& model_;
    ParseContext& context_;
    const MeshLimits& limits_;
    const std::string& asset_;
    AccessorReader reader_;
    Mesh mesh_;
    std::vector<Mark> marks_;
    std::vector<int> material_slot_;  // glTF material -> index in mesh_.materials, or -1
    std::vector<int> image_slot_;     // glTF image -> index in mesh_.textures, or -1
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
