#pragma once
// The shadow maps and ground visibilities of a frame's lights as the layers of two array
// textures, so that the shading pass binds two textures whatever the number of lights (GPUs
// and llvmpipe offer 32 units at least, fewer than two per light of a 16-light rig). Layer k
// belongs to the rig's light k, so switching other lights on or off moves nothing; a layer is
// copied from the cache only when the map it should hold is not the one it holds.
//
// Two sets of arrays are kept, the two layouts (layer count, resolution) used last: the web
// client alternates previews (512-texel maps) with full frames (2048), and remaking and
// refilling one set at each switch cost 160-220 ms of a full frame on llvmpipe (measured by
// web/tests/browser_benchmark.mjs); a third layout replaces the one used least recently.
#include <GL/glcorearb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gl_objects.hpp"
#include "shadow_map_cache.hpp"

namespace oer {

class ShadowLayers {
  public:
    // Room for `layers` maps of resolution squared: the set of that layout, made (in place of
    // the set used least recently) when neither set has it.
    void reserve(int layers, int resolution);
    void hold_depth(int layer, const ShadowMap& map);
    void hold_ground_visibility(int layer, const ShadowMap& map);  // map's must be baked

    GLuint depth() const { return current().depth.get(); }
    GLuint ground_visibility() const { return current().ground_visibility.get(); }

  private:
    struct Set {
        int layers = 0;
        int resolution = 0;
        gl::Object depth;
        gl::Object ground_visibility;
        std::vector<std::uint64_t> depth_serials;  // per layer: the ShadowMap it holds, 0 none
        std::vector<std::uint64_t> ground_visibility_serials;
    };
    const Set& current() const { return sets_[current_]; }
    Set& current() { return sets_[current_]; }

    std::array<Set, 2> sets_;
    std::size_t current_ = 0;
    gl::Object read_framebuffer_;  // for magnifying a bake smaller than the layers
    gl::Object draw_framebuffer_;
};

}  // namespace oer
