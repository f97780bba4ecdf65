#pragma once
// The colour pass's render targets, kept between frames of the same size and format: fresh
// ones cost a page fault per 4 KiB on first touch, several milliseconds a frame on llvmpipe.
#include <GL/glcorearb.h>

#include <map>
#include <tuple>

#include "gl_objects.hpp"

namespace oer {

struct RenderTargets {
    gl::Object colour;  // multisampled (or not) float colour
    gl::Object depth;
    gl::Object framebuffer;
    gl::Object resolved;  // single-sample float colour
    gl::Object resolved_framebuffer;
    gl::Object display;  // RGBA8 after tone mapping
    gl::Object display_framebuffer;
};

class RenderTargetCache {
  public:
    // The targets of a width x height frame with `samples` samples of a float `format`; at most
    // a few sizes are kept.
    RenderTargets& get(int width, int height, int samples, GLenum format);

  private:
    std::map<std::tuple<int, int, int, GLenum>, RenderTargets> targets_;
};

}  // namespace oer
