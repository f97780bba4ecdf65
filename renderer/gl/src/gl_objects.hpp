#pragma once
// Owning handles for GL object names (GL 4.5 direct state access), so that every buffer,
// texture, framebuffer and vertex array is deleted exactly once, on the GL thread that made it.
#include <GL/glcorearb.h>

#include <utility>

namespace oer::gl {

class Object {
  public:
    using Deleter = void (*)(GLuint);
    Object() = default;
    Object(GLuint name, Deleter deleter) : name_(name), deleter_(deleter) {}
    Object(Object&& other) noexcept
        : name_(std::exchange(other.name_, 0)), deleter_(other.deleter_) {}
    Object& operator=(Object&& other) noexcept {
        if (this != &other) {
            reset();
            name_ = std::exchange(other.name_, 0);
            deleter_ = other.deleter_;
        }
        return *this;
    }
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    ~Object() { reset(); }

    GLuint get() const { return name_; }
    explicit operator bool() const { return name_ != 0; }
    void reset() {
        if (name_ != 0 && deleter_ != nullptr) {
            deleter_(name_);
        }
        name_ = 0;
    }

  private:
    GLuint name_ = 0;
    Deleter deleter_ = nullptr;
};

Object create_buffer();
Object create_texture(GLenum target);
Object create_framebuffer();
Object create_renderbuffer();
Object create_vertex_array();
Object create_sampler();

}  // namespace oer::gl
