#include "shadow_map_cache.hpp"

#include <algorithm>

namespace oer {

ShadowMapCache::ShadowMapCache(std::size_t capacity)
    : capacity_(std::max<std::size_t>(1, capacity)), framebuffer_(gl::create_framebuffer()) {
    glNamedFramebufferDrawBuffer(framebuffer_.get(), GL_NONE);
}

ShadowMap& ShadowMapCache::get(const std::string& key, int resolution,
                               const std::function<void()>& draw_casters, bool& rendered) {
    ++clock_;
    auto found = entries_.find(key);
    rendered = found == entries_.end();
    if (rendered) {
        if (entries_.size() >= capacity_) {
            entries_.erase(std::min_element(entries_.begin(), entries_.end(),
                                            [](const auto& a, const auto& b) {
                                                return a.second.last_used < b.second.last_used;
                                            }));
        }
        ShadowMap entry;
        entry.serial = next_serial_++;
        entry.depth = gl::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(entry.depth.get(), 1, GL_DEPTH_COMPONENT32F, resolution, resolution);
        glNamedFramebufferTexture(framebuffer_.get(), GL_DEPTH_ATTACHMENT, entry.depth.get(), 0);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
        glViewport(0, 0, resolution, resolution);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_LESS);
        const float clear_depth = 1.0f;
        glClearNamedFramebufferfv(framebuffer_.get(), GL_DEPTH, 0, &clear_depth);
        // Front faces culled and a slope-scaled bias: the depths stored are of the casters'
        // back faces, pushed away, so lit surfaces do not shadow themselves.
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.5f, 2.0f);
        draw_casters();
        glDisable(GL_POLYGON_OFFSET_FILL);
        glDisable(GL_CULL_FACE);
        found = entries_.emplace(key, std::move(entry)).first;
    }
    found->second.last_used = clock_;
    return found->second;
}

}  // namespace oer
