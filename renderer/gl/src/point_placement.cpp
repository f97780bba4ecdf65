// FrameRenderer::place_points: the frame's geometry pass alone, then its depth buffer read back
// at each point. Only one sample a point crosses the bus (glReadnPixels), never the whole
// buffer: a 4096x4096 frame's depth is 64 MiB of floats.
#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include "frame_context.hpp"
#include "frame_validation.hpp"
#include "oer/core/cancellation.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/gl_context.hpp"
#include "oer/mesh/camera_rays.hpp"
#include "passes/frame_passes.hpp"
#include "renderer_state.hpp"

namespace oer {

namespace {

// The depth along the view direction of the surface at sample (column, row) of the geometry
// pass (row 0 at the bottom, as GL keeps it), from its window depth; infinity where nothing was
// drawn.
double surface_depth(const FrameContext& frame, const glm::dmat4& clip_to_world,
                     const CameraRays& rays, int column, int row, float window_depth) {
    if (window_depth >= 1.0f) {
        return std::numeric_limits<double>::infinity();
    }
    const glm::dvec4 clip{(column + 0.5) / frame.samples_wide * 2.0 - 1.0,
                          (row + 0.5) / frame.samples_high * 2.0 - 1.0,
                          2.0 * double(window_depth) - 1.0, 1.0};
    const glm::dvec4 world = clip_to_world * clip;
    return glm::dot(glm::dvec3(world) / world.w - rays.eye, rays.forward);
}

}  // namespace

std::vector<PointPlacement> FrameRenderer::place_points(const FrameRequest& request,
                                                        std::span<const ScenePoint> points,
                                                        const std::stop_token& stop) {
    validate_frame_request(request, state_->limits, state_->max_texture_size);
    RendererState& state = *state_;
    throw_if_stopped(stop, "the hotspots' placement");
    FrameContext frame = make_frame_context(request, state.transferred);
    // The geometry pass reads the lighting buffers only for an occlusion frame's transferred
    // irradiance, which depth does not need.
    frame.transfer = false;
    const RenderTargets& targets = render_geometry(frame, FrameLightingBuffers{}, state);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, targets.geometry_framebuffer.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);

    const CameraRays rays = camera_rays(frame.camera, request.width, request.height);
    const glm::dmat4 clip_to_world = glm::inverse(glm::dmat4(frame.view_projection));
    const double scale = frame.scale;
    std::vector<PointPlacement> placements;
    placements.reserve(points.size());
    for (const ScenePoint& point : points) {
        PointPlacement placement;
        placement.facing = glm::dot(point.normal, rays.eye - point.position) > 0.0;
        const auto image = rays.project(point.position);
        if (image) {
            placement.x = image->x;
            placement.y = image->y;
            placement.depth = image->depth;
            placement.in_frame = image->x >= 0.0 && image->x < request.width && image->y >= 0.0 &&
                                 image->y < request.height;
        }
        if (placement.in_frame) {
            // The (super)sample whose centre is nearest the point, in GL's rows (bottom up).
            const int column =
                std::clamp(int(std::floor(image->x * scale)), 0, frame.samples_wide - 1);
            const int row = std::clamp(int(std::floor((request.height - image->y) * scale)), 0,
                                       frame.samples_high - 1);
            float window_depth = 1.0f;
            glReadnPixels(column, row, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, sizeof window_depth,
                          &window_depth);
            const double tolerance =
                occlusion_tolerance_pixels(point.normal, glm::normalize(rays.eye - point.position));
            placement.unoccluded = unoccluded_by(
                image->depth, surface_depth(frame, clip_to_world, rays, column, row, window_depth),
                rays.pixel_size_per_depth(), tolerance);
        }
        placements.push_back(placement);
    }
    leave_frame_state();
    check_gl_errors("FrameRenderer::place_points");
    return placements;
}

}  // namespace oer
