// Shading pass. Reads: the G-buffer of frame.targets (texture units 0 to 2, and 7 for the
// emissive) and its stencil, the irradiance sets (state.irradiance_buffer, shader storage
// binding 0), the environment map (unit 3) for its background, the shadow layers (units 4 to 6),
// the lights (frame), and in a specular frame the prefiltered cube and the DFG table (units 8
// and 9, bound here for the transparent pass too). Writes: frame.targets->shaded, one shaded
// sample per G-buffer sample: linear radiance, or at one sample per pixel with display output
// and no blending the display-encoded color. Leaves the stencil test off and every texture and
// sampler bound, for the transparent pass.
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "passes/frame_passes.hpp"
#include "surface_shading.hpp"

namespace oer {

void upload_irradiance_sets(const FrameContext& frame, RendererState& state) {
    const int order = frame.rig.sh.all.order;
    const int count = order * order;
    std::vector<float> packed;
    packed.reserve(frame.irradiance_sets.size() * count * 4);
    for (const ShRgb& set : frame.irradiance_sets) {
        for (const glm::dvec3& c : set.coefficients) {
            packed.insert(packed.end(), {float(c.r), float(c.g), float(c.b), 0.0f});
        }
    }
    glNamedBufferData(state.irradiance_buffer.get(), GLsizeiptr(packed.size() * sizeof(float)),
                      packed.data(), GL_DYNAMIC_DRAW);
    if (!frame.transfer) {
        return;
    }
    glNamedBufferData(
        state.transferred_vertex_buffer.get(),
        GLsizeiptr(std::max<std::size_t>(1, frame.transferred_vertices.size()) * sizeof(glm::vec3)),
        frame.transferred_vertices.data(), GL_STREAM_DRAW);
    const std::optional<GroundTransfer>& ground = frame.request.transfer->ground;
    if (!ground) {
        return;
    }
    if (state.ground_transfer_resolution != ground->resolution) {
        state.ground_transfer = gl::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(state.ground_transfer.get(), 1, GL_RGB32F, ground->resolution,
                           ground->resolution);
        glTextureParameteri(state.ground_transfer.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(state.ground_transfer.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(state.ground_transfer.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(state.ground_transfer.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        state.ground_transfer_resolution = ground->resolution;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(state.ground_transfer.get(), 0, 0, 0, ground->resolution,
                        ground->resolution, GL_RGB, GL_FLOAT, frame.transferred_ground.data());
}

void shade_surfaces(const FrameContext& frame, RendererState& state) {
    const FrameRequest& request = frame.request;
    const RenderTargets& targets = *frame.targets;
    const bool environment_background = request.background.kind == BackgroundKind::Environment;
    const bool display_in_shading = frame.scale == 1 && !request.linear && !frame.blending;
    const std::string shading_defines =
        frame.lighting_defines + frame.transfer_define + "#define ENVIRONMENT_BACKGROUND " +
        std::to_string(environment_background ? 1 : 0) + "\n#define DISPLAY_OUTPUT " +
        std::to_string(display_in_shading ? 1 : 0) + "\n";
    // The ground's normal is +Y, which the yaw leaves unchanged.
    std::vector<glm::vec3> flat_irradiance;
    for (const ShRgb& set : frame.irradiance_sets) {
        flat_irradiance.push_back(glm::vec3(set.evaluate({0.0, 1.0, 0.0})));
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, state.irradiance_buffer.get());
    glBindTextureUnit(0, targets.positions.get());
    glBindTextureUnit(1, targets.normals.get());
    glBindTextureUnit(2, targets.albedos.get());
    glBindTextureUnit(7, targets.emissive.get());
    if (environment_background) {
        glBindTextureUnit(3, state.environment(request.environment_map));
    }
    if (frame.shadows) {
        glBindTextureUnit(5, state.shadow_layers.ground_visibility());
    }
    bind_specular_textures(frame, state);
    glBindFramebuffer(GL_FRAMEBUFFER, targets.shaded_framebuffer.get());
    glBindVertexArray(state.empty_vertex_array.get());
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    for (const int surface : {kBackgroundSurface, kObjectSurface, kGroundSurface}) {
        if ((surface == kObjectSurface && request.objects.empty()) ||
            (surface == kGroundSurface && !request.ground)) {
            continue;
        }
        // Only objects have specular materials; the background and the ground take SPECULAR 0.
        const std::string specular_define =
            surface == kObjectSurface ? frame.specular_define : "#define SPECULAR 0\n";
        gl::Program& shade =
            state.program("shade", shading_defines + specular_define + "#define SURFACE " +
                                       std::to_string(surface) + "\n");
        glUseProgram(shade.id());
        set_surface_shading_uniforms(shade, frame);
        glUniformMatrix4fv(shade.uniform("u_inverse_view_projection"), 1, GL_FALSE,
                           glm::value_ptr(glm::inverse(frame.view_projection)));
        glUniform2f(shade.uniform("u_viewport_size"), float(frame.samples_wide),
                    float(frame.samples_high));
        glUniform3fv(shade.uniform("u_flat_irradiance"), GLsizei(flat_irradiance.size()),
                     glm::value_ptr(flat_irradiance[0]));
        if (frame.transfer && surface == kObjectSurface) {
            glBindTextureUnit(15, targets.transferred.get());
        }
        if (frame.transfer && surface == kGroundSurface) {
            const GroundTransfer& ground = *request.transfer->ground;
            glBindTextureUnit(15, state.ground_transfer.get());
            glUniform4f(shade.uniform("u_ground_transfer_rect"), ground.centre.x - ground.half_size,
                        ground.centre.y - ground.half_size, 0.5f / ground.half_size, 0.0f);
        }
        if (display_in_shading) {
            set_display_uniforms(shade, request);
        }
        glStencilFunc(GL_EQUAL, surface, 0xff);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glDisable(GL_STENCIL_TEST);
}

}  // namespace oer
