#pragma once
// Phase 3 of OER (docs/design.md section 2): draws meshes lit by a light rig, with one shadow map
// per light that is on, the environment (or a color, or nothing) behind them, an optional
// ground plane that receives shadows, exposure, tone mapping and sRGB output.
//
// A FrameRenderer holds GL objects (meshes, environment textures, cached shadow maps): create
// and use it on one thread with a current GL context (inside RenderThread jobs).
#include <memory>
#include <span>
#include <stop_token>
#include <vector>

#include "oer/scene/frame_request.hpp"
#include "oer/scene/point_placement.hpp"

namespace oer {

struct RendererState;

class FrameRenderer {
  public:
    explicit FrameRenderer(const FrameLimits& limits = {});
    ~FrameRenderer();
    FrameRenderer(const FrameRenderer&) = delete;
    FrameRenderer& operator=(const FrameRenderer&) = delete;

    // Throws oer::Error: InvalidInput for a malformed request (naming the member),
    // LimitExceeded past the limits, Internal on a GL error, Cancelled once stop is requested
    // (looked at between passes and between lights' shadow maps: oer/core/cancellation.hpp).
    Frame render(const FrameRequest& request, const std::stop_token& stop = {});

    // Where each point lands in the frame `request` draws, and whether that frame shows it
    // (point_placement.hpp): the frame's geometry pass alone (no shadow maps, no shading), its
    // depth read back at the (super)sample nearest each point in the frame, against the point's
    // depth. The same camera, levels of detail, alpha tests and ground as render's. Throws as
    // render does.
    std::vector<PointPlacement> place_points(const FrameRequest& request,
                                             std::span<const ScenePoint> points,
                                             const std::stop_token& stop = {});

    std::size_t cached_shadow_maps() const;
    // Prefiltered cubes (FrameRequest::specular) uploaded so far: only frames with glossy
    // materials under the hdr model upload one, once per cube while its owner lives.
    std::size_t specular_uploads() const;
    // Frames with occlusion that reused the previous one's transferred irradiance (only the
    // camera, or nothing the transfer's lighting reads, changed).
    std::size_t transferred_irradiance_reuses() const;

  private:
    std::unique_ptr<RendererState> state_;
};

}  // namespace oer
