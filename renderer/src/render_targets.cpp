#include "render_targets.hpp"

#include "oer/error.hpp"

namespace oer {

namespace {
constexpr std::size_t kSizesKept = 4;
}  // namespace

RenderTargets& RenderTargetCache::get(int width, int height, int samples, GLenum format) {
    const auto key = std::make_tuple(width, height, samples, format);
    auto found = targets_.find(key);
    if (found != targets_.end()) {
        return found->second;
    }
    if (targets_.size() >= kSizesKept) {
        targets_.clear();
    }
    RenderTargets t;
    t.colour = gl::create_renderbuffer();
    t.depth = gl::create_renderbuffer();
    glNamedRenderbufferStorageMultisample(t.colour.get(), samples > 1 ? samples : 0, format, width,
                                          height);
    glNamedRenderbufferStorageMultisample(t.depth.get(), samples > 1 ? samples : 0,
                                          GL_DEPTH_COMPONENT24, width, height);
    t.framebuffer = gl::create_framebuffer();
    glNamedFramebufferRenderbuffer(t.framebuffer.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                   t.colour.get());
    glNamedFramebufferRenderbuffer(t.framebuffer.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                   t.depth.get());
    if (glCheckNamedFramebufferStatus(t.framebuffer.get(), GL_FRAMEBUFFER) !=
        GL_FRAMEBUFFER_COMPLETE) {
        throw Error(ErrorKind::Internal, "colour target framebuffer is incomplete");
    }
    t.resolved = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(t.resolved.get(), 1, format, width, height);
    t.resolved_framebuffer = gl::create_framebuffer();
    glNamedFramebufferTexture(t.resolved_framebuffer.get(), GL_COLOR_ATTACHMENT0, t.resolved.get(),
                              0);
    t.display = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(t.display.get(), 1, GL_RGBA8, width, height);
    t.display_framebuffer = gl::create_framebuffer();
    glNamedFramebufferTexture(t.display_framebuffer.get(), GL_COLOR_ATTACHMENT0, t.display.get(),
                              0);
    return targets_.emplace(key, std::move(t)).first->second;
}

}  // namespace oer
