#include "oer/gl/frame_renderer.hpp"

#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "frame_programs.hpp"
#include "gl_program.hpp"
#include "gpu_mesh.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/gl_context.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "render_targets.hpp"
#include "sh_shader_constants.hpp"
#include "shader_sources.hpp"
#include "shadow_layers.hpp"
#include "shadow_map_cache.hpp"

namespace oer {

namespace {

using Clock = std::chrono::steady_clock;

double elapsed_ms(Clock::time_point since) {
    return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

void fail(const std::string& member, const std::string& message) {
    throw Error(ErrorKind::InvalidInput, member + ": " + message);
}

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) {
                return false;
            }
        }
    }
    return true;
}

// The ground: a square in the plane y = 0 facing +Y, scaled and placed per frame.
Mesh unit_ground() {
    Mesh mesh;
    Primitive quad;
    quad.name = "ground";
    quad.positions = {{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}};
    quad.normals.assign(4, {0, 1, 0});
    quad.indices = {0, 1, 2, 0, 2, 3};
    mesh.primitives.push_back(std::move(quad));
    // A horizontal Lambertian plane of albedo 0.8 (DESIGN.md section 7).
    Material material;
    material.name = "ground";
    material.base_color = {0.8f, 0.8f, 0.8f, 1.0f};
    material.specular = false;
    mesh.materials.push_back(material);
    return mesh;
}

struct SceneBounds {
    Bounds box;
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
};

SceneBounds scene_bounds(const std::vector<SceneObject>& objects) {
    SceneBounds scene;
    bool any = false;
    for (const SceneObject& object : objects) {
        const Bounds& b = object.mesh->bounds;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 local{(corner & 1) ? b.max.x : b.min.x,
                                  (corner & 2) ? b.max.y : b.min.y,
                                  (corner & 4) ? b.max.z : b.min.z};
            const glm::vec3 world = glm::vec3(object.transform * glm::vec4(local, 1.0f));
            scene.box.min = any ? glm::min(scene.box.min, world) : world;
            scene.box.max = any ? glm::max(scene.box.max, world) : world;
            any = true;
        }
    }
    if (!any) {
        scene.box = {glm::vec3(-0.5f), glm::vec3(0.5f)};
    }
    scene.centre = scene.box.centre();
    scene.radius = std::max(1e-4f, 0.5f * glm::length(scene.box.max - scene.box.min));
    return scene;
}

