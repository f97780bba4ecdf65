#pragma once
// Phase 3 of OER (DESIGN.md section 2): draws meshes lit by a light rig, with one shadow map
// per light that is on, the environment (or a colour, or nothing) behind them, an optional
// ground plane that receives shadows, exposure, tone mapping and sRGB output.
//
// A FrameRenderer holds GL objects (meshes, environment textures, cached shadow maps): create
// and use it on one thread with a current GL context (inside RenderThread jobs).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "oer/camera.hpp"
#include "oer/image.hpp"
#include "oer/image_encoding.hpp"
#include "oer/mesh.hpp"
#include "oer/rig.hpp"
#include "oer/tonemap.hpp"

namespace oer {

struct SceneObject {
    std::shared_ptr<const Mesh> mesh;
    glm::mat4 transform{1.0f};
    std::optional<glm::vec3> base_color;  // linear RGB, replaces every material's base colour
};

enum class BackgroundKind { Environment, Colour, Transparent };
struct Background {
    BackgroundKind kind = BackgroundKind::Environment;
    glm::vec3 colour{0.0f};  // display-referred sRGB in [0, 1] (as in "#rrggbb")
};

enum class ShadowFilter {
    Hard,  // the thesis's test: one depth comparison per light
    Pcf,   // filtered, kernel sized from the light's angular radius: soft, alias-free edges
};

struct ShadowOptions {
    bool enabled = true;  // false: every light reaches every point (no shadow pass)
    int resolution = 2048;
    ShadowFilter filter = ShadowFilter::Pcf;
};

struct FrameRequest {
    std::shared_ptr<const Rig> rig;
    // The map the rig was made from, for the background; may be null unless the background is
    // the environment.
    std::shared_ptr<const HdrImage> environment;
    std::vector<SceneObject> objects;
    std::optional<Camera> camera;  // empty: frame the scene's bounds automatically
    std::vector<bool> lights;      // one per rig light; empty: every light on
    int width = 512;
    int height = 512;
    bool ground = true;
    Background background;
    double exposure_ev = 0.0;
    ToneMapper tone_mapper = ToneMapper::Neutral;
    ShadowOptions shadows;
    // Anti-aliasing samples per pixel, 1 for none: the frame is shaded at s x s samples per
    // pixel, s = ceil(sqrt(samples)), and their radiance averaged before tone mapping.
    int samples = 4;
    double yaw_degrees = 0.0;  // environment rotation about +Y, lights and SH alike
    bool linear = false;       // true: keep linear radiance (EXR), no exposure or tone mapping
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
    // Pixels times samples: the G-buffer costs about 48 bytes per sample.
    std::int64_t max_samples_total = 4096LL * 4096LL;
    std::size_t max_cached_shadow_maps = 32;
};

class FrameRenderer {
  public:
    explicit FrameRenderer(const FrameLimits& limits = {});
    ~FrameRenderer();
    FrameRenderer(const FrameRenderer&) = delete;
    FrameRenderer& operator=(const FrameRenderer&) = delete;

    // Throws oer::Error: InvalidInput for a malformed request (naming the member),
    // LimitExceeded past the limits, Internal on a GL error.
    Frame render(const FrameRequest& request);

    std::size_t cached_shadow_maps() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace oer
