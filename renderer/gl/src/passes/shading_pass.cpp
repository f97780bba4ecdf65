// Shading pass. Reads: the targets' G-buffer (with the layer targets in a frame with layered
// materials) and its stencil, the irradiance sets and in an occlusion frame the transferred
// irradiance (lighting), the environment map for its background, the shadow layers (shadows: the
// depth layers the shadow pass bound, the ground visibility bound here), the lights (frame), and in
// a specular frame the prefiltered cube and the DFG table (bound here for the transparent pass
// too), each at its binding of gl_bindings.hpp. Writes: targets.shaded, one shaded sample per
// G-buffer sample: linear radiance, or at one sample per pixel with display output and no blending
// the display-encoded color. Leaves the stencil test off and every texture and sampler bound, for
// the transparent pass.
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "gl_bindings.hpp"
#include "oer/core/cancellation.hpp"
#include "passes/frame_passes.hpp"
#include "surface_shading.hpp"

namespace oer {

FrameLightingBuffers upload_irradiance_sets(const FrameContext& frame, RendererState& state) {
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
    FrameLightingBuffers buffers;
    buffers.irradiance_sets = state.irradiance_buffer.get();
    if (!frame.transfer) {
        return buffers;
    }
    glNamedBufferData(
        state.transferred_vertex_buffer.get(),
        GLsizeiptr(std::max<std::size_t>(1, frame.transferred_vertices.size()) * sizeof(glm::vec3)),
        frame.transferred_vertices.data(), GL_STREAM_DRAW);
    buffers.transferred_vertices = state.transferred_vertex_buffer.get();
    const std::optional<GroundTransfer>& ground = frame.request.transfer->ground;
    if (!ground) {
        return buffers;
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
    buffers.ground_transfer = state.ground_transfer.get();
    return buffers;
}

namespace {

// The rows of samples the pass shades between two looks at the stop token: about 0.1-0.25 s of
// shading on llvmpipe (2^20 samples). Each band ends with a glFinish, which costs a frame of one
// band 15-20 % (measured with 256-row bands: the bunny's 512x512 colour pass went from 27 to
// 32 ms), so frames up to this size are one band, and a frame that cannot be stopped is never
// banded.
int shading_band_rows(const FrameContext& frame, const std::stop_token& stop) {
    constexpr long kShadingBandSamples = 1l << 20;
    return stop.stop_possible()
               ? std::max(1, int(kShadingBandSamples / std::max(1, frame.samples_wide)))
               : frame.samples_high;
}

}  // namespace

GLuint shade_surfaces(const FrameContext& frame, const FrameLightingBuffers& lighting,
                      const ShadowMaps& shadows, const RenderTargets& targets, RendererState& state,
                      const std::stop_token& stop) {
    using namespace gl_bindings;
    const FrameRequest& request = frame.request;
    const bool environment_background = request.background.kind == BackgroundKind::Environment;
    const bool display_in_shading = frame.scale == 1 && !request.linear && !frame.blending;
    const bool shadow_catcher = request.ground_look == GroundLook::ShadowCatcher;
    const std::string shading_defines =
        frame.lighting_defines + frame.transfer_define + "#define ENVIRONMENT_BACKGROUND " +
        std::to_string(environment_background ? 1 : 0) + "\n#define DISPLAY_OUTPUT " +
        std::to_string(display_in_shading ? 1 : 0) + "\n";
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kIrradianceSets.index, lighting.irradiance_sets);
    glBindTextureUnit(kGBufferPositions.index, targets.positions.get());
    glBindTextureUnit(kGBufferNormals.index, targets.normals.get());
    glBindTextureUnit(kGBufferAlbedos.index, targets.albedos.get());
    glBindTextureUnit(kGBufferEmissive.index, targets.emissive.get());
    if (frame.layered) {
        glBindTextureUnit(kGBufferLayersFirst.index, targets.layers_first.get());
        glBindTextureUnit(kGBufferLayersSecond.index, targets.layers_second.get());
    }
    if (environment_background) {
        glBindTextureUnit(kEnvironment.index, state.environment(request.environment_map));
    }
    // The ground's textures: for its own shading, and for what glossy objects reflect of it
    // (ground_lighting.glsl), here and in the transparent pass.
    if (frame.shadows) {
        glBindTextureUnit(kGroundVisibility.index, shadows.ground_visibility_layers);
    }
    if (frame.transfer && request.ground) {
        glBindTextureUnit(kGroundTransfer.index, lighting.ground_transfer);
    }
    bind_specular_textures(frame, state);
    glBindFramebuffer(GL_FRAMEBUFFER, targets.shaded_framebuffer.get());
    glBindVertexArray(state.empty_vertex_array.get());
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    // In bands of rows, each finished before the next starts, so that a frame asked to stop
    // stops within a band's time (a 2048 x 2048 shading pass takes about a second on llvmpipe
    // under load), not the whole pass's.
    const int band_rows = shading_band_rows(frame, stop);
    glEnable(GL_SCISSOR_TEST);
    for (int band = 0; band < frame.samples_high; band += band_rows) {
        throw_if_stopped(stop, "the frame's shading pass");
        glScissor(0, band, frame.samples_wide, std::min(band_rows, frame.samples_high - band));
        for (const int surface :
             {kBackgroundSurface, kObjectSurface, kLayeredSurface, kGroundSurface}) {
            if ((surface == kObjectSurface && request.objects.empty()) ||
                (surface == kLayeredSurface && !frame.layered) ||
                (surface == kGroundSurface && !request.ground)) {
                continue;
            }
            const bool object = surface == kObjectSurface || surface == kLayeredSurface;
            // Only objects have specular materials; the background and the ground take SPECULAR 0.
            const std::string specular_define =
                object ? frame.specular_define : "#define SPECULAR 0\n";
            // The shadow-catching ground (GroundLook::ShadowCatcher) is program SURFACE 3 of
            // the ground's samples.
            const int program =
                surface == kGroundSurface && shadow_catcher ? kShadowCatcherProgram : surface;
            gl::Program& shade =
                state.program("shade", shading_defines + specular_define + "#define SURFACE " +
                                           std::to_string(program) + "\n");
            glUseProgram(shade.id());
            set_surface_shading_uniforms(shade, frame);
            glUniformMatrix4fv(shade.uniform("u_inverse_view_projection"), 1, GL_FALSE,
                               glm::value_ptr(glm::inverse(frame.view_projection)));
            glUniform2f(shade.uniform("u_viewport_size"), float(frame.samples_wide),
                        float(frame.samples_high));
            if (frame.transfer && object) {
                glBindTextureUnit(kGBufferTransferred.index, targets.transferred.get());
            }
            if (surface == kGroundSurface) {
                glUniform4f(shade.uniform("u_ground_fade"), frame.scene.centre.x,
                            frame.scene.centre.z, frame.scene.ground_fade_start(),
                            frame.scene.ground_half_size());
                if (shadow_catcher) {
                    glUniform1f(shade.uniform("u_shadow_intensity"), request.shadows.intensity);
                }
            }
            if (display_in_shading) {
                set_display_uniforms(shade, request);
            }
            glStencilFunc(GL_EQUAL, surface, 0xff);
            glDrawArrays(GL_TRIANGLES, 0, 3);
        }
        glFinish();
    }
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    return targets.shaded.get();
}

}  // namespace oer
