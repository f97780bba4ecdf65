#include "gl_objects.hpp"

namespace oer::gl {

Object create_buffer() {
    GLuint name = 0;
    glCreateBuffers(1, &name);
    return {name, [](GLuint n) { glDeleteBuffers(1, &n); }};
}

Object create_texture(GLenum target) {
    GLuint name = 0;
    glCreateTextures(target, 1, &name);
    return {name, [](GLuint n) { glDeleteTextures(1, &n); }};
}

Object create_framebuffer() {
    GLuint name = 0;
    glCreateFramebuffers(1, &name);
    return {name, [](GLuint n) { glDeleteFramebuffers(1, &n); }};
}

Object create_renderbuffer() {
    GLuint name = 0;
    glCreateRenderbuffers(1, &name);
    return {name, [](GLuint n) { glDeleteRenderbuffers(1, &n); }};
}

Object create_vertex_array() {
    GLuint name = 0;
    glCreateVertexArrays(1, &name);
    return {name, [](GLuint n) { glDeleteVertexArrays(1, &n); }};
}

Object create_sampler() {
    GLuint name = 0;
    glCreateSamplers(1, &name);
    return {name, [](GLuint n) { glDeleteSamplers(1, &n); }};
}

}  // namespace oer::gl
