// Ground visibility bake. Reads: the shadow layers' depth (kShadowMaps and kShadowDepths of
// gl_bindings.hpp, bound by the shadow pass) and the light's uniforms (frame). Returns a new R8
// texture of the light's visibility over the ground plane, which the shadow pass keeps with the
// light's map in the cache; leaves state.bake_framebuffer bound.
//
// A soft shadow is sharp where it touches its caster (PCSS: the penumbra grows from zero at the
// contact), so the bake keeps half the shadow map's resolution: two shadow texels per bake
// texel, finer than the one-texel kernel of a contact shadow's filter taps spread.
#include <algorithm>

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "passes/frame_passes.hpp"

namespace oer {

gl::Object bake_ground_visibility(const FrameContext& frame, RendererState& state, int light,
                                  float ground_height) {
    const int resolution =
        frame.pcf ? std::max(64, frame.shadow_resolution / 2) : frame.shadow_resolution;
    const glm::mat4 inverse_light_matrix = glm::inverse(frame.light_matrices[std::size_t(light)]);
    gl::Object visibility = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(visibility.get(), 1, GL_R8, resolution, resolution);
    glNamedFramebufferTexture(state.bake_framebuffer.get(), GL_COLOR_ATTACHMENT0, visibility.get(),
                              0);
    glBindFramebuffer(GL_FRAMEBUFFER, state.bake_framebuffer.get());
    glViewport(0, 0, resolution, resolution);
    glDisable(GL_DEPTH_TEST);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl::Program& bake = state.program("ground visibility", frame.lighting_defines);
    glUseProgram(bake.id());
    set_light_uniforms(bake, frame);
    glUniformMatrix4fv(bake.uniform("u_inverse_light_matrix"), 1, GL_FALSE,
                       glm::value_ptr(inverse_light_matrix));
    glUniform1f(bake.uniform("u_ground_height"), ground_height);
    glUniform1i(bake.uniform("u_light"), light);
    glUniform2f(bake.uniform("u_size"), float(resolution), float(resolution));
    glBindVertexArray(state.empty_vertex_array.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    return visibility;
}

}  // namespace oer
