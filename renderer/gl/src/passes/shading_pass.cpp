// Shading pass. Reads: the G-buffer of frame.targets (texture units 0 to 2) and its stencil,
// the irradiance sets (state.irradiance_buffer, shader storage binding 0), the environment map
// (unit 3) for its background, the shadow layers (units 4 and 5) and the lights (frame).
// Writes: frame.targets->shaded, one shaded sample per G-buffer sample: linear radiance, or at
// one sample per pixel with display output the display-encoded color. Leaves the stencil test
// off and unit 4 without a sampler.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "passes/frame_passes.hpp"

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
}

void shade_surfaces(const FrameContext& frame, RendererState& state) {
    const FrameRequest& request = frame.request;
    const Rig& rig = frame.rig;
    const RenderTargets& targets = *frame.targets;
    const bool environment_background = request.background.kind == BackgroundKind::Environment;
    const bool display_in_shading = frame.scale == 1 && !request.linear;
    const std::string shading_defines = frame.lighting_defines + "#define ENVIRONMENT_BACKGROUND " +
                                        std::to_string(environment_background ? 1 : 0) +
                                        "\n#define DISPLAY_OUTPUT " +
                                        std::to_string(display_in_shading ? 1 : 0) + "\n";
    // The ground's normal is +Y, which the yaw leaves unchanged.
    std::vector<glm::vec3> flat_irradiance;
    for (const ShRgb& set : frame.irradiance_sets) {
        flat_irradiance.push_back(glm::vec3(set.evaluate({0.0, 1.0, 0.0})));
    }
    const bool thesis = rig.model == LightingModel::Thesis;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, state.irradiance_buffer.get());
    glBindTextureUnit(0, targets.positions.get());
    glBindTextureUnit(1, targets.normals.get());
    glBindTextureUnit(2, targets.albedos.get());
    if (environment_background) {
        glBindTextureUnit(3, state.environment(request.environment_map));
    }
    if (frame.shadows) {
        glBindTextureUnit(5, state.shadow_layers.ground_visibility());
    }
    glBindFramebuffer(GL_FRAMEBUFFER, targets.shaded_framebuffer.get());
    glBindVertexArray(state.empty_vertex_array.get());
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    for (const int surface : {kBackgroundSurface, kObjectSurface, kGroundSurface}) {
        if ((surface == kObjectSurface && request.objects.empty()) ||
            (surface == kGroundSurface && !request.ground)) {
            continue;
        }
        gl::Program& shade = state.program(
            "shade", shading_defines + "#define SURFACE " + std::to_string(surface) + "\n");
        glUseProgram(shade.id());
        set_light_uniforms(shade, frame);
        glUniformMatrix4fv(shade.uniform("u_inverse_view_projection"), 1, GL_FALSE,
                           glm::value_ptr(glm::inverse(frame.view_projection)));
        glUniform2f(shade.uniform("u_viewport_size"), float(frame.samples_wide),
                    float(frame.samples_high));
        glUniform2f(shade.uniform("u_yaw"), frame.yaw_cos_sin.x, frame.yaw_cos_sin.y);
        glUniform3fv(shade.uniform("u_eye"), 1, glm::value_ptr(frame.camera.eye));
        glUniform1f(shade.uniform("u_albedo_scale"), thesis ? 1.0f : float(1.0 / std::numbers::pi));
        glUniform1f(shade.uniform("u_attenuation_base"), float(frame.attenuation_base));
        glUniform3fv(shade.uniform("u_flat_irradiance"), GLsizei(flat_irradiance.size()),
                     glm::value_ptr(flat_irradiance[0]));
        for (std::size_t i = 0; i < frame.lit.size(); ++i) {
            const std::size_t k = frame.lit[i];
            const double weight = frame.weights[k];
            // Intensity from the light's own SH: sum L dOmega = sqrt(4 pi) c_00, in the units
            // of the projected map (radiance in the hdr model, tone-mapped values in the
            // thesis's), times its weight. The share is weighted as its irradiance set is
            // (frame_context.hpp).
            const glm::vec3 intensity = glm::vec3(rig.sh.per_light[k].coefficients[0] *
                                                  (weight * std::sqrt(4.0 * std::numbers::pi)));
            glUniform3fv(shade.uniform(element("u_light_direction", i)), 1,
                         glm::value_ptr(frame.light_directions[i]));
            glUniform3fv(shade.uniform(element("u_light_intensity", i)), 1,
                         glm::value_ptr(intensity));
            glUniform1f(shade.uniform(element("u_light_share", i)),
                        thesis ? float(weight * rig.lights[k].luminance_share) : 0.0f);
        }
        if (display_in_shading) {
            set_display_uniforms(shade, request);
        }
        glStencilFunc(GL_EQUAL, surface, 0xff);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glDisable(GL_STENCIL_TEST);
    glBindSampler(4, 0);
    glBindSampler(6, 0);
}

}  // namespace oer
