#include "surface_shading.hpp"

#include <algorithm>
#include <numbers>

#include <glm/gtc/type_ptr.hpp>

#include "gl_bindings.hpp"
#include "oer/lighting/specular_environment.hpp"

namespace oer {

void bind_specular_textures(const FrameContext& frame, RendererState& state) {
    if (!frame.specular) {
        return;
    }
    const RendererState::SpecularTextures cubes = state.specular(frame.request.specular);
    glBindTextureUnit(gl_bindings::kSpecularCube.index, cubes.residual);
    glBindTextureUnit(gl_bindings::kLightCubes.index, cubes.lights);
    glBindTextureUnit(gl_bindings::kDfgTable.index, state.dfg());
    if (frame.layered) {
        glBindTextureUnit(gl_bindings::kSheenAlbedo.index, state.sheen_albedo());
    }
}

namespace {

// The uniforms of ground_lighting.glsl, which the ground's shading and glossy objects' reflection
// of the floor read: the irradiance of each set on the plane and, in an occlusion frame with a
// ground, its transfer grid's place and the open ground's transferred irradiance.
void set_ground_lighting_uniforms(gl::Program& program, const FrameContext& frame) {
    glUniform3fv(program.uniform("u_flat_irradiance"), GLsizei(frame.ground_irradiance.size()),
                 glm::value_ptr(frame.ground_irradiance[0]));
    if (frame.transfer && frame.request.ground) {
        const GroundTransfer& ground = *frame.request.transfer->ground;
        glUniform4f(program.uniform("u_ground_transfer_rect"), ground.centre.x - ground.half_size,
                    ground.centre.y - ground.half_size, 0.5f / ground.half_size, 0.0f);
        glUniform3fv(program.uniform("u_open_ground_transferred"), 1,
                     glm::value_ptr(frame.open_ground_transferred));
    }
}

}  // namespace

void set_surface_shading_uniforms(gl::Program& program, const FrameContext& frame) {
    const Rig& rig = frame.rig;
    const bool thesis = rig.model == LightingModel::Thesis;
    set_light_uniforms(program, frame);
    glUniform2f(program.uniform("u_yaw"), frame.yaw_cos_sin.x, frame.yaw_cos_sin.y);
    glUniform3fv(program.uniform("u_eye"), 1, glm::value_ptr(frame.camera.eye));
    glUniform1f(program.uniform("u_albedo_scale"), thesis ? 1.0f : float(1.0 / std::numbers::pi));
    glUniform1f(program.uniform("u_attenuation_base"), float(frame.attenuation_base));
    for (std::size_t i = 0; i < frame.lit.size(); ++i) {
        const std::size_t k = frame.lit[i];
        glUniform3fv(program.uniform(element("u_light_direction", i)), 1,
                     glm::value_ptr(frame.light_directions[i]));
        // The share is weighted as its irradiance set is (frame_context.hpp).
        glUniform1f(program.uniform(element("u_light_share", i)),
                    thesis ? float(frame.weights[k] * rig.lights[k].luminance_share) : 0.0f);
    }
    set_ground_lighting_uniforms(program, frame);
    if (!frame.specular) {
        return;
    }
    glUniform1f(program.uniform("u_specular_max_lod"),
                float(frame.request.specular->residual.levels - 1));
    // The opaque floor as reflections see it (surface_shading.glsl, floor_share and
    // floor_radiance): its height and albedo, and the fade that draws it. A shadow catcher's
    // floor is not seen, so it reflects nothing.
    const FrameRequest& request = frame.request;
    const bool opaque_floor = request.ground && request.ground_look == GroundLook::Opaque;
    glm::vec4 floor_fade(0.0f);
    if (opaque_floor) {
        floor_fade = glm::vec4(frame.scene.centre.x, frame.scene.centre.z,
                               frame.scene.ground_fade_start(), frame.scene.ground_half_size());
    }
    glUniform1f(program.uniform("u_floor_height"), frame.scene.box.min.y);
    glUniform1f(program.uniform("u_floor_albedo"), kGroundAlbedo);
    glUniform4fv(program.uniform("u_floor_fade"), 1, glm::value_ptr(floor_fade));
    // Light k's reflection is layer k of the lights' cube, by its weight (its visibility is
    // the shader's). On an opaque floor, which hides what lies below the horizon, it is the
    // layer of its pixels above the horizon (SpecularEnvironment::floor_layers): nothing of a
    // light wholly below.
    const SpecularEnvironment& specular = *request.specular;
    for (std::size_t i = 0; i < frame.lit.size(); ++i) {
        const std::size_t k = frame.lit[i];
        const int floor_layer = specular.floor_layers.at(k);
        const bool hidden = opaque_floor && floor_layer < 0;
        glUniform1i(program.uniform(element("u_light_cube_layer", i)),
                    opaque_floor && !hidden ? GLint(floor_layer) : GLint(k));
        glUniform1f(program.uniform(element("u_light_weight", i)),
                    hidden ? 0.0f : float(frame.weights[k]));
        const LightSpread& spread = frame.reflection_spreads[i];
        glUniform3f(program.uniform(element("u_light_reflection_spread", i)),
                    float(spread.core_share), float(spread.core_cap_tan2),
                    float(spread.glow_cap_tan2));
        // The core is at the light's direction: a floor layer holds it where that is above
        // the horizon.
        const Light& light = frame.rig.lights[k];
        const bool core_hidden = opaque_floor && light.direction.y < 0.0;
        const glm::vec3 core_energy =
            core_hidden ? glm::vec3(0.0f)
                        : glm::vec3(light_core_energy(light, spread, specular.lights.levels));
        glUniform3fv(program.uniform(element("u_light_core_energy", i)), 1,
                     glm::value_ptr(core_energy));
        const glm::vec3 map_direction(light.direction);
        glUniform3fv(program.uniform(element("u_light_map_direction", i)), 1,
                     glm::value_ptr(map_direction));
    }
}

}  // namespace oer
