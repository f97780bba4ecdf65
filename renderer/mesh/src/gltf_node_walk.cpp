// The glTF scene's node graph, walked (see gltf_node_walk.hpp).
#include "gltf_node_walk.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

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

// A node's translation, rotation and scale (absent: the identity) as matrices; `name` is
// "node N", for messages.
glm::dmat4 translation_matrix(const tinygltf::Node& node, const std::string& name,
                              const std::string& asset) {
    glm::dmat4 translation(1.0);
    if (!node.translation.empty()) {
        if (node.translation.size() != 3) {
            fail(ErrorKind::InvalidInput, asset, name + ": translation needs 3 numbers");
        }
        translation[3] =
            glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
    }
    return translation;
}

glm::dmat4 rotation_matrix(const tinygltf::Node& node, const std::string& name,
                           const std::string& asset) {
    glm::dmat4 rotation(1.0);
    if (!node.rotation.empty()) {
        if (node.rotation.size() != 4) {
            fail(ErrorKind::InvalidInput, asset, name + ": rotation needs 4 numbers");
        }
        // glTF stores (x, y, z, w); glm's constructor takes (w, x, y, z).
        const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        const double length = glm::length(q);
        if (!(length > 0.0) || !std::isfinite(length)) {
            fail(ErrorKind::InvalidInput, asset, name + ": rotation is not a valid quaternion");
        }
        rotation = glm::mat4_cast(q / length);
    }
    return rotation;
}

glm::dmat4 scale_matrix(const tinygltf::Node& node, const std::string& name,
                        const std::string& asset) {
    glm::dmat4 scale(1.0);
    if (!node.scale.empty()) {
        if (node.scale.size() != 3) {
            fail(ErrorKind::InvalidInput, asset, name + ": scale needs 3 numbers");
        }
        scale[0][0] = node.scale[0];
        scale[1][1] = node.scale[1];
        scale[2][2] = node.scale[2];
    }
    return scale;
}

// The node's transform relative to its parent: its matrix (column-major, as glTF), or
// translation * rotation * scale; it must be finite.
glm::dmat4 local_transform(const tinygltf::Model& model, int index, const std::string& asset) {
    const tinygltf::Node& node = model.nodes[std::size_t(index)];
    const std::string name = "node " + std::to_string(index);
    glm::dmat4 local(1.0);
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) {
            fail(ErrorKind::InvalidInput, asset,
                 name + ": matrix has " + std::to_string(node.matrix.size()) + " numbers, not 16");
        }
        local = glm::make_mat4(node.matrix.data());
    } else {
        const glm::dmat4 translation = translation_matrix(node, name, asset);
        const glm::dmat4 rotation = rotation_matrix(node, name, asset);
        const glm::dmat4 scale = scale_matrix(node, name, asset);
        local = translation * rotation * scale;
    }
    if (!finite_matrix(local)) {
        fail(ErrorKind::InvalidInput, asset, name + ": transform is not finite");
    }
    return local;
}

class NodeWalk {
  public:
    NodeWalk(const tinygltf::Model& model, const std::string& asset, int max_node_depth,
             const NodeVisitor& visit)
        : model_(model),
          asset_(asset),
          max_node_depth_(max_node_depth),
          visit_(visit),
          marks_(model.nodes.size(), Mark::None) {}

    void run() {
        for (int root : root_nodes()) {
            traverse(root);
        }
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
        return parentless_nodes();
    }

    // No scene: every node that is nobody's child.
    std::vector<int> parentless_nodes() const {
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

    // Depth-first, with an explicit stack, so that the depth limit and not the call stack
    // bounds the walk.
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
        check_first_visit(node);
        if (depth > max_node_depth_) {
            fail(ErrorKind::LimitExceeded, asset_,
                 "node graph deeper than " + std::to_string(max_node_depth_) + " levels at node " +
                     std::to_string(node));
        }
        marks_[std::size_t(node)] = Mark::Active;
        const glm::dmat4 world = parent * local_transform(model_, node, asset_);
        visit_(node, world);
        stack.push_back(Frame{node, world, depth, 0});
    }

    void check_first_visit(int node) const {
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
    }

    const tinygltf::Model& model_;
    const std::string& asset_;
    const int max_node_depth_;
    const NodeVisitor& visit_;
    std::vector<Mark> marks_;
};

}  // namespace

void walk_nodes(const tinygltf::Model& model, const std::string& asset, int max_node_depth,
                const NodeVisitor& visit) {
    NodeWalk(model, asset, max_node_depth, visit).run();
}

}  // namespace oer::mesh_detail
