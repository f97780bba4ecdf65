#include "frame_validation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include "frame_context.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/camera.hpp"

namespace oer {

namespace {

void fail(const std::string& member, const std::string& message) {
    throw Error(ErrorKind::InvalidInput, member + ": " + message);
}

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace

void validate_frame_request(const FrameRequest& request, const FrameLimits& limits,
                            int max_texture_size) {
    if (!request.rig) {
        fail("environment", "no light rig given");
    }
    if (request.width < 1 || request.height < 1) {
        fail("width", "the frame must be at least 1x1");
    }
    if (request.width > limits.max_width || request.height > limits.max_height) {
        throw Error(ErrorKind::LimitExceeded,
                    "width/height: " + std::to_string(request.width) + "x" +
                        std::to_string(request.height) + " is over the limit of " +
                        std::to_string(limits.max_width) + "x" + std::to_string(limits.max_height));
    }
    if (!request.lights.empty() && request.lights.size() != request.rig->lights.size()) {
        fail("lights", "the environment has " + std::to_string(request.rig->lights.size()) +
                           " light(s), got " + std::to_string(request.lights.size()) + " switches");
    }
    if (request.samples < 1 || request.samples > 16) {
        fail("samples", "must be in 1..16");
    }
    const int scale = supersampling_scale(request.samples);
    if (std::int64_t(request.width) * request.height * scale * scale > limits.max_samples_total ||
        std::max(request.width, request.height) * scale > max_texture_size) {
        throw Error(ErrorKind::LimitExceeded,
                    "samples: " + std::to_string(scale * scale) + " samples per pixel at " +
                        std::to_string(request.width) + "x" + std::to_string(request.height) +
                        " are over the limit of " + std::to_string(limits.max_samples_total) +
                        " samples per frame and " + std::to_string(max_texture_size) +
                        " samples per side");
    }
    if (request.shadows.resolution < 16 ||
        request.shadows.resolution > limits.max_shadow_resolution) {
        throw Error(ErrorKind::LimitExceeded, "shadow_resolution: must be in 16.." +
                                                  std::to_string(limits.max_shadow_resolution));
    }
    if (!std::isfinite(request.exposure) || std::abs(request.exposure) > 64.0) {
        fail("exposure", "must be a finite number of stops in [-64, 64]");
    }
    if (!std::isfinite(request.environment_yaw)) {
        fail("yaw", "must be finite");
    }
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        const std::string member = "objects[" + std::to_string(i) + "]";
        if (!object.mesh) {
            fail(member + ".mesh", "no mesh given");
        }
        if (!finite(object.transform) || std::abs(glm::determinant(object.transform)) < 1e-12f) {
            fail(member + ".transform", "must be finite and invertible");
        }
        if (object.base_color &&
            !(glm::all(glm::greaterThanEqual(*object.base_color, glm::vec3(0))) &&
              std::isfinite(object.base_color->x + object.base_color->y + object.base_color->z))) {
            fail(member + ".base_color", "must be finite and non-negative");
        }
    }
    if (!request.linear && request.background.kind == BackgroundKind::Color &&
        !glm::all(glm::lessThanEqual(glm::abs(request.background.color - 0.5f), glm::vec3(0.5f)))) {
        fail("background", "the color must be in [0, 1]");
    }
    if (request.background.kind == BackgroundKind::Environment && !request.environment_map) {
        fail("background", "the environment background needs the environment map");
    }
    if (request.camera) {
        validate_camera(*request.camera);
    }
}

}  // namespace oer
