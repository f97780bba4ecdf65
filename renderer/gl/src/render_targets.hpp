#pragma once
// The frame's render targets, kept between frames of the same size and format: fresh ones cost
// a page fault per 4 KiB on first touch, several milliseconds a frame on llvmpipe.
//
// Deferred shading: the geometry pass fills the G-buffer at the supersampled size (width and
// height times the anti-aliasing scale), the shading pass shades it into `shaded`, and when
// the scale is above 1 the resolve pass averages the supersamples into `output`.
#include <GL/glcorearb.h>

#include <map>
#include <tuple>

#include "gl_objects.hpp"

namespace oer {

struct RenderTargets {
    gl::Object positions;  // RGBA32F: world position
    gl::Object normals;    // RGBA16F (RGBA32F for linear output): world normal, shininess
    gl::Object albedos;    // RGBA16F (RGBA32F for linear output): albedo, specular weight
    gl::Object depth;      // and stencil: the surface kind of each sample (0 background)
    gl::Object geometry_framebuffer;
    gl::Object shaded;  // linear: RGBA32F; display: RGBA8 at scale 1, RGBA16F above
    gl::Object shaded_framebuffer;
    gl::Object output;  // scale above 1 only: RGBA32F (linear) or RGBA8 (display)
    gl::Object output_framebuffer;

    // The texture holding the finished frame.
    GLuint result() const { return output ? output.get() : shaded.get(); }
};

class RenderTargetCache {
  public:
    // The targets of a width x height frame supersampled scale x scale, with linear (float)
    // or display (8-bit sRGB) output; at most a few sizes are kept.
    RenderTargets& get(int width, int height, int scale, bool linear);

  private:
    std::map<std::tuple<int, int, int, bool>, RenderTargets> targets_;
};

}  // namespace oer
