// Resolve pass, for frames of more than one sample per pixel or with blended surfaces. Reads:
// `shaded` (the targets' shaded texture), linear radiance at scale x scale samples per pixel.
// Writes: targets.output, which it returns, each pixel the mean of its samples' radiance, then
// (display output) exposed, tone mapped and sRGB-encoded: averaging before tone mapping, as a
// camera's pixel integrates light.
#include <string>

#include "gl_bindings.hpp"
#include "passes/frame_passes.hpp"

namespace oer {

GLuint resolve_supersamples(const FrameContext& frame, GLuint shaded, const RenderTargets& targets,
                            RendererState& state) {
    const FrameRequest& request = frame.request;
    gl::Program& resolve = state.program(
        "resolve", "#define DISPLAY_OUTPUT " + std::to_string(request.linear ? 0 : 1) + "\n");
    glUseProgram(resolve.id());
    glUniform1i(resolve.uniform("u_scale"), frame.scale);
    if (!request.linear) {
        set_display_uniforms(resolve, request);
    }
    glBindTextureUnit(gl_bindings::kResolveRadiance.index, shaded);
    glBindFramebuffer(GL_FRAMEBUFFER, targets.output_framebuffer.get());
    glViewport(0, 0, request.width, request.height);
    glBindVertexArray(state.empty_vertex_array.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    return targets.output.get();
}

}  // namespace oer