// Orthographic light view fitted to the scene's bounding sphere along the light's direction.
glm::mat4 light_matrix(const glm::vec3& direction, const SceneBounds& scene) {
    const glm::vec3 up = std::abs(direction.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const float r = scene.radius;
    const glm::mat4 view = glm::lookAt(scene.centre + direction * (2.0f * r), scene.centre, up);
    return glm::ortho(-r, r, -r, r, r, 3.0f * r) * view;
}

// The name of element i of a uniform array: "name[i]".
std::string element(const char* name, std::size_t i) {
    std::string text = name;
    text += '[';
    text += std::to_string(i);
    text += ']';
    return text;
}

// The largest factor by which a transform stretches a length: a mesh-space error times it bounds
// the world-space error.
float largest_scale(const glm::mat4& transform) {
    return std::max({glm::length(glm::vec3(transform[0])), glm::length(glm::vec3(transform[1])),
                     glm::length(glm::vec3(transform[2]))});
}

// Surface kinds, the geometry pass's stencil values; each has its own shading program.
constexpr int kBackgroundSurface = 0;
constexpr int kObjectSurface = 1;
constexpr int kGroundSurface = 2;

// Supersamples per pixel side for `samples` samples per pixel (FrameRequest::samples).
int supersampling_scale(int samples) {
    return int(std::ceil(std::sqrt(double(samples)) - 1e-9));
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

}  // namespace

struct FrameRenderer::State {
    explicit State(const FrameLimits& limits_)
        : limits(limits_), shadows(limits_.max_cached_shadow_maps) {}
    FrameLimits limits;
    std::map<std::string, std::unique_ptr<gl::Program>> programs;

    struct CachedMesh {
        std::weak_ptr<const Mesh> owner;
        std::uint64_t id = 0;
        GpuMesh gpu;
    };
    std::map<const Mesh*, CachedMesh> meshes;
    std::uint64_t next_mesh_id = 1;

    struct CachedEnvironment {
        std::weak_ptr<const HdrImage> owner;
        gl::Object texture;
    };
    std::map<const HdrImage*, CachedEnvironment> environments;

    ShadowMapCache shadows;
    ShadowLayers shadow_layers;
    gl::Object bake_framebuffer;
    RenderTargetCache targets;

    Mesh ground_mesh = unit_ground();
    GpuMesh ground;
    gl::Object empty_vertex_array;
    gl::Object compare_linear;
    gl::Object compare_nearest;
    gl::Object irradiance_buffer;
    int max_texture_size = 0;

    // The program `name` of renderer/gl/src/frame_programs.cpp specialised by `defines`.
    gl::Program& program(const std::string& name, const std::string& defines) {
        const std::string key = name + "\n" + defines;
        auto found = programs.find(key);
        if (found == programs.end()) {
            const shaders::FrameProgram& stages = shaders::frame_program(name);
            shaders::check_defines(stages, defines);
            found = programs
                        .emplace(key, std::make_unique<gl::Program>(
                                          shaders::program_source(stages.vertex, defines),
                                          shaders::program_source(stages.fragment, defines), name))
                        .first;
        }
        return *found->second;
    }

    // Bakes the visibility of the frame's light `light` (the index among the lights that are
    // on) over the ground plane at ground_height into map.ground_visibility, from its depth,
    // which the shadow layers hold.
    //
    // A filtered shadow has no detail finer than its kernel, so the bake is made with about
    // two texels per kernel radius (at most the shadow map's resolution): there the fixed
    // 16-tap disc covers the kernel densely, and the bake costs a few thousand texels for a
    // soft light instead of millions.
    void bake_ground_visibility(ShadowMap& map, int light, const glm::mat4& inverse_light_matrix,
                                float ground_height, int shadow_resolution, float kernel_uv,
                                bool filtered, const std::string& lighting_defines,
                                const std::function<void(gl::Program&)>& set_light_uniforms) {
        int resolution = shadow_resolution;
        if (filtered) {
            resolution = 64;
            while (resolution < shadow_resolution && float(resolution) * kernel_uv < 4.0f) {
                resolution *= 2;
            }
        }
        map.ground_visibility = gl::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(map.ground_visibility.get(), 1, GL_R8, resolution, resolution);
        glNamedFramebufferTexture(bake_framebuffer.get(), GL_COLOR_ATTACHMENT0,
                                  map.ground_visibility.get(), 0);
        glBindFramebuffer(GL_FRAMEBUFFER, bake_framebuffer.get());
        glViewport(0, 0, resolution, resolution);
        glDisable(GL_DEPTH_TEST);
        glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl::Program& bake = program("ground visibility", lighting_defines);
        glUseProgram(bake.id());
        set_light_uniforms(bake);
        glUniformMatrix4fv(bake.uniform("u_inverse_light_matrix"), 1, GL_FALSE,
                           glm::value_ptr(inverse_light_matrix));
        glUniform1f(bake.uniform("u_ground_height"), ground_height);
        glUniform1i(bake.uniform("u_light"), light);
        glUniform2f(bake.uniform("u_size"), float(resolution), float(resolution));
        glBindVertexArray(empty_vertex_array.get());
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }

    CachedMesh& mesh(const std::shared_ptr<const Mesh>& owner) {
        auto found = meshes.find(owner.get());
        if (found != meshes.end() && found->second.owner.expired()) {
            meshes.erase(found);  // the address was reused by a new mesh
            found = meshes.end();
        }
        if (found == meshes.end()) {
            std::erase_if(meshes, [](const auto& entry) { return entry.second.owner.expired(); });
            CachedMesh cached{owner, next_mesh_id++, upload_mesh(*owner)};
            found = meshes.emplace(owner.get(), std::move(cached)).first;
        }
        return found->second;
    }

    GLuint environment(const std::shared_ptr<const HdrImage>& owner) {
        auto found = environments.find(owner.get());
        if (found != environments.end() && found->second.owner.expired()) {
            environments.erase(found);
            found = environments.end();
        }
        if (found == environments.end()) {
            std::erase_if(environments,
                          [](const auto& entry) { return entry.second.owner.expired(); });
            gl::Object texture = gl::create_texture(GL_TEXTURE_2D);
            glTextureStorage2D(texture.get(), 1, GL_RGB32F, owner->width, owner->height);
            glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
            glTextureSubImage2D(texture.get(), 0, 0, 0, owner->width, owner->height, GL_RGB,
                                GL_FLOAT, owner->pixels.data());
            glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_S, GL_REPEAT);
            glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            found = environments.emplace(owner.get(), CachedEnvironment{owner, std::move(texture)})
                        .first;
        }
        return found->second.texture.get();
    }
};

