#pragma once
// The frame's render targets, kept between frames of the same size and format: fresh ones cost
// a page fault per 4 KiB on first touch, several milliseconds a frame on llvmpipe.
//
// Deferred shading: the geometry pass fills the G-buffer at the supersampled size (width and
// height times the anti-aliasing scale), the shading pass shades it into `shaded`, the
// transparent pass blends the BLEND primitives over it, and when the scale is above 1 or the
// transparent pass ran the resolve pass averages the supersamples into `output`.
#include <GL/glcorearb.h>

#include <map>
#include <tuple>

#include "gl_objects.hpp"

namespace oer {

struct RenderTargets {
    gl::Object positions;    // RGBA32F: world position, ambient occlusion
    gl::Object normals;      // RGBA16F (RGBA32F for linear output): shading normal, roughness
    gl::Object albedos;      // RGBA16F (RGBA32F for linear output): base colour, metallic or -1
    gl::Object emissive;     // RGBA16F: emitted radiance
    gl::Object transferred;  // RGBA16F: the transfer's irradiance (occlusion frames only)
    // Frames with layered materials only, RGBA32UI: their layers, packed (layer_gbuffer.glsl).
    gl::Object layers_first;
    gl::Object layers_second;
    gl::Object depth;  // and stencil: the surface kind of each sample (0 background)
    gl::Object geometry_framebuffer;
    // linear: RGBA32F; display: RGBA8 at scale 1 without forward passes, RGBA16F otherwise
    gl::Object shaded;
    gl::Object shaded_framebuffer;
    // scale above 1 or blending only: RGBA32F (linear) or RGBA8 (display)
    gl::Object output;
    gl::Object output_framebuffer;
};

class RenderTargetCache {
  public:
    // The targets of a width x height frame supersampled scale x scale, with linear (float)
    // or display (8-bit sRGB) output, with transparent surfaces blended over it or not, and with
    // the layer targets or not; at most a few sizes are kept.
    RenderTargets& get(int width, int height, int scale, bool linear, bool blending, bool layered);

  private:
    std::map<std::tuple<int, int, int, bool, bool, bool>, RenderTargets> targets_;
};

}  // namespace oer
