#pragma once
// The frame's render targets, kept between frames of the same size and format: fresh ones cost
// a page fault per 4 KiB on first touch, several milliseconds a frame on llvmpipe.
//
// Deferred shading: the geometry pass fills the G-buffer at the supersampled size (width and
// height times the anti-aliasing scale), the shading pass shades it into `shaded`, the layered
// pass shades the materials with layers into it, the transparent pass blends the BLEND
// primitives over it, and when the scale is above 1 or a forward pass (layered or transparent)
// ran the resolve pass averages the supersamples into `output`.
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
    gl::Object depth;        // and stencil: the surface kind of each sample (0 background)
    gl::Object geometry_framebuffer;
    // linear: RGBA32F; display: RGBA8 at scale 1 without forward passes, RGBA16F otherwise
    gl::Object shaded;
    gl::Object shaded_framebuffer;
    // scale above 1 or forward passes only: RGBA32F (linear) or RGBA8 (display)
    gl::Object output;
    gl::Object output_framebuffer;
};

class RenderTargetCache {
  public:
    // The targets of a width x height frame supersampled scale x scale, with linear (float)
    // or display (8-bit sRGB) output, and forward passes (layered or transparent surfaces) shaded
    // over it or not; at most a few sizes are kept.
    RenderTargets& get(int width, int height, int scale, bool linear, bool forward_passes);

  private:
    std::map<std::tuple<int, int, int, bool, bool>, RenderTargets> targets_;
};

}  // namespace oer