FrameRenderer::FrameRenderer(const FrameLimits& limits) : state_(std::make_unique<State>(limits)) {
    state_->ground = upload_mesh(state_->ground_mesh);
    state_->empty_vertex_array = gl::create_vertex_array();
    state_->irradiance_buffer = gl::create_buffer();
    for (auto [sampler, filter] : {std::pair{&state_->compare_linear, GL_LINEAR},
                                   std::pair{&state_->compare_nearest, GL_NEAREST}}) {
        *sampler = gl::create_sampler();
        glSamplerParameteri(sampler->get(), GL_TEXTURE_MIN_FILTER, filter);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_MAG_FILTER, filter);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
    state_->bake_framebuffer = gl::create_framebuffer();
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &state_->max_texture_size);
    check_gl_errors("FrameRenderer set-up");
}

FrameRenderer::~FrameRenderer() = default;

std::size_t FrameRenderer::cached_shadow_maps() const {
    return state_->shadows.size();
}

namespace {

void validate(const FrameRequest& request, const FrameLimits& limits, int max_texture_size) {
    if (!request.rig) {
        fail("environment", "no light rig given");
    }
    if (request.width < 1 || request.height < 1) {
        fail("width", "the frame must be at least 1x1");
    }
    if (request.width > limits.max_width || request.height > limits.max_height) {
        throw Error(ErrorKind::LimitExceeded,
                    "width/height: " + std::to_string(request.width) + "x" +
                        std::to_string(request.height) + " is over the limit of " +
                        std::to_string(limits.max_width) + "x" + std::to_string(limits.max_height));
    }
    if (!request.lights.empty() && request.lights.size() != request.rig->lights.size()) {
        fail("lights", "the environment has " + std::to_string(request.rig->lights.size()) +
                           " light(s), got " + std::to_string(request.lights.size()) + " switches");
    }
    if (request.samples < 1 || request.samples > 16) {
        fail("samples", "must be in 1..16");
    }
    const int scale = supersampling_scale(request.samples);
    if (std::int64_t(request.width) * request.height * scale * scale > limits.max_samples_total ||
        std::max(request.width, request.height) * scale > max_texture_size) {
        throw Error(ErrorKind::LimitExceeded,
                    "samples: " + std::to_string(scale * scale) + " samples per pixel at " +
                        std::to_string(request.width) + "x" + std::to_string(request.height) +
                        " are over the limit of " + std::to_string(limits.max_samples_total) +
                        " samples per frame and " + std::to_string(max_texture_size) +
                        " samples per side");
    }
    if (request.shadows.resolution < 16 ||
        request.shadows.resolution > limits.max_shadow_resolution) {
        throw Error(ErrorKind::LimitExceeded, "shadow_resolution: must be in 16.." +
                                                  std::to_string(limits.max_shadow_resolution));
    }
    if (!std::isfinite(request.exposure) || std::abs(request.exposure) > 64.0) {
        fail("exposure", "must be a finite number of stops in [-64, 64]");
    }
    if (!std::isfinite(request.environment_yaw)) {
        fail("yaw", "must be finite");
    }
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        const std::string member = "objects[" + std::to_string(i) + "]";
        if (!object.mesh) {
            fail(member + ".mesh", "no mesh given");
        }
        if (!finite(object.transform) || std::abs(glm::determinant(object.transform)) < 1e-12f) {
            fail(member + ".transform", "must be finite and invertible");
        }
        if (object.base_color &&
            !(glm::all(glm::greaterThanEqual(*object.base_color, glm::vec3(0))) &&
              std::isfinite(object.base_color->x + object.base_color->y + object.base_color->z))) {
            fail(member + ".base_color", "must be finite and non-negative");
        }
    }
    if (!request.linear && request.background.kind == BackgroundKind::Color &&
        !glm::all(glm::lessThanEqual(glm::abs(request.background.color - 0.5f), glm::vec3(0.5f)))) {
        fail("background", "the color must be in [0, 1]");
    }
    if (request.background.kind == BackgroundKind::Environment && !request.environment_map) {
        fail("background", "the environment background needs the environment map");
    }
    if (request.camera) {
        validate_camera(*request.camera);
    }
}

}  // namespace

