// Transparent pass, for frames with BLEND primitives (glTF 2.0 section 3.9.4). Reads: those
// primitives and their materials (gl_bindings.hpp's kMaterialTextures), the depth of the
// geometry pass (targets), in an occlusion frame the transferred irradiance per vertex
// (lighting), everything the shading pass bound for objects (irradiance sets, shadow layers,
// specular cube and DFG table) and the lights (frame). Writes: targets.shaded, which it returns,
// a float target in such frames (render_targets.hpp), each primitive blended over it in
// premultiplied form,
// farthest first by the distance from the eye to its bounds' centre: the usual sorting of
// transparent geometry, exact between separate primitives and approximate where they
// interpenetrate. Depth is tested against the opaque surfaces and not written. Leaves
// blending, depth test and culling off, depth writes on, and the material units without
// samplers. A material with the extensions' layers is shaded by the MATERIAL_LAYERS 1 variant.
#include <algorithm>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "material_uniforms.hpp"
#include "passes/frame_passes.hpp"
#include "surface_shading.hpp"

namespace oer {

namespace {

// One primitive (`primitive_index` of request.objects[object_index]) drawn by a forward program
// of this pass, `program`: made current with the surface shading's uniforms unless it is
// `current` (which it becomes), then the object's transform, the material's uniforms and
// textures, its winding and culling, and its transferred irradiance.
void draw_forward(const FrameContext& frame, const FrameLightingBuffers& lighting,
                  RendererState& state, gl::Program& program, gl::Program*& current,
                  std::size_t object_index, std::size_t primitive_index) {
    const SceneObject& object = frame.request.objects[object_index];
    const Mesh& mesh = *object.mesh;
    const GpuMesh& gpu = state.mesh(object.mesh).gpu;
    const Material& material = mesh.materials.at(
        std::size_t(mesh.primitives[primitive_index].material_under(object.variant)));
    if (current != &program) {
        current = &program;
        glUseProgram(program.id());
        set_surface_shading_uniforms(program, frame);
        glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE,
                           glm::value_ptr(frame.view_projection));
    }
    glUniformMatrix4fv(program.uniform("u_model"), 1, GL_FALSE, glm::value_ptr(object.transform));
    const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(object.transform));
    glUniformMatrix3fv(program.uniform("u_normal_matrix"), 1, GL_FALSE,
                       glm::value_ptr(normal_matrix));
    set_material_uniforms(program, state, gpu, material, base_color_override(object, material));
    glFrontFace(glm::determinant(glm::mat3(object.transform)) < 0.0f ? GL_CW : GL_CCW);
    if (material.double_sided) {
        glDisable(GL_CULL_FACE);
    } else {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);  // the shadow pass culls front faces
    }
    const GpuPrimitive& primitive = gpu.primitives[primitive_index];
    attach_object_transfer(frame, lighting, primitive, object_index, primitive_index);
    draw_primitive(primitive, sample_lod_error(frame, mesh, object.transform),
                   transfer_lod_edge(frame, mesh));
}

}  // namespace

GLuint blend_transparent_surfaces(const FrameContext& frame, const FrameLightingBuffers& lighting,
                                  const RenderTargets& targets, RendererState& state) {
    const FrameRequest& request = frame.request;
    struct Transparent {
        const SceneObject* object;
        std::size_t object_index;
        std::size_t primitive_index;
        float distance;
    };
    std::vector<Transparent> surfaces;
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        const GpuMesh& gpu = state.mesh(object.mesh).gpu;
        for (std::size_t p = 0; p < gpu.primitives.size(); ++p) {
            const GpuPrimitive& primitive = gpu.primitives[p];
            const int material = object.mesh->primitives[p].material_under(object.variant);
            if (object.mesh->materials.at(std::size_t(material)).alpha_mode != AlphaMode::Blend) {
                continue;
            }
            const glm::vec3 centre =
                glm::vec3(object.transform * glm::vec4(primitive.centre, 1.0f));
            surfaces.push_back({&object, i, p, glm::length(centre - frame.camera.eye)});
        }
    }
    std::stable_sort(
        surfaces.begin(), surfaces.end(),
        [](const Transparent& a, const Transparent& b) { return a.distance > b.distance; });

    glBindFramebuffer(GL_FRAMEBUFFER, targets.shaded_framebuffer.get());
    glViewport(0, 0, frame.samples_wide, frame.samples_high);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    // Porter and Duff's "over" on premultiplied colour: src + (1 - src alpha) dst.
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl::Program* current = nullptr;
    for (const Transparent& surface : surfaces) {
        const SceneObject& object = *surface.object;
        const Mesh& mesh = *object.mesh;
        const Material& material = mesh.materials.at(
            std::size_t(mesh.primitives[surface.primitive_index].material_under(object.variant)));
        gl::Program& program =
            state.program("transparent", frame.lighting_defines + frame.specular_define +
                                             frame.transfer_define + "#define MATERIAL_LAYERS " +
                                             (shaded_layered(frame, material) ? "1" : "0") + "\n");
        draw_forward(frame, lighting, state, program, current, surface.object_index,
                     surface.primitive_index);
    }
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
    unbind_material_samplers();
    return targets.shaded.get();
}

}  // namespace oer
