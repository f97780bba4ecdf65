#pragma once
// The passes of a frame, in the order FrameRenderer::render runs them, each in its own file.
// The division follows Filament's (ShadowMapManager for the shadow maps, Renderer for the
// color passes, PostProcessManager for the resolve): every pass reads the FrameContext and
// the RendererState, and says below what it leaves behind for the next.
#include "frame_context.hpp"
#include "oer/scene/frame_request.hpp"
#include "renderer_state.hpp"
#include "shadow_map_cache.hpp"

namespace oer {

// Setup (shading_pass.cpp): the frame's irradiance sets into state.irradiance_buffer, and in an
// occlusion frame the transferred irradiance into state.transferred_vertex_buffer and, with the
// ground, state.ground_transfer.
void upload_irradiance_sets(const FrameContext& frame, RendererState& state);

// Shadow pass: a depth map per light that is on, from the cache or rendered, and for a frame
// with a ground its ground visibility, held in state.shadow_layers at the light's rig index;
// the depth layers bound to texture unit 4 with the frame's comparison sampler. Counts the
// maps it rendered in result.shadow_maps_rendered.
void render_shadow_maps(const FrameContext& frame, RendererState& state, Frame& result);

// Ground visibility bake (part of the shadow pass): light `light`'s visibility over the ground
// plane at ground_height into map.ground_visibility, from the shadow layers' depth.
void bake_ground_visibility(const FrameContext& frame, RendererState& state, ShadowMap& map,
                            int light, float ground_height);

// Geometry pass: chooses frame.targets and fills their G-buffer (positions with ambient
// occlusion, shading normals with roughness, base colours with metallic, emitted radiance) at
// the supersampled size from the primitives that do not blend, the stencil holding each
// sample's surface kind.
void render_geometry(FrameContext& frame, RendererState& state);

// Attribute 4 of primitive `primitive` of object `object` (the geometry and transparent passes):
// its vertices' transferred irradiance in an occlusion frame, else (0, 0, 0).
void attach_object_transfer(const FrameContext& frame, const RendererState& state,
                            const GpuPrimitive& gpu, std::size_t object, std::size_t primitive);

// Shading pass: each G-buffer sample shaded once by its surface's program, routed by the
// stencil, into frame.targets->shaded (display-encoded at one sample per pixel without
// blending).
void shade_surfaces(const FrameContext& frame, RendererState& state);

// Transparent pass, for frames with BLEND primitives: each blended over frame.targets->shaded,
// farthest first, shaded as the shading pass shades objects.
void blend_transparent_surfaces(const FrameContext& frame, RendererState& state);

// Resolve pass, above one sample per pixel or after blending: the mean of each pixel's
// supersamples, then the display transform, into frame.targets->output.
void resolve_supersamples(const FrameContext& frame, RendererState& state);

// Readback: the finished frame into result.display or result.linear, top row first; leaves
// the default framebuffer, no program and no shadow sampler bound.
void read_back(const FrameContext& frame, Frame& result);

}  // namespace oer
