#pragma once
// Shadow maps depend on the scene and the lights, not on the camera (docs/design.md section 2,
// phase 3): depth textures kept by a key of scene, light and resolution, the least recently
// used dropped first. Each entry also keeps its light's visibility on the ground plane once
// it has been baked, so moving the camera or switching other lights re-renders nothing.
#include <GL/glcorearb.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "gl_objects.hpp"

namespace oer {

struct ShadowMap {
    gl::Object depth;              // GL_DEPTH_COMPONENT32F, resolution squared
    gl::Object ground_visibility;  // GL_R8, at most the depth's size; empty until baked
    std::uint64_t serial = 0;      // unique over the cache's life: identifies the contents
    std::uint64_t last_used = 0;
};

class ShadowMapCache {
  public:
    explicit ShadowMapCache(std::size_t capacity);

    // The shadow map stored under key. When it is missing, it is made and draw_casters()
    // renders into it, with its framebuffer bound, the viewport set, depth cleared to 1 and
    // tested, front faces culled and a slope-scaled bias on; rendered tells which happened.
    // The reference is valid until the next call.
    ShadowMap& get(const std::string& key, int resolution,
                   const std::function<void()>& draw_casters, bool& rendered);

    std::size_t size() const { return entries_.size(); }

  private:
    std::size_t capacity_;
    std::uint64_t clock_ = 0;
    std::uint64_t next_serial_ = 1;
    std::map<std::string, ShadowMap> entries_;
    gl::Object framebuffer_;
};

}  // namespace oer
