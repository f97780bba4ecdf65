// Geometry pass. Reads: the objects, their meshes' levels of detail and materials, the ground
// (frame, state.mesh and state.ground), the camera. Writes: frame.targets, chosen by size and
// format from state.targets, with its G-buffer filled at the supersampled size: positions,
// normals with shininess, albedos with specular weight, depth, and in the stencil each
// sample's surface kind (kBackgroundSurface where nothing was drawn).
#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "passes/frame_passes.hpp"

namespace oer {

void render_geometry(FrameContext& frame, RendererState& state) {
    const FrameRequest& request = frame.request;
    const Camera& camera = frame.camera;
    RenderTargets& targets =
        state.targets.get(request.width, request.height, frame.scale, request.linear);
    frame.targets = &targets;
    glBindFramebuffer(GL_FRAMEBUFFER, targets.geometry_framebuffer.get());
    glViewport(0, 0, frame.samples_wide, frame.samples_high);
    // Clears honour the write masks, which the previous frame's passes may have left off.
    glDepthMask(GL_TRUE);
    for (GLuint buffer = 0; buffer < 3; ++buffer) {
        glColorMaski(buffer, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        const float clear_color[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearNamedFramebufferfv(targets.geometry_framebuffer.get(), GL_COLOR, GLint(buffer),
                                  clear_color);
    }
    glStencilMask(0xff);
    glClearNamedFramebufferfi(targets.geometry_framebuffer.get(), GL_DEPTH_STENCIL, 0, 1.0f,
                              kBackgroundSurface);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_STENCIL_TEST);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    gl::Program& geometry = state.program("geometry", "");
    glUseProgram(geometry.id());
    glUniformMatrix4fv(geometry.uniform("u_view_projection"), 1, GL_FALSE,
                       glm::value_ptr(frame.view_projection));
    glUniform3fv(geometry.uniform("u_eye"), 1, glm::value_ptr(camera.eye));
    // Detail down to one sample at the nearest point of a mesh's bounding sphere. A level's
    // stated error already carries a fivefold margin over meshoptimizer's (mesh_lod.cpp), and
    // a sample is half a pixel or less in an anti-aliased frame. Half a sample had kept the
    // bunny at full detail at 512x512, where its 70k triangles cost 15 ms against 10 ms for
    // 35k (llvmpipe shades a whole 4x4 block for each tiny triangle).
    const float sample_size_per_distance =
        2.0f * std::tan(glm::radians(camera.fov_y) / 2.0f) / float(frame.samples_high);
    const auto draw = [&](const Mesh& mesh, const GpuMesh& gpu, const glm::mat4& model,
                          const std::optional<glm::vec3>& base_override, int surface_kind) {
        glStencilFunc(GL_ALWAYS, surface_kind, 0xff);
        const float scale = largest_scale(model);
        const glm::vec3 centre = glm::vec3(model * glm::vec4(mesh.bounds.centre(), 1.0f));
        const float radius = 0.5f * glm::length(mesh.bounds.max - mesh.bounds.min) * scale;
        const float distance =
            std::max(frame.near_plane, glm::length(camera.eye - centre) - radius);
        const float max_error = sample_size_per_distance * distance / scale;
        glUniformMatrix4fv(geometry.uniform("u_model"), 1, GL_FALSE, glm::value_ptr(model));
        const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(model));
        glUniformMatrix3fv(geometry.uniform("u_normal_matrix"), 1, GL_FALSE,
                           glm::value_ptr(normal_matrix));
        for (const GpuPrimitive& primitive : gpu.primitives) {
            const Material& material = mesh.materials.at(std::size_t(primitive.material));
            const glm::vec4 base =
                base_override ? glm::vec4(*base_override, 1.0f) : material.base_color;
            glUniform4fv(geometry.uniform("u_base_color"), 1, glm::value_ptr(base));
            const bool textured = !base_override && material.base_color_texture.present();
            glUniform1i(geometry.uniform("u_has_texture"), textured ? 1 : 0);
            if (textured) {
                glBindTextureUnit(
                    0, gpu.textures.at(std::size_t(material.base_color_texture.texture)).get());
            }
            glUniform1f(geometry.uniform("u_specular_weight"), material.glossy() ? 0.04f : 0.0f);
            // Blinn-Phong exponent of a GGX roughness (alpha = roughness^2): 2 / alpha^2 - 2.
            const float alpha = std::max(0.02f, material.roughness * material.roughness);
            glUniform1f(geometry.uniform("u_shininess"),
                        std::max(1.0f, 2.0f / (alpha * alpha) - 2.0f));
            draw_primitive(primitive, max_error);
        }
    };
    for (const SceneObject& object : request.objects) {
        const RendererState::CachedMesh& cached = state.mesh(object.mesh);
        draw(*object.mesh, cached.gpu, object.transform, object.base_color, kObjectSurface);
    }
    if (request.ground) {
        const SceneBounds& scene = frame.scene;
        const glm::mat4 ground_model =
            glm::translate(glm::mat4(1.0f),
                           glm::vec3(scene.centre.x, scene.box.min.y, scene.centre.z)) *
            glm::scale(glm::mat4(1.0f),
                       glm::vec3(frame.ground_half_size, 1.0f, frame.ground_half_size));
        draw(state.ground_mesh, state.ground, ground_model, std::nullopt, kGroundSurface);
    }
    glDisable(GL_DEPTH_TEST);
}

}  // namespace oer
