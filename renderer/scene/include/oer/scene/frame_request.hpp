#pragma once
// What a frame is made of and what comes back (docs/design.md section 2, phase 3): plain data, no
// GL, so that the API (api/) and the command line can build requests without linking EGL or GL.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "oer/core/image.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/lighting/tonemap.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/scene/scene_transfer.hpp"

namespace oer {

struct SceneObject {
    std::shared_ptr<const Mesh> mesh;
    glm::mat4 transform{1.0f};
    std::optional<glm::vec3> base_color;  // linear RGB, replaces the base color of
                                          // base_color_material's materials, or of every one
    // KHR_materials_variants: the index into mesh->variants whose materials are drawn (none:
    // the file's default materials; Primitive::material_under).
    std::optional<std::uint32_t> variant = std::nullopt;
    // The material base_color recolours, with every other of its name (a configurator's
    // per-part colour), as an index into mesh->materials; none: every material.
    std::optional<std::uint32_t> base_color_material = std::nullopt;
};

// The base colour that replaces `material`'s when `object` draws it, if any.
inline std::optional<glm::vec3> base_color_override(const SceneObject& object,
                                                    const Material& material) {
    if (!object.base_color_material ||
        material.name == object.mesh->materials.at(*object.base_color_material).name) {
        return object.base_color;
    }
    return std::nullopt;
}

enum class BackgroundKind { Environment, Color, Transparent };
struct Background {
    BackgroundKind kind = BackgroundKind::Environment;
    glm::vec3 color{0.0f};  // display-referred sRGB in [0, 1] (as in "#rrggbb")
};

enum class ShadowFilter {
    Hard,  // the thesis's test: one depth comparison per light
    Pcf,   // filtered, kernel sized from the light's angular radius: soft, alias-free edges
};

struct ShadowOptions {
    bool enabled = true;  // false: every light reaches every point (no shadow pass)
    int resolution = 2048;
    ShadowFilter filter = ShadowFilter::Pcf;
    // In [0, 1], as model-viewer's shadow-softness: each light's penumbra, a blocker's shadow
    // growing with its distance from the receiver by the light's angular size, is scaled by it
    // (1: the light's own size, as the environment shows it; 0: the hard shadow of a point).
    double softness = 1.0;
    // In [0, 1], as model-viewer's shadow-intensity: how much of its shadows the shadow-catching
    // floor (GroundLook::ShadowCatcher) shows (1: all the light the objects take away; 0: none).
    double intensity = 1.0;
};

// How the ground plane (FrameRequest::ground) is drawn. It takes shadows, lights and occludes
// the scene alike in both; both fade into the background with the distance from the scene
// (SceneBounds::ground_weight), so that no edge of the plane is ever seen.
enum class GroundLook {
    Opaque,  // a Lambertian floor of albedo 0.8
    // Invisible: the background shows through it, darkened by what the objects take away from
    // the floor's light (each light's shadow, the residual map's occlusion), as a product
    // photographer's shadow catcher does. Over a colour or transparency the shadow is a black
    // of that opacity, so that a transparent frame carries it in its alpha.
    ShadowCatcher,
};

// The brightest a request can make a light: four times as captured (docs/design.md section 2).
constexpr float kMaxLightWeight = 4.0f;

struct FrameRequest {
    std::shared_ptr<const Rig> rig;
    // The map the rig was made from, for the background; may be null unless the background is
    // the environment.
    std::shared_ptr<const HdrImage> environment_map;
    // The rig's residual map prefiltered (specular_environment.hpp): needed when an object has
    // a glossy material (Material::glossy) and the rig's model is Hdr, else unused and best
    // left null, so that a scene without glossy materials costs no specular memory.
    std::shared_ptr<const SpecularEnvironment> specular;
    // Occlusion of the residual map and the ground as lighting (docs/design.md section 2): true,
    // the residual map (the rig's radiance minus its lights' pixels) reaches objects and ground
    // through `transfer`, baked for this request's objects, transforms and ground
    // (transfer_bake.hpp), and, with the ground, lights below its horizon reach no object; false,
    // the residual lights every point unoccluded (OER as before) and `transfer` must be null. The
    // renderer's default is false because a transfer has to be baked first; the API's and the
    // command line's is true, and they bake it.
    bool occlusion = false;
    // None: the ground lights nothing and nothing reflects (to compare with the reference's
    // direct mode); One: the ground and the objects reflect once. Must match transfer->bounce.
    Bounce bounce = Bounce::One;
    std::shared_ptr<const SceneTransfer> transfer;
    std::vector<SceneObject> objects;
    std::optional<Camera> camera;  // empty: frame the scene's bounds automatically
    // One weight per rig light (docs/design.md section 2, dimmable lights): 0 off, 1 as captured,
    // up to kMaxLightWeight; empty: every light at 1.
    std::vector<float> lights;
    int width = 512;
    int height = 512;
    bool ground = true;
    GroundLook ground_look = GroundLook::Opaque;  // with the ground
    Background background;
    double exposure = 0.0;  // EV
    ToneMapper tonemap = ToneMapper::Neutral;
    ShadowOptions shadows;
    // Anti-aliasing samples per pixel, 1 for none: the frame is shaded at s x s samples per
    // pixel, s = ceil(sqrt(samples)), and their radiance averaged before tone mapping.
    int samples = 4;
    double environment_yaw = 0.0;  // degrees about +Y, lights and SH alike
    bool linear = false;           // true: keep linear radiance (EXR), no exposure or tone mapping
};

struct Frame {
    int width = 0;
    int height = 0;
    Rgba8Image display;         // when !linear: tone-mapped sRGB, straight alpha
    std::vector<float> linear;  // when linear: RGBA radiance, row 0 at the top
    std::map<std::string, double> timings_ms;
    int shadow_maps_rendered = 0;  // this frame (the others came from the cache)
};

struct FrameLimits {
    int max_width = 4096;
    int max_height = 4096;
    int max_shadow_resolution = 8192;
    // Pixels times samples: the G-buffer costs about 64 bytes per sample.
    std::int64_t max_samples_total = 4096LL * 4096LL;
    std::size_t max_cached_shadow_maps = 32;
};

}  // namespace oer
