#pragma once
// The passes of a frame, in the order FrameRenderer::render runs them, each in its own file.
// The division follows Filament's (ShadowMapManager for the shadow maps, Renderer for the
// color passes, PostProcessManager for the resolve), and like the passes of Filament's frame
// graph each states what it reads and what it writes, here in its signature: it takes the
// FrameContext (the request and what follows from it before any GL call) and the products of
// the passes before it as const references, and returns its own product, so that
// FrameRenderer::render spells out the frame's data flow. Every pass also takes the
// RendererState, the caches kept between frames (programs, meshes, maps, render targets, the
// buffers the setup fills), which a pass fills on first use. The texture units and buffer
// bindings a pass binds for the shaders are gl_bindings.hpp's.
#include <GL/glcorearb.h>

#include <cstddef>
#include <stop_token>

#include "frame_context.hpp"
#include "gl_objects.hpp"
#include "oer/scene/frame_request.hpp"
#include "render_targets.hpp"
#include "renderer_state.hpp"

namespace oer {

// What the setup leaves on the GPU for the passes after it.
struct FrameLightingBuffers {
    GLuint irradiance_sets = 0;  // shader storage: the frame's SH irradiance sets, packed
    // Occlusion frames: the transferred irradiance per vertex of every object's primitives (RGB
    // floats, FrameContext::transferred_vertices, for attribute 4) and, with the ground, over
    // its grid (RGB32F texture); 0 otherwise.
    GLuint transferred_vertices = 0;
    GLuint ground_transfer = 0;
};

// Setup (shading_pass.cpp): the frame's irradiance sets uploaded, and in an occlusion frame its
// transferred irradiance, into the buffers of `state` that the result names.
FrameLightingBuffers upload_irradiance_sets(const FrameContext& frame, RendererState& state);

// What the shadow pass leaves for the passes after it.
struct ShadowMaps {
    // Frames with shadows: the array of the lights' ground visibilities, layer k rig light k's
    // (filled in frames with a ground); 0 without shadows. The depth array, of the lights'
    // shadow maps, stays bound to kShadowMaps with the frame's comparison sampler (PCF or hard)
    // and, with PCF, to kShadowDepths with a nearest sampler, for the bake and every pass after.
    GLuint ground_visibility_layers = 0;
    int rendered = 0;  // shadow maps rendered this frame; the others came from the cache
};

// Shadow pass: a depth map per light that is on, from the cache or rendered, and for a frame
// with a ground its ground visibility, held in state.shadow_layers at the light's rig index.
// Looks at stop before each light (throwing Cancelled once it is requested): sixteen lights at
// a large resolution take seconds.
ShadowMaps render_shadow_maps(const FrameContext& frame, RendererState& state,
                              const std::stop_token& stop);

// Ground visibility bake (part of the shadow pass): the visibility of the frame's light
// `light` (its index among the lights that are on) over the ground plane at ground_height, a
// new texture, from the depth layers the shadow pass bound.
gl::Object bake_ground_visibility(const FrameContext& frame, RendererState& state, int light,
                                  float ground_height);

// Geometry pass: the frame's targets, chosen from state.targets, with their G-buffer filled
// (positions with ambient occlusion, shading normals with roughness, base colours with
// metallic, emitted radiance, and in an occlusion frame the transferred irradiance) at the
// supersampled size from the primitives that do not blend, the stencil holding each sample's
// surface kind.
RenderTargets& render_geometry(const FrameContext& frame, const FrameLightingBuffers& lighting,
                               RendererState& state);

// Attribute 4 of primitive `primitive` of object `object` (the geometry and transparent passes):
// its vertices' transferred irradiance in an occlusion frame, else (0, 0, 0).
void attach_object_transfer(const FrameContext& frame, const FrameLightingBuffers& lighting,
                            const GpuPrimitive& gpu, std::size_t object, std::size_t primitive);

// Shading pass: each sample of the targets' G-buffer shaded once by its surface's program,
// routed by the stencil, into targets.shaded (display-encoded at one sample per pixel without
// blending), which it returns.
GLuint shade_surfaces(const FrameContext& frame, const FrameLightingBuffers& lighting,
                      const ShadowMaps& shadows, const RenderTargets& targets, RendererState& state,
                      const std::stop_token& stop);

// Transparent pass, for frames with BLEND primitives: each blended over targets.shaded, the
// shading pass's product, farthest first, shaded as the shading pass shades objects (with the
// textures and buffers it left bound); returns targets.shaded.
GLuint blend_transparent_surfaces(const FrameContext& frame, const FrameLightingBuffers& lighting,
                                  const RenderTargets& targets, RendererState& state);

// Resolve pass, above one sample per pixel or after blending: the mean of each pixel's
// supersamples in `shaded`, then the display transform, into targets.output, which it returns.
GLuint resolve_supersamples(const FrameContext& frame, GLuint shaded, const RenderTargets& targets,
                            RendererState& state);

// Readback: the finished frame, the texture `finished` of the request's size, into
// result.display or result.linear, top row first; then leave_frame_state.
void read_back(const FrameRequest& request, GLuint finished, Frame& result);

// GL as a frame found it: the default framebuffer, depth writes on, no vertex array, program or
// shadow sampler bound.
void leave_frame_state();

}  // namespace oer
