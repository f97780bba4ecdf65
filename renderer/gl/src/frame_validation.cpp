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
#include "oer/scene/scene_rules.hpp"
#include "oer/transfer/transfer_lighting.hpp"

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

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A cube's sizes as GL will read them: a texture of face_size texels square per face and
// `levels` levels, each of its layers' six faces' RGB half floats. `which` names it.
void validate_cube(const PrefilteredCube& cube, const std::string& which, int max_texture_size) {
    if (cube.face_size < 1 || cube.face_size > max_texture_size) {
        fail("specular", which + ": the face size must be in 1.." +
                             std::to_string(max_texture_size) + ", got " +
                             std::to_string(cube.face_size));
    }
    int largest_levels = 1;
    while ((cube.face_size >> largest_levels) > 0) {
        ++largest_levels;
    }
    if (cube.levels < 1 || cube.levels > largest_levels) {
        fail("specular", which + ": a cube of face size " + std::to_string(cube.face_size) +
                             " has 1.." + std::to_string(largest_levels) + " levels, got " +
                             std::to_string(cube.levels));
    }
    if (cube.rgb_half.size() != std::size_t(cube.levels)) {
        fail("specular", which + ": " + std::to_string(cube.levels) + " levels but " +
                             std::to_string(cube.rgb_half.size()) + " level buffers");
    }
    for (int level = 0; level < cube.levels; ++level) {
        const std::size_t side = std::size_t(cube.face_size >> level);
        const std::size_t expected = std::size_t(cube.layers) * 6 * side * side * 3;
        if (cube.rgb_half[std::size_t(level)].size() != expected) {
            fail("specular", which + ": level " + std::to_string(level) + " holds " +
                                 std::to_string(cube.rgb_half[std::size_t(level)].size()) +
                                 " half floats, its " + std::to_string(cube.layers) +
                                 " layers' faces need " + std::to_string(expected));
        }
    }
}

// The residual's cube and one light cube per rig light, of the same levels (one lod reads both).
void validate_specular(const SpecularEnvironment& specular, const Rig& rig, int max_texture_size) {
    validate_cube(specular.residual, "the residual's cube", max_texture_size);
    validate_cube(specular.lights, "the lights' cube", max_texture_size);
    if (specular.residual.layers != 1) {
        fail("specular", "the residual's cube has " + std::to_string(specular.residual.layers) +
                             " layers, not 1");
    }
    if (std::size_t(specular.lights.layers) < rig.lights.size() ||
        specular.floor_layers.size() != rig.lights.size()) {
        fail("specular", "the lights' cube has " + std::to_string(specular.lights.layers) +
                             " layers and " + std::to_string(specular.floor_layers.size()) +
                             " floor layers for a rig of " + std::to_string(rig.lights.size()) +
                             " lights: it was prefiltered for another rig");
    }
    for (std::size_t k = 0; k < specular.floor_layers.size(); ++k) {
        const int layer = specular.floor_layers[k];
        if (layer < -1 || layer >= specular.lights.layers) {
            fail("specular", "light " + std::to_string(k) + "'s floor layer " +
                                 std::to_string(layer) + " is neither -1 nor one of the " +
                                 std::to_string(specular.lights.layers) +
                                 " layers of the lights' cube");
        }
    }
    if (specular.lights.levels != specular.residual.levels) {
        fail("specular", "the lights' cube has " + std::to_string(specular.lights.levels) +
                             " levels, the residual's " + std::to_string(specular.residual.levels));
    }
}

