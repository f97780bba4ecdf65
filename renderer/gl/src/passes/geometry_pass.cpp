// Geometry pass. Reads: the objects, their meshes' levels of detail and materials, the ground
// (frame, state.mesh and state.ground), the camera, and in an occlusion frame the transferred
// irradiance per vertex (lighting). Returns the frame's targets, chosen by size, format and
// blending from state.targets, with their G-buffer filled at the supersampled size from the
// OPAQUE and MASK primitives (MASK ones alpha tested; BLEND ones are the transparent pass's):
// positions with ambient occlusion, shading normals with roughness, base colours with metallic
// (-1 for Lambertian), emitted radiance, in an occlusion frame the transferred irradiance,
// depth, and in the stencil each sample's surface kind (kBackgroundSurface where nothing was
// drawn, kLayeredSurface where a material with layers was, whose layers it packs into the layer
// targets: layer_gbuffer.glsl). Back faces of single-sided materials are culled. Material
// textures use gl_bindings.hpp's kMaterialTextures, whose samplers it unbinds.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "material_uniforms.hpp"
#include "passes/frame_passes.hpp"

namespace oer {

void attach_object_transfer(const FrameContext& frame, const FrameLightingBuffers& lighting,
                            const GpuPrimitive& gpu, std::size_t object, std::size_t primitive) {
    if (frame.transfer) {
        attach_transferred_irradiance(gpu, lighting.transferred_vertices,
                                      frame.transferred_offsets.at(object).at(primitive));
    } else {
        attach_transferred_irradiance(gpu, 0, 0);
    }
}

RenderTargets& render_geometry(const FrameContext& frame, const FrameLightingBuffers& lighting,
                               RendererState& state) {
    const FrameRequest& request = frame.request;
    const Camera& camera = frame.camera;
    RenderTargets& targets = state.targets.get(request.width, request.height, frame.scale,
                                               request.linear, frame.blending, frame.layered);
    glBindFramebuffer(GL_FRAMEBUFFER, targets.geometry_framebuffer.get());
    // The fifth target, the transferred irradiance, only in occlusion frames, and the sixth and
    // seventh, the layers, only in frames with layered materials: a frame without either writes
    // and pays for four.
    const GLenum targets_drawn[] = {GL_COLOR_ATTACHMENT0,
                                    GL_COLOR_ATTACHMENT1,
                                    GL_COLOR_ATTACHMENT2,
                                    GL_COLOR_ATTACHMENT3,
                                    frame.transfer ? GLenum(GL_COLOR_ATTACHMENT4) : GLenum(GL_NONE),
                                    GL_COLOR_ATTACHMENT5,
                                    GL_COLOR_ATTACHMENT6};
    glNamedFramebufferDrawBuffers(targets.geometry_framebuffer.get(),
                                  frame.layered    ? 7
                                  : frame.transfer ? 5
                                                   : 4,
                                  targets_drawn);
    glViewport(0, 0, frame.samples_wide, frame.samples_high);
    // The colour targets are not cleared: the shading pass reads them only at the samples whose
    // stencil names an object or the ground, and a fragment that passes there writes every
    // target, so no stale value is ever read. (Clearing them cost about 40 bytes of memset per
    // sample, 42 MB in the default 512x512 frame at 4 samples.) The draws need every target's write
    // mask on, and the clear below the depth and stencil masks: the previous frame's passes may
    // have left them off.
    for (GLuint buffer = 0; buffer < 7; ++buffer) {
        glColorMaski(buffer, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    glDepthMask(GL_TRUE);
    glStencilMask(0xff);
    glClearNamedFramebufferfi(targets.geometry_framebuffer.get(), GL_DEPTH_STENCIL, 0, 1.0f,
                              kBackgroundSurface);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_STENCIL_TEST);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    gl::Program* current = nullptr;
    // object: the index in request.objects, or none for the ground.
    // drawn: the object (its variant and base colour), or none for the ground.
    const auto draw = [&](const Mesh& mesh, const GpuMesh& gpu, const glm::mat4& model,
                          const SceneObject* drawn, int surface_kind,
                          std::optional<std::size_t> object) {
        const float max_error = sample_lod_error(frame, mesh, model);
        const float max_edge = transfer_lod_edge(frame, mesh);
        const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(model));
        // A mirroring transform turns the triangles' winding around.
        glFrontFace(glm::determinant(glm::mat3(model)) < 0.0f ? GL_CW : GL_CCW);
        for (std::size_t p = 0; p < gpu.primitives.size(); ++p) {
            const GpuPrimitive& primitive = gpu.primitives[p];
            const Material& material = mesh.materials.at(std::size_t(
                mesh.primitives[p].material_under(drawn ? drawn->variant : std::nullopt)));
            if (material.alpha_mode == AlphaMode::Blend) {
                continue;
            }
            const bool layered = drawn && shaded_layered(frame, material);
            glStencilFunc(GL_ALWAYS, layered ? kLayeredSurface : surface_kind, 0xff);
            const bool alpha_test = material.alpha_mode == AlphaMode::Mask &&
                                    alpha_tested(material, mesh.primitives[p]);
            gl::Program& geometry = state.program(
                "geometry",
                std::string("#define ALPHA_TEST ") + (alpha_test ? "1" : "0") +
                    "\n#define MATERIAL_TEXTURES " +
                    (reads_textures_or_colors(material, mesh.primitives[p]) ? "1" : "0") +
                    "\n#define MATERIAL_LAYERS " + (layered ? "1" : "0") + "\n" +
                    frame.transfer_define);
            if (current != &geometry) {
                current = &geometry;
                glUseProgram(geometry.id());
                glUniformMatrix4fv(geometry.uniform("u_view_projection"), 1, GL_FALSE,
                                   glm::value_ptr(frame.view_projection));
                glUniform3fv(geometry.uniform("u_eye"), 1, glm::value_ptr(camera.eye));
            }
            glUniformMatrix4fv(geometry.uniform("u_model"), 1, GL_FALSE, glm::value_ptr(model));
            glUniformMatrix3fv(geometry.uniform("u_normal_matrix"), 1, GL_FALSE,
                               glm::value_ptr(normal_matrix));
            set_material_uniforms(geometry, state, gpu, material,
                                  drawn ? base_color_override(*drawn, material) : std::nullopt);
            if (material.double_sided) {
                glDisable(GL_CULL_FACE);
            } else {
                glEnable(GL_CULL_FACE);
                glCullFace(GL_BACK);  // the shadow pass culls front faces
            }
            if (object) {
                attach_object_transfer(frame, lighting, primitive, *object, p);
            } else {
                attach_transferred_irradiance(primitive, 0, 0);
            }
            draw_primitive(primitive, max_error, max_edge);
        }
    };
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        const RendererState::CachedMesh& cached = state.mesh(object.mesh);
        draw(*object.mesh, cached.gpu, object.transform, &object, kObjectSurface, i);
    }
    if (request.ground) {
        const SceneBounds& scene = frame.scene;
        const glm::mat4 ground_model =
            glm::translate(glm::mat4(1.0f),
                           glm::vec3(scene.centre.x, scene.box.min.y, scene.centre.z)) *
            glm::scale(glm::mat4(1.0f),
                       glm::vec3(frame.ground_half_size, 1.0f, frame.ground_half_size));
        draw(state.ground_mesh, state.ground, ground_model, nullptr, kGroundSurface, std::nullopt);
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    unbind_material_samplers();
    return targets;
}

}  // namespace oer
