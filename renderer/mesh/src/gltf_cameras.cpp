// The asset's own cameras (see gltf_cameras.hpp).
#include "gltf_cameras.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

// Below this, a view direction or up vector is taken as flattened by its node's scale, or the
// two as parallel (a sheared transform): the camera has no orientation to draw from.
constexpr double kDegenerate = 1e-9;

bool representable(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// "camera 2 'Front' of node 5", for warnings.
std::string camera_label(const tinygltf::Model& model, int node) {
    const int index = model.nodes[std::size_t(node)].camera;
    std::string label = "camera " + std::to_string(index);
    if (index >= 0 && std::size_t(index) < model.cameras.size() &&
        !model.cameras[std::size_t(index)].name.empty()) {
        label += " '" + one_line(model.cameras[std::size_t(index)].name, 80) + "'";
    }
    return label + " of node " + std::to_string(node);
}

// Why the perspective projection cannot be drawn (empty: it can). The file's numbers are finite
// (the JSON parser refuses an overflow), so the yfov's range is what is left to check, as glTF
// 2.0 section 5.12 states it; the informative aspect ratio and planes are kept as given.
std::string perspective_fault(const tinygltf::PerspectiveCamera& perspective) {
    if (!(perspective.yfov > 0.0) || !(perspective.yfov < std::numbers::pi)) {
        return "its yfov is not in (0, pi) radians";
    }
    return {};
}

}  // namespace

GltfCameras::GltfCameras(const tinygltf::Model& model, std::size_t max_cameras,
                         std::vector<AssetCamera>& cameras, std::vector<std::string>& warnings)
    : model_(model), max_cameras_(max_cameras), cameras_(cameras), warnings_(warnings) {}

void GltfCameras::place(int node, const glm::dmat4& world) {
    const tinygltf::Node& holder = model_.nodes[std::size_t(node)];
    if (holder.camera < 0) {
        return;
    }
    if (std::size_t(holder.camera) >= model_.cameras.size()) {
        leave_out(node, "it does not exist");
        return;
    }
    const tinygltf::Camera& source = model_.cameras[std::size_t(holder.camera)];
    AssetCamera camera;
    if (source.type == "perspective") {
        if (const std::string fault = perspective_fault(source.perspective); !fault.empty()) {
            leave_out(node, fault);
            return;
        }
        camera.projection = CameraProjection::Perspective;
        camera.camera.fov_y = float(source.perspective.yfov * 180.0 / std::numbers::pi);
        camera.aspect_ratio = float(source.perspective.aspectRatio);
        camera.znear = float(source.perspective.znear);
        camera.zfar = float(source.perspective.zfar);
    } else {
        // tinygltf refuses any type but these two, as glTF 2.0 does.
        camera.projection = CameraProjection::Orthographic;
        camera.camera.fov_y = 0.0f;  // none: an orthographic camera is listed, never drawn
        camera.znear = float(source.orthographic.znear);
        camera.zfar = float(source.orthographic.zfar);
    }
    // glTF 2.0 section 3.10.1: the camera looks down its node's local -Z, +Y up.
    const glm::dvec3 eye(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dvec3 forward(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
    const glm::dvec3 up(world * glm::dvec4(0.0, 1.0, 0.0, 0.0));
    const double forward_length = glm::length(forward);
    const double up_length = glm::length(up);
    if (!(forward_length > kDegenerate) || !(up_length > kDegenerate) ||
        !(glm::length(glm::cross(forward / forward_length, up / up_length)) > kDegenerate)) {
        leave_out(node, "its node's transform flattens its view (a zero or degenerate scale)");
        return;
    }
    camera.camera.eye = glm::vec3(eye);
    // As far ahead as the eye is from the origin, so that the direction survives in float.
    const double ahead = std::max(1.0, glm::length(eye));
    camera.camera.target = glm::vec3(eye + ahead * forward / forward_length);
    camera.camera.up = glm::vec3(up / up_length);
    if (!representable(camera.camera.eye) || !representable(camera.camera.target)) {
        leave_out(node, "its position is beyond the range of a float");
        return;
    }
    if (cameras_.size() >= max_cameras_) {
        ++over_limit_;
        return;
    }
    const std::string& node_name = holder.name;
    camera.name = !source.name.empty() ? source.name
                  : !node_name.empty() ? node_name
                                       : "camera " + std::to_string(cameras_.size());
    cameras_.push_back(std::move(camera));
}

void GltfCameras::finish() {
    if (over_limit_ > 0) {
        warnings_.push_back(std::to_string(over_limit_) + " camera(s) beyond the limit of " +
                            std::to_string(max_cameras_) + " were left out");
    }
}

void GltfCameras::leave_out(int node, const std::string& why) {
    warnings_.push_back(camera_label(model_, node) + " was left out: " + why);
}

void aim_asset_cameras(std::vector<AssetCamera>& cameras, const Bounds& bounds) {
    const float size = glm::length(bounds.max - bounds.min);
    for (AssetCamera& asset : cameras) {
        Camera& camera = asset.camera;
        const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
        const float depth = glm::dot(bounds.centre() - camera.eye, forward);
        // A centre at or behind the eye (or beside it, for a product far smaller than its
        // distance) gives no target worth turning about: keep the one place() chose.
        if (std::isfinite(depth) && depth > 1e-3f * size) {
            camera.target = camera.eye + depth * forward;
        }
    }
}

}  // namespace oer::mesh_detail
