// Shadow pass. Reads: the scene's objects and the lights that are on (frame), the mesh cache.
// Writes: state.shadows (a depth map per scene, light, filter and resolution, rendered only
// when missing; MASK and BLEND primitives whose alpha can cut them alpha tested, BLEND ones
// casting where they are at least half opaque), state.shadow_layers (layer k: rig light k's depth
// and ground visibility), the depth layers bound to kShadowMaps (with the PCF or hard comparison
// sampler) and kShadowDepths (gl_bindings.hpp); returns the ground visibility layers and the
// count of maps rendered.
#include <cstdint>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "gl_bindings.hpp"
#include "material_uniforms.hpp"
#include "oer/core/cancellation.hpp"
#include "passes/frame_passes.hpp"

namespace oer {

namespace {

// The object's variant where it changes what the shadow pass alpha tests (a primitive drawn
// with another material, alpha tested under one of the two), else -1: a variant that only
// recolours casts the default's shadows, and shares its maps.
std::int64_t shadow_variant(const SceneObject& object) {
    if (!object.variant) {
        return -1;
    }
    const Mesh& mesh = *object.mesh;
    for (const Primitive& primitive : mesh.primitives) {
        const int drawn = primitive.material_under(object.variant);
        if (drawn != primitive.material &&
            (alpha_tested(mesh.materials.at(std::size_t(drawn)), primitive) ||
             alpha_tested(mesh.materials.at(std::size_t(primitive.material)), primitive))) {
            return std::int64_t(*object.variant);
        }
    }
    return -1;
}

// The part of every shadow map's key that the scene decides: each object's mesh, transform and
// shadow_variant.
std::string scene_key(const FrameContext& frame, RendererState& state) {
    std::string key;
    for (const SceneObject& object : frame.request.objects) {
        const std::uint64_t id = state.mesh(object.mesh).id;
        key.append(reinterpret_cast<const char*>(&id), sizeof id);
        key.append(reinterpret_cast<const char*>(glm::value_ptr(object.transform)),
                   16 * sizeof(float));
        const std::int64_t variant = shadow_variant(object);
        key.append(reinterpret_cast<const char*>(&variant), sizeof variant);
    }
    return key;
}

}  // namespace

ShadowMaps render_shadow_maps(const FrameContext& frame, RendererState& state,
                              const std::stop_token& stop) {
    using namespace gl_bindings;
    const FrameRequest& request = frame.request;
    ShadowMaps shadows;
    // The meshes are uploaded here, shadows or not: the geometry pass finds them cached.
    const std::string scene = scene_key(frame, state);
    const int resolution = frame.shadow_resolution;
    if (frame.shadows) {
        state.shadow_layers.reserve(int(frame.rig.lights.size()), resolution);
        glBindTextureUnit(kShadowMaps.index, state.shadow_layers.depth());
        glBindSampler(kShadowMaps.index,
                      frame.pcf ? state.compare_linear.get() : state.compare_nearest.get());
        if (frame.pcf) {
            glBindTextureUnit(kShadowDepths.index, state.shadow_layers.depth());
            glBindSampler(kShadowDepths.index, state.depth_nearest.get());
        }
        shadows.ground_visibility_layers = state.shadow_layers.ground_visibility();
    }
    gl::Program& depth = state.program("depth", "#define ALPHA_TEST 0\n");
    for (std::size_t i = 0; frame.shadows && i < frame.lit.size(); ++i) {
        throw_if_stopped(stop, "the frame's shadow pass");
        std::string key = scene;
        key.append(reinterpret_cast<const char*>(glm::value_ptr(frame.light_directions[i])),
                   3 * sizeof(float));
        key.append(reinterpret_cast<const char*>(&frame.light_spreads[i]), sizeof(float));
        key.append(reinterpret_cast<const char*>(&frame.light_core_shares[i]), sizeof(float));
        key.append(reinterpret_cast<const char*>(&resolution), sizeof resolution);
        key.push_back(frame.pcf ? 'p' : 'h');
        bool rendered = false;
        ShadowMap& map = state.shadows.get(
            key, resolution,
            [&] {
                // Detail down to half a shadow-map texel.
                const float texel = 2.0f * frame.scene.radius / float(resolution);
                gl::Program* current = nullptr;
                for (const SceneObject& object : request.objects) {
                    const float max_error = 0.5f * texel / largest_scale(object.transform);
                    const GpuMesh& gpu = state.mesh(object.mesh).gpu;
                    for (std::size_t p = 0; p < gpu.primitives.size(); ++p) {
                        const GpuPrimitive& primitive = gpu.primitives[p];
                        const Material& material = object.mesh->materials.at(
                            std::size_t(object.mesh->primitives[p].material_under(object.variant)));
                        const bool alpha_test = alpha_tested(material, object.mesh->primitives[p]);
                        gl::Program& program =
                            alpha_test ? state.program("depth", "#define ALPHA_TEST 1\n") : depth;
                        if (current != &program) {
                            current = &program;
                            glUseProgram(program.id());
                            glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE,
                                               glm::value_ptr(frame.light_matrices[i]));
                        }
                        glUniformMatrix4fv(program.uniform("u_model"), 1, GL_FALSE,
                                           glm::value_ptr(object.transform));
                        if (alpha_test) {
                            set_material_uniforms(program, state, gpu, material,
                                                  base_color_override(object, material));
                            // Cut-outs are cards, leaves, decals: thin, often one quad, which
                            // would cast nothing with its face to the light culled.
                            glDisable(GL_CULL_FACE);
                        }
                        // The frame before may have left its transferred irradiance there.
                        attach_transferred_irradiance(primitive, 0, 0);
                        draw_primitive(primitive, max_error);
                        if (alpha_test) {
                            glEnable(GL_CULL_FACE);
                        }
                    }
                }
                unbind_material_samplers();
            },
            rendered);
        shadows.rendered += rendered ? 1 : 0;
        const int layer = int(frame.lit[i]);
        state.shadow_layers.hold_depth(layer, map);
        if (!request.ground) {
            continue;
        }
        if (!map.ground_visibility) {
            map.ground_visibility =
                bake_ground_visibility(frame, state, int(i), frame.scene.box.min.y);
        }
        state.shadow_layers.hold_ground_visibility(layer, map);
    }
    return shadows;
}

}  // namespace oer
