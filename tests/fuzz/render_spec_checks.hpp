#pragma once
// What fuzz_render_json and fuzz_render_query check of a request the parser accepted, as the
// service goes on with it (server/src/routes_render.cpp, frame_service.cpp): its ETag, and its
// frame request once the ids are resolved, here every mesh to the built-in product and the
// environment to the built-in preset's rig and map.
//
// Properties (findings when broken):
// - the canonical document (normalised_render_json) is itself a valid body that parses back
//   to the same ETag (oer/api/render_request.hpp);
// - the frame request passes what the renderer checks of the values the parser vouches for
//   (renderer/gl/src/frame_validation.cpp, which needs GL to link: its checks of the frame
//   size, exposure, yaw, transforms, base colours, background and camera are restated here
//   with the renderer's own numbers), so that a request answered with an ETag is never
//   refused by the renderer afterwards.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <glm/matrix.hpp>

#include "fuzz_support.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/render_request.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/default_product.hpp"

namespace oer::fuzz {

struct PresetScene {
    std::shared_ptr<const HdrImage> map;
    std::shared_ptr<const Rig> rig;
    std::shared_ptr<const Mesh> product;
};

// Made once: the rig takes a while, and every input resolves to the same assets.
inline const PresetScene& preset_scene() {
    static const PresetScene scene = [] {
        auto map = std::make_shared<const HdrImage>(make_default_environment());
        auto rig = std::make_shared<const Rig>(build_rig(*map, {}, RigOptions{}));
        return PresetScene{map, rig, std::make_shared<const Mesh>(make_default_product())};
    }();
    return scene;
}

// The limits the service parses requests with at its default configuration
// (server/src/service.cpp).
inline api::RenderLimits service_render_limits() {
    const server::ServiceConfig config;
    api::RenderLimits limits;
    limits.max_width = config.max_frame_width;
    limits.max_height = config.max_frame_height;
    return limits;
}

inline bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        if (!finite(glm::vec3(m[c])) || !std::isfinite(m[c][3])) {
            return false;
        }
    }
    return true;
}

inline void check_frame_request(const FrameRequest& request, const api::RenderLimits& limits) {
    if (request.width < 1 || request.height < 1 || request.width > limits.max_width ||
        request.height > limits.max_height) {
        finding("an accepted frame of " + std::to_string(request.width) + "x" +
                std::to_string(request.height));
    }
    if (!std::isfinite(request.exposure) || std::abs(request.exposure) > 64.0) {
        finding("an accepted exposure of " + std::to_string(request.exposure));
    }
    if (!std::isfinite(request.environment_yaw)) {
        finding("an accepted non-finite environment yaw");
    }
    for (const float weight : request.lights) {
        if (!(weight >= 0.0f && weight <= kMaxLightWeight)) {
            finding("an accepted light weight of " + std::to_string(weight));
        }
    }
    for (const SceneObject& object : request.objects) {
        // The renderer's test, in float, after the API's in double.
        if (!finite(object.transform) || std::abs(glm::determinant(object.transform)) < 1e-12f) {
            finding("an accepted transform the renderer refuses (determinant " +
                    std::to_string(glm::determinant(object.transform)) + " in float)");
        }
        if (object.base_color && !(finite(*object.base_color) && object.base_color->r >= 0.0f &&
                                   object.base_color->g >= 0.0f && object.base_color->b >= 0.0f)) {
            finding("an accepted base colour the renderer refuses");
        }
    }
    if (!finite(request.background.color)) {
        finding("an accepted non-finite background colour");
    }
    if (!request.camera) {
        finding("a frame request without its resolved camera");
    }
    try {
        validate_camera(*request.camera);
    } catch (const Error& error) {
        finding(std::string("an accepted request whose resolved camera the renderer refuses: ") +
                error.what());
    }
}

// After the parser accepted `spec` from the body or query at `limits`.
inline void check_accepted(const api::RenderSpec& spec, const api::RenderLimits& limits) {
    const std::string etag = api::render_etag(spec);
    const std::string canonical = api::normalised_render_json(spec).dump();
    try {
        if (api::render_etag(api::parse_render_json(canonical, limits)) != etag) {
            finding("the canonical document parses to another ETag: " + canonical);
        }
    } catch (const Error& error) {
        finding("the canonical document is refused (" + std::string(error.what()) +
                "): " + canonical);
    }
    const PresetScene& scene = preset_scene();
    const std::vector<std::shared_ptr<const Mesh>> meshes(spec.objects.size(), scene.product);
    FrameRequest request;
    try {
        request = api::to_frame_request(spec, scene.rig, scene.map, meshes);
    } catch (const api::InvalidParameter& error) {
        if (error.parameter() == "lights") {
            return;  // weights that do not match the rig's lights: 422, documented
        }
        throw;
    }
    check_frame_request(request, limits);
}

// parse() parses the body or query at `limits`: a parameter a refusal names goes into the
// problem body as "parameter", so it must be UTF-8 as its message.
template <typename Parse>
void check_accepted_or_refused(Parse&& parse, const api::RenderLimits& limits) {
    api::RenderSpec spec;
    try {
        spec = parse();
    } catch (const api::InvalidParameter& error) {
        require_utf8(error.parameter(), "a refused parameter's name");
        throw;
    }
    check_accepted(spec, limits);
}

}  // namespace oer::fuzz
