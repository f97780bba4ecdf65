#include "frame_context.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/light_location.hpp"
#include "oer/mesh/mesh_refinement.hpp"
#include "oer/scene/scene_rules.hpp"
#include "oer/transfer/transfer_lighting.hpp"
#include "sh_shader_constants.hpp"

namespace oer {

namespace {

// Orthographic light view fitted to the scene's bounding sphere along the light's direction.
glm::mat4 light_matrix(const glm::vec3& direction, const SceneBounds& scene) {
    const glm::vec3 up = std::abs(direction.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const float r = scene.radius;
    const glm::mat4 view = glm::lookAt(scene.centre + direction * (2.0f * r), scene.centre, up);
    return glm::ortho(-r, r, -r, r, r, 3.0f * r) * view;
}

void add_lights(FrameContext& frame) {
    const FrameRequest& request = frame.request;
    const Rig& rig = frame.rig;
    const std::size_t light_count = rig.lights.size();
    frame.weights.assign(light_count, 1.0f);
    std::copy(request.lights.begin(), request.lights.end(), frame.weights.begin());
    for (std::size_t k = 0; k < light_count; ++k) {
        if (frame.weights[k] > 0.0f) {
            frame.lit.push_back(k);
        }
    }
    const double yaw = glm::radians(request.environment_yaw);
    frame.yaw_cos_sin = {float(std::cos(yaw)), float(std::sin(yaw))};

    // The split of frame_context.hpp (visibility_coefficients' sum with 1 - w_k for 1 - v_k,
    // which it cannot take: w_k goes up to 4). A weight of 1 adds nothing, and a weight of 0
    // takes E(k) off exactly as an off light did.
    // Under occlusion the residual map's part, E(all) - sum_k E(k), is the transfer's instead,
    // and with the ground a light lights only with its part above the horizon (the plane hides
    // the rest: a light straddling the horizon, as Blender's studio has two, loses half).
    const std::vector<ShRgb>& lights =
        frame.transfer && request.ground ? rig.sh.per_light_above_horizon : rig.sh.per_light;
    ShRgb constant = frame.transfer ? ShRgb(rig.sh.all.order) : rig.sh.all;
    for (std::size_t k = 0; k < light_count; ++k) {
        const double change =
            frame.transfer ? double(frame.weights[k]) : double(frame.weights[k]) - 1.0;
        if (change != 0.0) {
            ShRgb scaled = lights[k];
            scaled *= change;
            constant += scaled;
        }
    }
    frame.irradiance_sets.push_back(irradiance_coefficients(constant, rig.window));
    for (const std::size_t k : frame.lit) {
        ShRgb weighted = irradiance_coefficients(lights[k], rig.window);
        if (frame.weights[k] != 1.0f) {
            weighted *= double(frame.weights[k]);
        }
        frame.irradiance_sets.push_back(std::move(weighted));
    }
    // Specular frames under occlusion: the open residual map's irradiance, E(all) - sum_k E(k),
    // last, against which surface_shading.glsl's residual_visibility measures the transfer's.
    if (frame.transfer && frame.specular) {
        ShRgb residual = rig.sh.all;
        for (std::size_t k = 0; k < light_count; ++k) {
            ShRgb light = rig.sh.per_light[k];
            light *= -1.0;
            residual += light;
        }
        frame.irradiance_sets.push_back(irradiance_coefficients(residual, rig.window));
    }
    for (const ShRgb& set : frame.irradiance_sets) {
        frame.ground_irradiance.push_back(glm::vec3(set.evaluate({0.0, 1.0, 0.0})));
    }
    if (rig.model == LightingModel::Thesis) {
        for (std::size_t k = 0; k < light_count; ++k) {
            frame.attenuation_base -=
                (1.0 - double(frame.weights[k])) * rig.lights[k].luminance_share;
        }
    }
}

void add_transferred_irradiance(FrameContext& frame, TransferredIrradianceCache& cache) {
    const FrameRequest& request = frame.request;
    const SceneTransfer& transfer = *request.transfer;
    TransferredIrradianceInputs inputs{request.transfer,
                                       request.rig,
                                       frame.weights,
                                       request.environment_yaw,
                                       request.ground,
                                       request.bounce,
                                       bounce_weights(transfer, request)};
    if (cache.inputs && cache.inputs->same_as(inputs)) {
        frame.transferred_vertices = cache.vertices;
        frame.transferred_offsets = cache.offsets;
        frame.transferred_ground = cache.ground;
        frame.open_ground_transferred = cache.open_ground;
        ++cache.reuses;
        return;
    }
    const TransferLighting lighting =
        transfer_lighting(frame.rig, frame.weights, request.environment_yaw,
                          transfer_order(frame.rig), request.ground, request.bounce);
    for (const std::vector<TransferPoints>& object : transfer.objects) {
        std::vector<std::size_t>& offsets = frame.transferred_offsets.emplace_back();
        for (const TransferPoints& primitive : object) {
            offsets.push_back(frame.transferred_vertices.size());
            const std::vector<glm::vec3> irradiance = transferred_irradiance(
                primitive, transfer.order, lighting, inputs.weights_of_bounce);
            frame.transferred_vertices.insert(frame.transferred_vertices.end(), irradiance.begin(),
                                              irradiance.end());
        }
    }
    if (transfer.ground) {
        frame.transferred_ground = transferred_irradiance(transfer.ground->points, transfer.order,
                                                          lighting, inputs.weights_of_bounce);
        frame.open_ground_transferred = open_ground_irradiance(transfer.order, lighting);
    }
    cache.inputs = std::move(inputs);
    cache.vertices = frame.transferred_vertices;
    cache.offsets = frame.transferred_offsets;
    cache.ground = frame.transferred_ground;
    cache.open_ground = frame.open_ground_transferred;
}

void add_camera(FrameContext& frame) {
    const FrameRequest& request = frame.request;
    const SceneBounds& scene = frame.scene;
    const float aspect = float(request.width) / float(request.height);
    frame.camera = request.camera.value_or(frame_bounds(scene.box, 45.0f, aspect));
    frame.ground_half_size = scene.ground_half_size();
    const float eye_distance = glm::length(frame.camera.eye - scene.centre);
    const float far_plane =
        eye_distance + (request.ground ? 1.5f * frame.ground_half_size : 2.0f * scene.radius);
    // In front of the scene's bounds, and with the ground in front of the plane too: a low
    // camera sees the plane from its own height on, which a near plane fitted to the bounds alone
    // would clip away below the frame's middle.
    float near_plane = 0.5f * (eye_distance - scene.radius);
    const float height = frame.camera.eye.y - scene.box.min.y;
    if (request.ground && height > 0.0f) {
        near_plane = std::min(near_plane, 0.5f * height);
    }
    frame.near_plane = std::max(far_plane * 1e-5f, near_plane);
    frame.view_projection =
        projection_matrix(frame.camera, aspect, std::min(frame.near_plane, far_plane * 0.5f),
                          far_plane) *
        view_matrix(frame.camera);
}

void add_shadow_views(FrameContext& frame) {
    const FrameRequest& request = frame.request;
    frame.shadows = request.shadows.enabled && !frame.lit.empty();
    frame.pcf = request.shadows.filter == ShadowFilter::Pcf;
    const int resolution = request.shadows.resolution;
    frame.shadow_resolution = resolution;
    for (const std::size_t k : frame.lit) {
        const glm::vec3 direction = glm::normalize(glm::vec3(
            equirect::rotate_yaw(frame.rig.lights[k].direction, request.environment_yaw)));
        frame.light_directions.push_back(direction);
        frame.light_matrices.push_back(light_matrix(direction, frame.scene));
        // The light's core casts hard shadows and its glow soft ones (light_profile): a sun's
        // pixels reach far into its glow (Blender's sunrise: 25.7 degrees) while most of its
        // energy is in a core a shadow map cannot resolve. The frame sweep measured the
        // filters this replaced (docs/accuracy.md, the bunny under sunrise): a fixed kernel of
        // a quarter of the extent's tangent, 13.9 % from the reference; one disc of the
        // light's mean cosine (11.1 degrees), 9.1 %; hard shadows, 6.6 %.
        const LightProfile profile =
            light_profile(frame.rig.sh.per_light[k], frame.rig.lights[k].direction);
        const double radius =
            std::min(frame.rig.lights[k].angular_radius, profile.glow_angular_radius);
        // The request's softness scales the penumbra (ShadowOptions::softness).
        frame.light_spreads.push_back(request.shadows.softness *
                                      float(std::tan(std::min(radius, 1.2))));
        frame.light_core_shares.push_back(float(profile.core_share));
        frame.reflection_spreads.push_back(
            light_spread(frame.rig.lights[k].angular_radius, profile));
    }
    frame.normal_offset = 1.5f * 2.0f * frame.scene.radius / float(resolution);
    frame.specular_define = "#define SPECULAR " + std::to_string(frame.specular ? 1 : 0) + "\n";
    frame.transfer_define = "#define TRANSFER " + std::to_string(frame.transfer ? 1 : 0) + "\n";
    frame.lighting_defines = "#define SH_ORDER " + std::to_string(frame.rig.sh.all.order) +
                             "\n#define LIGHTS_ON " + std::to_string(frame.lit.size()) +
                             "\n#define SHADOWS " + std::to_string(frame.shadows ? 1 : 0) +
                             "\n#define PCF " + std::to_string(frame.pcf ? 1 : 0) + "\n";
}

template <typename Predicate>
bool any_primitive_material(const FrameRequest& request, Predicate predicate) {
    for (const SceneObject& object : request.objects) {
        for (const Primitive& primitive : object.mesh->primitives) {
            const int material = primitive.material_under(object.variant);
            if (predicate(object.mesh->materials.at(std::size_t(material)))) {
                return true;
            }
        }
    }
    return false;
}

}  // namespace

bool has_blending(const FrameRequest& request) {
    return any_primitive_material(
        request, [](const Material& m) { return m.alpha_mode == AlphaMode::Blend; });
}

bool shaded_layered(const FrameContext& frame, const Material& material) {
    return frame.specular && material.layered();
}

bool TransferredIrradianceInputs::same_as(const TransferredIrradianceInputs& other) const {
    const auto same_object = [](const auto& a, const auto& b) {
        const auto locked = a.lock();
        return locked != nullptr && locked == b.lock();
    };
    return same_object(transfer, other.transfer) && same_object(rig, other.rig) &&
           weights == other.weights && yaw_degrees == other.yaw_degrees && ground == other.ground &&
           bounce == other.bounce && weights_of_bounce == other.weights_of_bounce;
}

FrameContext make_frame_context(const FrameRequest& request, TransferredIrradianceCache& cache) {
    FrameContext frame(request);
    frame.specular = needs_specular(request);
    frame.blending = has_blending(request);
    frame.layered = frame.specular &&
                    any_primitive_material(request, [](const Material& m) { return m.layered(); });
    frame.transfer = request.occlusion;
    add_lights(frame);
    if (frame.transfer) {
        add_transferred_irradiance(frame, cache);
    }
    frame.scene = scene_bounds(request.objects);
    add_camera(frame);
    add_shadow_views(frame);
    frame.scale = supersampling_scale(request.samples);
    frame.samples_wide = request.width * frame.scale;
    frame.samples_high = request.height * frame.scale;
    return frame;
}

int supersampling_scale(int samples) {
    return int(std::ceil(std::sqrt(double(samples)) - 1e-9));
}

void set_light_uniforms(gl::Program& program, const FrameContext& frame) {
    const std::vector<float>& sh_scale = sh_shader_scales(frame.rig.sh.all.order);
    glUniform1fv(program.uniform("u_sh_scale"), GLsizei(sh_scale.size()), sh_scale.data());
    for (std::size_t i = 0; i < frame.lit.size(); ++i) {
        glUniformMatrix4fv(program.uniform(element("u_light_matrix", i)), 1, GL_FALSE,
                           glm::value_ptr(frame.light_matrices[i]));
        glUniform1i(program.uniform(element("u_light_layer", i)), GLint(frame.lit[i]));
        glUniform1f(program.uniform(element("u_light_spread", i)), frame.light_spreads[i]);
        glUniform1f(program.uniform(element("u_light_core_share", i)), frame.light_core_shares[i]);
        glUniform1f(program.uniform(element("u_normal_offset", i)), frame.normal_offset);
    }
    glUniform1f(program.uniform("u_shadow_texel"), 1.0f / float(frame.shadow_resolution));
}

void set_display_uniforms(gl::Program& program, const FrameRequest& request) {
    glUniform1f(program.uniform("u_exposure_scale"), float(std::exp2(request.exposure)));
    glUniform1i(program.uniform("u_tonemap"), request.tonemap == ToneMapper::Neutral ? 0
                                              : request.tonemap == ToneMapper::Aces  ? 1
                                                                                     : 2);
    const glm::vec4 background = request.background.kind == BackgroundKind::Color
                                     ? glm::vec4(request.background.color, 1.0f)
                                     : glm::vec4(0.0f);
    glUniform4fv(program.uniform("u_background"), 1, glm::value_ptr(background));
}

std::string element(const char* name, std::size_t i) {
    std::string text = name;
    text += '[';
    text += std::to_string(i);
    text += ']';
    return text;
}

// A level's stated error already carries a fivefold margin over meshoptimizer's (mesh_lod.cpp),
// and a sample is half a pixel or less in an anti-aliased frame. Half a sample had kept the
// bunny at full detail at 512x512, where its 70k triangles cost 15 ms against 10 ms for 35k
// (llvmpipe shades a whole 4x4 block for each tiny triangle).
float sample_lod_error(const FrameContext& frame, const Mesh& mesh, const glm::mat4& model) {
    const Camera& camera = frame.camera;
    const float sample_size_per_distance =
        2.0f * std::tan(glm::radians(camera.fov_y) / 2.0f) / float(frame.samples_high);
    const float scale = largest_scale(model);
    const glm::vec3 centre = glm::vec3(model * glm::vec4(mesh.bounds.centre(), 1.0f));
    const float radius = 0.5f * glm::length(mesh.bounds.max - mesh.bounds.min) * scale;
    const float distance = std::max(frame.near_plane, glm::length(camera.eye - centre) - radius);
    return sample_size_per_distance * distance / scale;
}

// A level lit through a transfer interpolates it along edges of at most 1.5 refinement lengths.
// The bound keeps a flat face from collapsing to its corners (a refined box's levels have edges
// of 8 lengths and more), while admitting the bunny's first levels: their simplification
// stretches a few edges just past the length (1.14 at 35k and 17k triangles, 1.49 at 8.7k),
// and a bound of exactly one length kept it at 70k triangles, 25 % more colour pass at
// 512x512 than the frame without occlusion; at 1.5 it is 4 % (bench/frame_benchmark), and the
// report's error on the product grows by at most a few tenths of a point.
constexpr double kLodEdgeOverRefinement = 1.5;

float transfer_lod_edge(const FrameContext& frame, const Mesh& mesh) {
    return frame.transfer ? float(transfer_edge_length(mesh.bounds) * kLodEdgeOverRefinement)
                          : std::numeric_limits<float>::infinity();
}

float largest_scale(const glm::mat4& transform) {
    return std::max({glm::length(glm::vec3(transform[0])), glm::length(glm::vec3(transform[1])),
                     glm::length(glm::vec3(transform[2]))});
}

}  // namespace oer
