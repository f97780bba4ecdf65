#pragma once
// The shadow maps and ground visibilities of a frame's lights as the layers of two array
// textures, so that the shading pass binds two textures whatever the number of lights (GPUs
// and llvmpipe offer 32 units at least, fewer than two per light of a 16-light rig). Layer k
// belongs to the rig's light k, so switching other lights on or off moves nothing; a layer is
// copied from the cache only when the map it should hold is not the one it holds.
#include <GL/glcorearb.h>

#include <cstdint>
#include <vector>

#include "gl_objects.hpp"
#include "shadow_map_cache.hpp"

namespace oer {

class ShadowLayers {
  public:
    // Room for `layers` maps of resolution squared; the arrays are remade when either changes.
    void reserve(int layers, int resolution);
    void hold_depth(int layer, const ShadowMap& map);
    void hold_ground_visibility(int layer, const ShadowMap& map);  // map's must be baked

    GLuint depth() const { return depth_.get(); }
    GLuint ground_visibility() const { return ground_visibility_.get(); }

  private:
    gl::Object depth_;
    gl::Object ground_visibility_;
    int layers_ = 0;
    int resolution_ = 0;
    std::vector<std::uint64_t> depth_serials_;  // per layer: the ShadowMap it holds, 0 none
    std::vector<std::uint64_t> ground_visibility_serials_;
    gl::Object read_framebuffer_;  // for magnifying a bake smaller than the layers
    gl::Object draw_framebuffer_;
};

}  // namespace oer
