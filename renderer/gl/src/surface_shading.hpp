#pragma once
// The uniforms and textures of surface_shading.glsl, which shades objects in the deferred
// shading pass and the transparent pass alike: the lights (set_light_uniforms), the yaw, the
// eye, the lighting model's scales, and in a specular frame the prefiltered cubes (the
// residual's and each light's), their lights' layers and weights, and the DFG table.
#include "frame_context.hpp"
#include "gl_program.hpp"
#include "renderer_state.hpp"

namespace oer {

// Binds the specular frame's cube (FrameRequest::specular) and the DFG table to gl_bindings.hpp's
// kSpecularCube and kDfgTable, and in a frame with layers (FrameContext::layered) the sheen
// albedo to kSheenAlbedo; a frame that is not specular binds none, so that none is uploaded.
void bind_specular_textures(const FrameContext& frame, RendererState& state);

// Sets the uniforms of surface_shading.glsl on `program` (in use).
void set_surface_shading_uniforms(gl::Program& program, const FrameContext& frame);

}  // namespace oer
