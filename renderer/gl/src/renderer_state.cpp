#include "renderer_state.hpp"

#include <utility>

#include "frame_programs.hpp"
#include "oer/gl/gl_context.hpp"
#include "shader_sources.hpp"

namespace oer {

namespace {

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
    material.model = ShadingModel::Lambertian;
    mesh.materials.push_back(material);
    return mesh;
}

}  // namespace

RendererState::RendererState(const FrameLimits& limits_)
    : limits(limits_), shadows(limits_.max_cached_shadow_maps), ground_mesh(unit_ground()) {
    ground = upload_mesh(ground_mesh);
    empty_vertex_array = gl::create_vertex_array();
    irradiance_buffer = gl::create_buffer();
    for (auto [sampler, filter] :
         {std::pair{&compare_linear, GL_LINEAR}, std::pair{&compare_nearest, GL_NEAREST}}) {
        *sampler = gl::create_sampler();
        glSamplerParameteri(sampler->get(), GL_TEXTURE_MIN_FILTER, filter);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_MAG_FILTER, filter);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glSamplerParameteri(sampler->get(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
    depth_nearest = gl::create_sampler();
    glSamplerParameteri(depth_nearest.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(depth_nearest.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(depth_nearest.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(depth_nearest.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(depth_nearest.get(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
    bake_framebuffer = gl::create_framebuffer();
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size);
    check_gl_errors("FrameRenderer set-up");
}

gl::Program& RendererState::program(const std::string& name, const std::string& defines) {
    const std::string key = name + "\n" + defines;
    auto found = programs_.find(key);
    if (found == programs_.end()) {
        const shaders::FrameProgram& stages = shaders::frame_program(name);
        shaders::check_defines(stages, defines);
        found = programs_
                    .emplace(key, std::make_unique<gl::Program>(
                                      shaders::program_source(stages.vertex, defines),
                                      shaders::program_source(stages.fragment, defines), name))
                    .first;
    }
    return *found->second;
}

RendererState::CachedMesh& RendererState::mesh(const std::shared_ptr<const Mesh>& owner) {
    auto found = meshes_.find(owner.get());
    if (found != meshes_.end() && found->second.owner.expired()) {
        meshes_.erase(found);  // the address was reused by a new mesh
        found = meshes_.end();
    }
    if (found == meshes_.end()) {
        std::erase_if(meshes_, [](const auto& entry) { return entry.second.owner.expired(); });
        CachedMesh cached{owner, next_mesh_id_++, upload_mesh(*owner)};
        found = meshes_.emplace(owner.get(), std::move(cached)).first;
    }
    return found->second;
}

GLuint RendererState::environment(const std::shared_ptr<const HdrImage>& owner) {
    auto found = environments_.find(owner.get());
    if (found != environments_.end() && found->second.owner.expired()) {
        environments_.erase(found);
        found = environments_.end();
    }
    if (found == environments_.end()) {
        std::erase_if(environments_,
                      [](const auto& entry) { return entry.second.owner.expired(); });
        gl::Object texture = gl::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(texture.get(), 1, GL_RGB32F, owner->width, owner->height);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage2D(texture.get(), 0, 0, 0, owner->width, owner->height, GL_RGB, GL_FLOAT,
                            owner->pixels.data());
        glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        found =
            environments_.emplace(owner.get(), CachedEnvironment{owner, std::move(texture)}).first;
    }
    return found->second.texture.get();
}

}  // namespace oer
