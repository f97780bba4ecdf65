#include "render_targets.hpp"

#include <string>
#include <vector>

#include "oer/core/error.hpp"

namespace oer {

namespace {

constexpr std::size_t kSizesKept = 4;

gl::Object make_texture(GLenum format, int width, int height) {
    gl::Object texture = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.get(), 1, format, width, height);
    return texture;
}

gl::Object make_framebuffer(const std::vector<GLuint>& colors, GLuint depth, const char* what) {
    gl::Object framebuffer = gl::create_framebuffer();
    std::vector<GLenum> buffers;
    for (const GLuint color : colors) {
        const GLenum attachment = GL_COLOR_ATTACHMENT0 + GLenum(buffers.size());
        glNamedFramebufferTexture(framebuffer.get(), attachment, color, 0);
        buffers.push_back(attachment);
    }
    glNamedFramebufferDrawBuffers(framebuffer.get(), GLsizei(buffers.size()), buffers.data());
    if (depth != 0) {
        glNamedFramebufferRenderbuffer(framebuffer.get(), GL_DEPTH_STENCIL_ATTACHMENT,
                                       GL_RENDERBUFFER, depth);
    }
    if (glCheckNamedFramebufferStatus(framebuffer.get(), GL_FRAMEBUFFER) !=
        GL_FRAMEBUFFER_COMPLETE) {
        throw Error(ErrorKind::Internal, std::string("the ") + what + " framebuffer is incomplete");
    }
    return framebuffer;
}

}  // namespace

RenderTargets& RenderTargetCache::get(int width, int height, int scale, bool linear, bool blending,
                                      bool layered) {
    const auto key = std::make_tuple(width, height, scale, linear, blending, layered);
    auto found = targets_.find(key);
    if (found != targets_.end()) {
        return found->second;
    }
    if (targets_.size() >= kSizesKept) {
        targets_.clear();
    }
    const int samples_wide = width * scale;
    const int samples_high = height * scale;
    RenderTargets t;
    t.positions = make_texture(GL_RGBA32F, samples_wide, samples_high);
    // Half floats suffice under 8-bit output; linear output keeps full precision (0.8 as a half
    // float is off by 2.4e-4).
    const GLenum attribute_format = linear ? GL_RGBA32F : GL_RGBA16F;
    t.normals = make_texture(attribute_format, samples_wide, samples_high);
    t.albedos = make_texture(attribute_format, samples_wide, samples_high);
    t.emissive = make_texture(GL_RGBA16F, samples_wide, samples_high);
    t.transferred = make_texture(GL_RGBA16F, samples_wide, samples_high);
    t.depth = gl::create_renderbuffer();
    glNamedRenderbufferStorage(t.depth.get(), GL_DEPTH24_STENCIL8, samples_wide, samples_high);
    std::vector<GLuint> geometry_targets{t.positions.get(), t.normals.get(), t.albedos.get(),
                                         t.emissive.get(), t.transferred.get()};
    if (layered) {
        t.layers_first = make_texture(GL_RGBA32UI, samples_wide, samples_high);
        t.layers_second = make_texture(GL_RGBA32UI, samples_wide, samples_high);
        // An integer texture filtered linearly (GL's default) is incomplete, and reads as 0.
        for (const GLuint layers : {t.layers_first.get(), t.layers_second.get()}) {
            glTextureParameteri(layers, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(layers, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        }
        geometry_targets.insert(geometry_targets.end(),
                                {t.layers_first.get(), t.layers_second.get()});
    }
    t.geometry_framebuffer = make_framebuffer(geometry_targets, t.depth.get(), "geometry");
    // Blending needs radiance, not display values: a frame with transparent surfaces shades
    // into floats and resolves even at one sample per pixel.
    const bool resolves = scale > 1 || blending;
    const GLenum shaded_format = linear ? GL_RGBA32F : resolves ? GL_RGBA16F : GL_RGBA8;
    t.shaded = make_texture(shaded_format, samples_wide, samples_high);
    // The shading pass tests the geometry pass's stencil (the surface kind of each sample).
    t.shaded_framebuffer = make_framebuffer({t.shaded.get()}, t.depth.get(), "shading");
    if (resolves) {
        t.output = make_texture(linear ? GL_RGBA32F : GL_RGBA8, width, height);
        t.output_framebuffer = make_framebuffer({t.output.get()}, 0, "output");
    }
    return targets_.emplace(key, std::move(t)).first->second;
}

}  // namespace oer