Frame FrameRenderer::render(const FrameRequest& request) {
    validate(request, state_->limits, state_->max_texture_size);
    State& state = *state_;
    const Rig& rig = *request.rig;
    const auto frame_start = Clock::now();
    Frame frame;
    frame.width = request.width;
    frame.height = request.height;

    // Which lights are on; their directions turned by the environment's yaw.
    const std::size_t light_count = rig.lights.size();
    std::vector<bool> on(light_count, true);
    for (std::size_t k = 0; k < request.lights.size(); ++k) {
        on[k] = request.lights[k];
    }
    std::vector<std::size_t> lit;
    for (std::size_t k = 0; k < light_count; ++k) {
        if (on[k]) {
            lit.push_back(k);
        }
    }
    const double yaw = glm::radians(request.environment_yaw);
    const glm::vec2 yaw_cos_sin{float(std::cos(yaw)), float(std::sin(yaw))};

    // Irradiance sets: the map without the lights that are off, then each light that is on.
    auto start = Clock::now();
    std::vector<double> visibility(light_count);
    for (std::size_t k = 0; k < light_count; ++k) {
        visibility[k] = on[k] ? 1.0 : 0.0;
    }
    std::vector<ShRgb> sets{
        irradiance_coefficients(visibility_coefficients(rig.sh, visibility), rig.window)};
    for (const std::size_t k : lit) {
        sets.push_back(irradiance_coefficients(rig.sh.per_light[k], rig.window));
    }
    const int order = rig.sh.all.order;
    const int count = order * order;
    std::vector<float> packed;
    packed.reserve(sets.size() * count * 4);
    for (const ShRgb& set : sets) {
        for (const glm::dvec3& c : set.coefficients) {
            packed.insert(packed.end(), {float(c.r), float(c.g), float(c.b), 0.0f});
        }
    }
    glNamedBufferData(state.irradiance_buffer.get(), GLsizeiptr(packed.size() * sizeof(float)),
                      packed.data(), GL_DYNAMIC_DRAW);
    double attenuation_base = 1.0;
    if (rig.model == LightingModel::Thesis) {
        for (std::size_t k = 0; k < light_count; ++k) {
            attenuation_base -= on[k] ? 0.0 : rig.lights[k].luminance_share;
        }
    }

    // Scene and camera.
    const SceneBounds scene = scene_bounds(request.objects);
    const float aspect = float(request.width) / float(request.height);
    const Camera camera = request.camera.value_or(frame_bounds(scene.box, 45.0f, aspect));
    const float ground_half_size = 20.0f * scene.radius;
    const float eye_distance = glm::length(camera.eye - scene.centre);
    const float far_plane =
        eye_distance + (request.ground ? 1.5f * ground_half_size : 2.0f * scene.radius);
    const float near_plane = std::max(far_plane * 1e-5f, 0.5f * (eye_distance - scene.radius));
    const glm::mat4 view_projection =
        projection_matrix(camera, aspect, std::min(near_plane, far_plane * 0.5f), far_plane) *
        view_matrix(camera);
    frame.timings_ms["setup"] = elapsed_ms(start);

    // Shadow maps, cached by scene, light, filter and resolution, held as layers by rig light.
    start = Clock::now();
    const bool shadows = request.shadows.enabled && !lit.empty();
    std::string scene_key;
    for (const SceneObject& object : request.objects) {
        const std::uint64_t id = state.mesh(object.mesh).id;
        scene_key.append(reinterpret_cast<const char*>(&id), sizeof id);
        scene_key.append(reinterpret_cast<const char*>(glm::value_ptr(object.transform)),
                         16 * sizeof(float));
    }
    const int resolution = request.shadows.resolution;
    const bool pcf = request.shadows.filter == ShadowFilter::Pcf;
    const std::string lighting_defines = "#define SH_ORDER " + std::to_string(order) +
                                         "\n#define LIGHTS_ON " + std::to_string(lit.size()) +
                                         "\n#define SHADOWS " + std::to_string(shadows ? 1 : 0) +
                                         "\n#define PCF " + std::to_string(pcf ? 1 : 0) + "\n";
    std::vector<glm::vec3> light_directions;  // of the lights that are on, turned by the yaw
    std::vector<glm::mat4> light_matrices;
    std::vector<float> light_kernels;
    for (const std::size_t k : lit) {
        const glm::vec3 direction = glm::normalize(
            glm::vec3(equirect::rotate_yaw(rig.lights[k].direction, request.environment_yaw)));
        light_directions.push_back(direction);
        light_matrices.push_back(light_matrix(direction, scene));
        // PCF radius: a penumbra about half the scene's radius from its occluder, seen through
        // the light's angular radius; at least one texel.
        light_kernels.push_back(std::max(1.0f / float(resolution),
                                         0.25f * float(std::tan(rig.lights[k].angular_radius))));
    }
    const float normal_offset = 1.5f * 2.0f * scene.radius / float(resolution);
    // The lights' uniforms, shared by the shading pass and the ground-visibility bake.
    const auto set_light_uniforms = [&](gl::Program& program) {
        const std::vector<float>& sh_scale = sh_shader_scales(order);
        glUniform1fv(program.uniform("u_sh_scale"), GLsizei(sh_scale.size()), sh_scale.data());
        for (std::size_t i = 0; i < lit.size(); ++i) {
            glUniformMatrix4fv(program.uniform(element("u_light_matrix", i)), 1, GL_FALSE,
                               glm::value_ptr(light_matrices[i]));
            glUniform1i(program.uniform(element("u_light_layer", i)), GLint(lit[i]));
            glUniform1f(program.uniform(element("u_light_kernel", i)), light_kernels[i]);
            glUniform1f(program.uniform(element("u_normal_offset", i)), normal_offset);
        }
    };
    if (shadows) {
        state.shadow_layers.reserve(int(light_count), resolution);
        glBindTextureUnit(4, state.shadow_layers.depth());
        glBindSampler(4, pcf ? state.compare_linear.get() : state.compare_nearest.get());
    }
    gl::Program& depth = state.program("depth", "");
    for (std::size_t i = 0; shadows && i < lit.size(); ++i) {
        std::string key = scene_key;
        key.append(reinterpret_cast<const char*>(glm::value_ptr(light_directions[i])),
                   3 * sizeof(float));
        key.append(reinterpret_cast<const char*>(&light_kernels[i]), sizeof(float));
        key.append(reinterpret_cast<const char*>(&resolution), sizeof resolution);
        key.push_back(pcf ? 'p' : 'h');
        bool rendered = false;
        ShadowMap& map = state.shadows.get(
            key, resolution,
            [&] {
                glUseProgram(depth.id());
                glUniformMatrix4fv(depth.uniform("u_view_projection"), 1, GL_FALSE,
                                   glm::value_ptr(light_matrices[i]));
                // Detail down to half a shadow-map texel.
                const float texel = 2.0f * scene.radius / float(resolution);
                for (const SceneObject& object : request.objects) {
                    glUniformMatrix4fv(depth.uniform("u_model"), 1, GL_FALSE,
                                       glm::value_ptr(object.transform));
                    const float max_error = 0.5f * texel / largest_scale(object.transform);
                    for (const GpuPrimitive& primitive : state.mesh(object.mesh).gpu.primitives) {
                        draw_primitive(primitive, max_error);
                    }
                }
            },
            rendered);
        frame.shadow_maps_rendered += rendered ? 1 : 0;
        const int layer = int(lit[i]);
        state.shadow_layers.hold_depth(layer, map);
        if (!request.ground) {
            continue;
        }
        if (!map.ground_visibility) {
            state.bake_ground_visibility(map, int(i), glm::inverse(light_matrices[i]),
                                         scene.box.min.y, resolution, light_kernels[i], pcf,
                                         lighting_defines, set_light_uniforms);
        }
        state.shadow_layers.hold_ground_visibility(layer, map);
    }
    glFinish();
    frame.timings_ms["shadow_pass"] = elapsed_ms(start);

    // Geometry pass: the G-buffer, supersampled for anti-aliasing.
    start = Clock::now();
    const int scale = supersampling_scale(request.samples);
    const int samples_wide = request.width * scale;
    const int samples_high = request.height * scale;
    RenderTargets& targets =
        state.targets.get(request.width, request.height, scale, request.linear);
    glBindFramebuffer(GL_FRAMEBUFFER, targets.geometry_framebuffer.get());
    glViewport(0, 0, samples_wide, samples_high);
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
                       glm::value_ptr(view_projection));
    glUniform3fv(geometry.uniform("u_eye"), 1, glm::value_ptr(camera.eye));
    // Detail down to one sample at the nearest point of a mesh's bounding sphere. A level's
    // stated error already carries a fivefold margin over meshoptimizer's (mesh_lod.cpp), and
    // a sample is half a pixel or less in an anti-aliased frame. Half a sample had kept the
    // bunny at full detail at 512x512, where its 70k triangles cost 15 ms against 10 ms for
    // 35k (llvmpipe shades a whole 4x4 block for each tiny triangle).
    const float sample_size_per_distance =
        2.0f * std::tan(glm::radians(camera.fov_y) / 2.0f) / float(samples_high);
    const auto draw = [&](const Mesh& mesh, const GpuMesh& gpu, const glm::mat4& model,
                          const std::optional<glm::vec3>& base_override, int surface_kind) {
        glStencilFunc(GL_ALWAYS, surface_kind, 0xff);
        const float scale = largest_scale(model);
        const glm::vec3 centre = glm::vec3(model * glm::vec4(mesh.bounds.centre(), 1.0f));
        const float radius = 0.5f * glm::length(mesh.bounds.max - mesh.bounds.min) * scale;
        const float distance = std::max(near_plane, glm::length(camera.eye - centre) - radius);
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
            const bool textured = !base_override && material.base_color_texture >= 0;
            glUniform1i(geometry.uniform("u_has_texture"), textured ? 1 : 0);
            if (textured) {
                glBindTextureUnit(0,
                                  gpu.textures.at(std::size_t(material.base_color_texture)).get());
            }
            glUniform1f(geometry.uniform("u_specular_weight"), material.specular ? 0.04f : 0.0f);
            // Blinn-Phong exponent of a GGX roughness (alpha = roughness^2): 2 / alpha^2 - 2.
            const float alpha = std::max(0.02f, material.roughness * material.roughness);
            glUniform1f(geometry.uniform("u_shininess"),
                        std::max(1.0f, 2.0f / (alpha * alpha) - 2.0f));
            draw_primitive(primitive, max_error);
        }
    };
    for (const SceneObject& object : request.objects) {
        const State::CachedMesh& cached = state.mesh(object.mesh);
        draw(*object.mesh, cached.gpu, object.transform, object.base_color, kObjectSurface);
    }
    if (request.ground) {
        const glm::mat4 ground_model =
            glm::translate(glm::mat4(1.0f),
                           glm::vec3(scene.centre.x, scene.box.min.y, scene.centre.z)) *
            glm::scale(glm::mat4(1.0f), glm::vec3(ground_half_size, 1.0f, ground_half_size));
        draw(state.ground_mesh, state.ground, ground_model, std::nullopt, kGroundSurface);
    }
    glDisable(GL_DEPTH_TEST);
    glFinish();
    frame.timings_ms["geometry_pass"] = elapsed_ms(start);

    // Shading pass: each sample shaded once from the G-buffer by its surface's program, which
    // the stencil test routes to it.
    start = Clock::now();
    const bool environment_background = request.background.kind == BackgroundKind::Environment;
    const bool display_in_shading = scale == 1 && !request.linear;
    const std::string shading_defines = lighting_defines + "#define ENVIRONMENT_BACKGROUND " +
                                        std::to_string(environment_background ? 1 : 0) +
                                        "\n#define DISPLAY_OUTPUT " +
                                        std::to_string(display_in_shading ? 1 : 0) + "\n";
    // The ground's normal is +Y, which the yaw leaves unchanged.
    std::vector<glm::vec3> flat_irradiance;
    for (const ShRgb& set : sets) {
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
    if (shadows) {
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
        set_light_uniforms(shade);
        glUniformMatrix4fv(shade.uniform("u_inverse_view_projection"), 1, GL_FALSE,
                           glm::value_ptr(glm::inverse(view_projection)));
        glUniform2f(shade.uniform("u_viewport_size"), float(samples_wide), float(samples_high));
        glUniform2f(shade.uniform("u_yaw"), yaw_cos_sin.x, yaw_cos_sin.y);
        glUniform3fv(shade.uniform("u_eye"), 1, glm::value_ptr(camera.eye));
        glUniform1f(shade.uniform("u_albedo_scale"), thesis ? 1.0f : float(1.0 / std::numbers::pi));
        glUniform1f(shade.uniform("u_attenuation_base"), float(attenuation_base));
        glUniform3fv(shade.uniform("u_flat_irradiance"), GLsizei(flat_irradiance.size()),
                     glm::value_ptr(flat_irradiance[0]));
        for (std::size_t i = 0; i < lit.size(); ++i) {
            const std::size_t k = lit[i];
            // Intensity from the light's own SH: sum L dOmega = sqrt(4 pi) c_00, in the units
            // of the projected map (radiance in the hdr model, tone-mapped values in the
            // thesis's).
            const glm::vec3 intensity =
                glm::vec3(rig.sh.per_light[k].coefficients[0] * std::sqrt(4.0 * std::numbers::pi));
            glUniform3fv(shade.uniform(element("u_light_direction", i)), 1,
                         glm::value_ptr(light_directions[i]));
            glUniform3fv(shade.uniform(element("u_light_intensity", i)), 1,
                         glm::value_ptr(intensity));
            glUniform1f(shade.uniform(element("u_light_share", i)),
                        thesis ? float(rig.lights[k].luminance_share) : 0.0f);
        }
        if (display_in_shading) {
            set_display_uniforms(shade, request);
        }
        glStencilFunc(GL_EQUAL, surface, 0xff);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glDisable(GL_STENCIL_TEST);
    glBindSampler(4, 0);

    // Resolve: the mean of each pixel's supersamples, then the display transform.
    if (scale > 1) {
        gl::Program& resolve = state.program(
            "resolve", "#define DISPLAY_OUTPUT " + std::to_string(request.linear ? 0 : 1) + "\n");
        glUseProgram(resolve.id());
        glUniform1i(resolve.uniform("u_scale"), scale);
        if (!request.linear) {
            set_display_uniforms(resolve, request);
        }
        glBindTextureUnit(0, targets.shaded.get());
        glBindFramebuffer(GL_FRAMEBUFFER, targets.output_framebuffer.get());
        glViewport(0, 0, request.width, request.height);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glFinish();
    frame.timings_ms["shading_pass"] = elapsed_ms(start);

    // Readback, top row first.
    start = Clock::now();
    const std::size_t row_values = std::size_t(request.width) * 4;
    if (request.linear) {
        std::vector<float> pixels(row_values * std::size_t(request.height));
        glGetTextureImage(targets.result(), 0, GL_RGBA, GL_FLOAT,
                          GLsizei(pixels.size() * sizeof(float)), pixels.data());
        frame.linear.resize(pixels.size());
        for (int y = 0; y < request.height; ++y) {
            std::memcpy(&frame.linear[std::size_t(y) * row_values],
                        &pixels[std::size_t(request.height - 1 - y) * row_values],
                        row_values * sizeof(float));
        }
    } else {
        std::vector<std::uint8_t> pixels(row_values * std::size_t(request.height));
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glGetTextureImage(targets.result(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(pixels.size()),
                          pixels.data());
        frame.display.width = request.width;
        frame.display.height = request.height;
        frame.display.pixels.resize(pixels.size());
        for (int y = 0; y < request.height; ++y) {
            std::memcpy(&frame.display.pixels[std::size_t(y) * row_values],
                        &pixels[std::size_t(request.height - 1 - y) * row_values], row_values);
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDepthMask(GL_TRUE);
    glBindVertexArray(0);
    glUseProgram(0);
    check_gl_errors("FrameRenderer::render");
    frame.timings_ms["readback"] = elapsed_ms(start);
    frame.timings_ms["total"] = elapsed_ms(frame_start);
    return frame;
}

}  // namespace oer
