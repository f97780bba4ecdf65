// Layered pass, for frames with materials that have the extensions' layers (mesh.hpp's
// Material::layered; docs/materials.md). Reads: the OPAQUE and MASK primitives of such
// materials and their materials (gl_bindings.hpp's kMaterialTextures), the depth and stencil of
// the geometry pass (targets), in an occlusion frame the transferred irradiance per vertex
// (lighting), everything the shading pass bound for objects (irradiance sets, shadow layers,
// specular cube, DFG table and sheen albedo) and the lights (frame). Writes: targets.shaded,
// which it returns, a float target in such frames (render_targets.hpp), at the samples whose
// stencil is kLayeredSurface: the geometry pass drew these primitives there, and the deferred
// shading pass, whose G-buffer holds no layers, left them. Each is drawn again with the depth
// test LEQUAL against its own depth (mesh.vert's gl_Position is invariant), not written, and
// shaded forward by the layered program. Leaves the depth and stencil tests and culling off,
// depth writes on, and the material units without samplers.
#include <algorithm>

#include "material_uniforms.hpp"
#include "oer/core/cancellation.hpp"
#include "passes/frame_passes.hpp"

namespace oer {

GLuint shade_layered_surfaces(const FrameContext& frame, const FrameLightingBuffers& lighting,
                              const RenderTargets& targets, RendererState& state,
                              const std::stop_token& stop) {
    const FrameRequest& request = frame.request;
    glBindFramebuffer(GL_FRAMEBUFFER, targets.shaded_framebuffer.get());
    glViewport(0, 0, frame.samples_wide, frame.samples_high);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0x00);
    glStencilFunc(GL_EQUAL, kLayeredSurface, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    const int band_rows = shading_band_rows(frame, stop);
    glEnable(GL_SCISSOR_TEST);
    for (int band = 0; band < frame.samples_high; band += band_rows) {
        throw_if_stopped(stop, "the frame's layered pass");
        glScissor(0, band, frame.samples_wide, std::min(band_rows, frame.samples_high - band));
        gl::Program* current = nullptr;
        for (std::size_t i = 0; i < request.objects.size(); ++i) {
            const Mesh& mesh = *request.objects[i].mesh;
            for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
                const Material& material = mesh.materials.at(
                    std::size_t(mesh.primitives[p].material_under(request.objects[i].variant)));
                if (material.alpha_mode == AlphaMode::Blend || !shaded_layered(frame, material)) {
                    continue;
                }
                // MASK ones cut where the geometry pass cut, or they would shade a layered surface
                // behind their holes.
                const bool alpha_test = material.alpha_mode == AlphaMode::Mask &&
                                        alpha_tested(material, mesh.primitives[p]);
                gl::Program& program =
                    state.program("layered", frame.lighting_defines + frame.specular_define +
                                                 frame.transfer_define + "#define ALPHA_TEST " +
                                                 (alpha_test ? "1" : "0") + "\n");
                draw_forward(frame, lighting, state, program, current, i, p);
            }
        }
        glFinish();
    }
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glStencilMask(0xff);
    glDisable(GL_STENCIL_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    unbind_material_samplers();
    return targets.shaded.get();
}

}  // namespace oer
