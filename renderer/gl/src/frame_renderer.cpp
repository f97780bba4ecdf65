#include "oer/gl/frame_renderer.hpp"

#include <GL/glcorearb.h>

#include <chrono>

#include "frame_context.hpp"
#include "frame_validation.hpp"
#include "oer/core/cancellation.hpp"
#include "oer/gl/gl_context.hpp"
#include "passes/frame_passes.hpp"
#include "renderer_state.hpp"

namespace oer {

namespace {

using Clock = std::chrono::steady_clock;

double elapsed_ms(Clock::time_point since) {
    return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

}  // namespace

FrameRenderer::FrameRenderer(const FrameLimits& limits)
    : state_(std::make_unique<RendererState>(limits)) {}

FrameRenderer::~FrameRenderer() = default;

std::size_t FrameRenderer::cached_shadow_maps() const {
    return state_->shadows.size();
}

std::size_t FrameRenderer::specular_uploads() const {
    return state_->specular_uploads;
}

std::size_t FrameRenderer::transferred_irradiance_reuses() const {
    return state_->transferred.reuses;
}

// The passes in order (passes/frame_passes.hpp), each taking what it reads and returning what
// it produces: the frame's data flow. GL runs commands asynchronously (llvmpipe on its
// rasterizer threads), so each pass's timing waits for them (glFinish) before it stops.
Frame FrameRenderer::render(const FrameRequest& request, const std::stop_token& stop) {
    validate_frame_request(request, state_->limits, state_->max_texture_size);
    RendererState& state = *state_;
    const auto frame_start = Clock::now();
    Frame result;
    result.width = request.width;
    result.height = request.height;

    auto start = Clock::now();
    const FrameContext frame = make_frame_context(request, state.transferred);
    const FrameLightingBuffers lighting = upload_irradiance_sets(frame, state);
    result.timings_ms["setup"] = elapsed_ms(start);

    start = Clock::now();
    throw_if_stopped(stop, "the frame");
    const ShadowMaps shadows = render_shadow_maps(frame, state, stop);
    result.shadow_maps_rendered = shadows.rendered;
    glFinish();
    result.timings_ms["shadow_pass"] = elapsed_ms(start);

    throw_if_stopped(stop, "the frame");
    start = Clock::now();
    const RenderTargets& targets = render_geometry(frame, lighting, state);
    glFinish();
    result.timings_ms["geometry_pass"] = elapsed_ms(start);

    throw_if_stopped(stop, "the frame");
    start = Clock::now();
    GLuint finished = shade_surfaces(frame, lighting, shadows, targets, state, stop);
    if (frame.blending) {
        finished = blend_transparent_surfaces(frame, lighting, targets, state);
    }
    if (frame.blending || frame.scale > 1) {
        finished = resolve_supersamples(frame, finished, targets, state);
    }
    glFinish();
    result.timings_ms["shading_pass"] = elapsed_ms(start);

    start = Clock::now();
    read_back(request, finished, result);
    check_gl_errors("FrameRenderer::render");
    result.timings_ms["readback"] = elapsed_ms(start);
    result.timings_ms["total"] = elapsed_ms(frame_start);
    return result;
}

}  // namespace oer