// The transfer must be the one baked for this request's scene: one receiver set per object and
// primitive with one point per vertex, the ground's grid exactly when the frame has a ground,
// reflector slots that fit its objects,
// the request's bounce, and the order its rig is evaluated at.
void validate_transfer(const FrameRequest& request) {
    if (!request.occlusion) {
        if (request.transfer) {
            fail("occlusion", "a transfer was given for a frame without occlusion");
        }
        return;
    }
    if (!request.transfer) {
        fail("occlusion", "occlusion needs the scene's baked transfer, and none was given");
    }
    const SceneTransfer& transfer = *request.transfer;
    const ShProjection& sh = request.rig->sh;
    if (request.ground && (sh.per_light_above_horizon.size() != sh.per_light.size() ||
                           sh.all_above_horizon.order < transfer_order(*request.rig))) {
        fail("environment",
             "occlusion with the ground needs the rig's projection above the "
             "horizon, and it has none");
    }
    if (transfer.order < transfer_order(*request.rig)) {
        fail("transfer", "baked at order " + std::to_string(transfer.order) +
                             ", the environment needs " +
                             std::to_string(transfer_order(*request.rig)));
    }
    if (const std::string misfit = transfer_misfit(transfer, request); !misfit.empty()) {
        fail("transfer", "not baked for this scene: " + misfit);
    }
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
                           " light(s), got " + std::to_string(request.lights.size()) + " weights");
    }
    for (std::size_t k = 0; k < request.lights.size(); ++k) {
        const float weight = request.lights[k];
        if (!(weight >= 0.0f && weight <= kMaxLightWeight)) {
            fail("lights", "the weight of light " + std::to_string(k) + " must be in [0, " +
                               std::to_string(int(kMaxLightWeight)) + "], got " +
                               std::to_string(weight));
        }
    }
    // Above one, the sample budget and the texture size below bound the samples.
    if (request.samples < 1) {
        fail("samples", "must be at least 1");
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
    if (request.shadows.resolution < 1 ||
        request.shadows.resolution > std::min(limits.max_shadow_resolution, max_texture_size)) {
        throw Error(ErrorKind::LimitExceeded,
                    "shadow_resolution: must be in 1.." +
                        std::to_string(std::min(limits.max_shadow_resolution, max_texture_size)));
    }
    for (const auto& [name, value] : {std::pair{"shadow_softness", request.shadows.softness},
                                      std::pair{"shadow_intensity", request.shadows.intensity}}) {
        if (!(value >= 0.0f && value <= 1.0f)) {
            fail(name, "must be in [0, 1]");
        }
    }
    // 2^64 and 2^-64 are still normal floats: the shaders' exposure scale stays finite and
    // non-zero.
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
        // The loaders bound a texture's pixels, not its sides: a 32768x1 image passes them,
        // and GL would refuse its storage.
        for (std::size_t t = 0; t < object.mesh->textures.size(); ++t) {
            const Texture& texture = object.mesh->textures[t];
            if (std::max(texture.width, texture.height) > max_texture_size) {
                throw Error(ErrorKind::LimitExceeded,
                            member + ".mesh: texture " + std::to_string(t) + " is " +
                                std::to_string(texture.width) + "x" +
                                std::to_string(texture.height) + ", over the limit of " +
                                std::to_string(max_texture_size) + " texels per side");
            }
        }
        // An albedo below zero would give negative radiance, which linear output would carry out.
        if (object.base_color &&
            !(finite(*object.base_color) &&
              glm::all(glm::greaterThanEqual(*object.base_color, glm::vec3(0.0f))))) {
            fail(member + ".base_color", "must be finite and non-negative");
        }
    }
    if (needs_specular(request)) {
        if (!request.specular) {
            fail("specular",
                 "the scene has glossy materials but no prefiltered environment was given");
        }
        validate_specular(*request.specular, *request.rig, max_texture_size);
    }
    // A color outside [0, 1] is clamped by the 8-bit output; only a NaN would spread.
    if (!finite(request.background.color)) {
        fail("background", "the color must be finite");
    }
    if (request.background.kind == BackgroundKind::Environment && !request.environment_map) {
        fail("background", "the environment background needs the environment map");
    }
    if (request.camera) {
        validate_camera(*request.camera);
    }
    validate_transfer(request);
}

}  // namespace oer
