#include "shadow_layers.hpp"

namespace oer {

namespace {

// The depth array's comparison and filter come from the sampler bound with it (hard or PCF).
gl::Object make_array(GLenum format, GLint filter, int resolution, int layers) {
    gl::Object texture = gl::create_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(texture.get(), 1, format, resolution, resolution, layers);
    glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, filter);
    glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

void copy_layer(const gl::Object& from, const gl::Object& to, int layer, int resolution) {
    glCopyImageSubData(from.get(), GL_TEXTURE_2D, 0, 0, 0, 0, to.get(), GL_TEXTURE_2D_ARRAY, 0, 0,
                       0, layer, resolution, resolution, 1);
}

}  // namespace

void ShadowLayers::reserve(int layers, int resolution) {
    const auto matches = [&](const Set& set) {
        return set.layers == layers && set.resolution == resolution;
    };
    if (matches(current())) {
        return;
    }
    const std::size_t other = 1 - current_;
    current_ = other;
    if (matches(current())) {
        return;
    }
    Set& set = current();
    set.layers = layers;
    set.resolution = resolution;
    set.depth_serials.assign(std::size_t(layers), 0);
    set.ground_visibility_serials.assign(std::size_t(layers), 0);
    set.depth = make_array(GL_DEPTH_COMPONENT32F, GL_LINEAR, resolution, layers);
    set.ground_visibility = make_array(GL_R8, GL_LINEAR, resolution, layers);
}

void ShadowLayers::hold_depth(int layer, const ShadowMap& map) {
    Set& set = current();
    std::uint64_t& held = set.depth_serials.at(std::size_t(layer));
    if (held != map.serial) {
        copy_layer(map.depth, set.depth, layer, set.resolution);
        held = map.serial;
    }
}

void ShadowLayers::hold_ground_visibility(int layer, const ShadowMap& map) {
    Set& set = current();
    std::uint64_t& held = set.ground_visibility_serials.at(std::size_t(layer));
    if (held == map.serial) {
        return;
    }
    GLint baked = 0;
    glGetTextureLevelParameteriv(map.ground_visibility.get(), 0, GL_TEXTURE_WIDTH, &baked);
    if (baked == set.resolution) {
        copy_layer(map.ground_visibility, set.ground_visibility, layer, set.resolution);
    } else {
        // A soft light's bake is smaller than the layer: magnified bilinearly.
        if (!read_framebuffer_) {
            read_framebuffer_ = gl::create_framebuffer();
            draw_framebuffer_ = gl::create_framebuffer();
        }
        glNamedFramebufferTexture(read_framebuffer_.get(), GL_COLOR_ATTACHMENT0,
                                  map.ground_visibility.get(), 0);
        glNamedFramebufferTextureLayer(draw_framebuffer_.get(), GL_COLOR_ATTACHMENT0,
                                       set.ground_visibility.get(), 0, layer);
        glBlitNamedFramebuffer(read_framebuffer_.get(), draw_framebuffer_.get(), 0, 0, baked, baked,
                               0, 0, set.resolution, set.resolution, GL_COLOR_BUFFER_BIT,
                               GL_LINEAR);
    }
    held = map.serial;
}

}  // namespace oer
