#pragma once
// Shadow maps depend on the scene and the lights, not on the camera (DESIGN.md section 2,
// phase 3): depth textures kept by a key of scene, light direction and resolution, the least
// recently used dropped first.
#include <GL/glcorearb.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "gl_objects.hpp"

namespace oer {

class ShadowMapCache {
  public:
    explicit ShadowMapCache(std::size_t capacity);

    // The depth texture (GL_DEPTH_COMPONENT32F, resolution squared) stored under key. When it is
    // missing, it is made and draw_casters() renders into it, with its framebuffer bound, the
    // viewport set, depth cleared to 1 and tested, front faces culled and a slope-scaled bias
    // on; rendered tells which happened.
    GLuint get(const std::string& key, int resolution, const std::function<void()>& draw_casters,
               bool& rendered);

    std::size_t size() const { return entries_.size(); }

  private:
    struct Entry {
        gl::Object texture;
        std::uint64_t last_used = 0;
    };
    std::size_t capacity_;
    std::uint64_t clock_ = 0;
    std::map<std::string, Entry> entries_;
    gl::Object framebuffer_;
};

}  // namespace oer
