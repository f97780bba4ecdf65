#include "renderer_state.hpp"

#include <utility>

#include "frame_programs.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/gl_context.hpp"
#include "oer/lighting/sheen_albedo.hpp"
#include "oer/lighting/split_sum.hpp"
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
    // A horizontal Lambertian plane of albedo 0.8 (docs/design.md section 7).
    Material material;
    material.name = "ground";
    material.base_color = {kGroundAlbedo, kGroundAlbedo, kGroundAlbedo, 1.0f};
    material.model = ShadingModel::Lambertian;
    material.double_sided = true;  // seen from below, lit with its normal flipped, as ever
    mesh.materials.push_back(material);
    return mesh;
}

}  // namespace

RendererState::RendererState(const FrameLimits& limits_)
    : limits(limits_), shadows(limits_.max_cached_shadow_maps), ground_mesh(unit_ground()) {
    ground = upload_mesh(ground_mesh);
    empty_vertex_array = gl::create_vertex_array();
    irradiance_buffer = gl::create_buffer();
    transferred_vertex_buffer = gl::create_buffer();
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
    // What mesh.vert reads for a primitive without tangents (its attribute 3 disabled): the
    // generic attribute, context state that no vertex array keeps.
    glVertexAttrib4f(3, 1.0f, 0.0f, 0.0f, 1.0f);
    // And for a primitive without vertex colours (attribute 6): white, opaque.
    glVertexAttrib4f(6, 1.0f, 1.0f, 1.0f, 1.0f);
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

namespace {

// A cube (its layers x 6 faces per level) as a trilinear RGB16F texture of `target`: a cube
// map for one layer, a cube-map array for any number. A cube map's faces, and an array's
// layer-faces, are the layers of its storage (GL 4.5 section 8.5.3), in the order of
// specular_environment.hpp. An array of no layer gets one black layer.
gl::Object cube_texture(const PrefilteredCube& cube, GLenum target) {
    gl::Object texture = gl::create_texture(target);
    const int layer_faces = 6 * std::max(cube.layers, 1);
    if (target == GL_TEXTURE_CUBE_MAP) {
        glTextureStorage2D(texture.get(), cube.levels, GL_RGB16F, cube.face_size, cube.face_size);
    } else {
        glTextureStorage3D(texture.get(), cube.levels, GL_RGB16F, cube.face_size, cube.face_size,
                           layer_faces);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    for (int level = 0; level < cube.levels; ++level) {
        const int size = cube.face_size >> level;
        const std::vector<std::uint16_t>& texels = cube.rgb_half[std::size_t(level)];
        if (cube.layers == 0) {
            const std::vector<std::uint16_t> black(std::size_t(6) * size * size * 3, 0);
            glTextureSubImage3D(texture.get(), level, 0, 0, 0, size, size, 6, GL_RGB, GL_HALF_FLOAT,
                                black.data());
        } else {
            glTextureSubImage3D(texture.get(), level, 0, 0, 0, size, size, layer_faces, GL_RGB,
                                GL_HALF_FLOAT, texels.data());
        }
    }
    glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture.get(), GL_TEXTURE_MAX_LEVEL, cube.levels - 1);
    return texture;
}

}  // namespace

RendererState::SpecularTextures RendererState::specular(
    const std::shared_ptr<const SpecularEnvironment>& owner) {
    auto found = speculars_.find(owner.get());
    if (found != speculars_.end() && found->second.owner.expired()) {
        speculars_.erase(found);
        found = speculars_.end();
    }
    if (found == speculars_.end()) {
        release_unowned_speculars();
        ++specular_uploads;
        found =
            speculars_
                .emplace(owner.get(),
                         CachedSpecular{owner, cube_texture(owner->residual, GL_TEXTURE_CUBE_MAP),
                                        cube_texture(owner->lights, GL_TEXTURE_CUBE_MAP_ARRAY)})
                .first;
    }
    return {found->second.residual.get(), found->second.lights.get()};
}

void RendererState::release_unowned_speculars() {
    std::erase_if(speculars_, [](const auto& entry) { return entry.second.owner.expired(); });
}

namespace {

// A size x size table of floats (channels 1 or 2) as a bilinear, clamped texture, for the
// shaders' lookups at (n.v, roughness).
gl::Object table_texture(int size, GLenum internal_format, GLenum format, const float* values) {
    gl::Object texture = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.get(), 1, internal_format, size, size);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture.get(), 0, 0, 0, size, size, format, GL_FLOAT, values);
    glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

}  // namespace

GLuint RendererState::dfg() {
    if (!dfg_) {
        const DfgTable table = dfg_table(32, 1024);
        dfg_ = table_texture(table.size, GL_RG32F, GL_RG, &table.scale_bias[0].x);
    }
    return dfg_.get();
}

GLuint RendererState::sheen_albedo() {
    if (!sheen_albedo_) {
        const SheenAlbedoTable table = sheen_albedo_table(32, 1024);
        sheen_albedo_ = table_texture(table.size, GL_R32F, GL_RED, table.albedo.data());
    }
    return sheen_albedo_.get();
}

namespace {

GLint gl_wrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Repeat:
            return GL_REPEAT;
        case TextureWrap::ClampToEdge:
            return GL_CLAMP_TO_EDGE;
        case TextureWrap::MirroredRepeat:
            return GL_MIRRORED_REPEAT;
    }
    throw Error(ErrorKind::Internal, "a texture wrap mode the renderer does not know");
}

// glTF's filters are GL's (specification, section 5.26). A magnification filter has no mipmaps:
// a *_MIPMAP_* value there (which the loaders do not give) means its texel filter, its first word.
GLint gl_filter(TextureFilter filter, bool magnification) {
    switch (filter) {
        case TextureFilter::Nearest:
            return GL_NEAREST;
        case TextureFilter::Linear:
            return GL_LINEAR;
        case TextureFilter::NearestMipmapNearest:
            return magnification ? GL_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
        case TextureFilter::LinearMipmapNearest:
            return magnification ? GL_LINEAR : GL_LINEAR_MIPMAP_NEAREST;
        case TextureFilter::NearestMipmapLinear:
            return magnification ? GL_NEAREST : GL_NEAREST_MIPMAP_LINEAR;
        case TextureFilter::LinearMipmapLinear:
            return magnification ? GL_LINEAR : GL_LINEAR_MIPMAP_LINEAR;
    }
    throw Error(ErrorKind::Internal, "a texture filter the renderer does not know");
}

}  // namespace

GLuint RendererState::sampler(const TextureSampler& sampler) {
    for (const auto& [known, object] : samplers_) {
        if (known == sampler) {
            return object.get();
        }
    }
    gl::Object object = gl::create_sampler();
    glSamplerParameteri(object.get(), GL_TEXTURE_WRAP_S, gl_wrap(sampler.wrap_s));
    glSamplerParameteri(object.get(), GL_TEXTURE_WRAP_T, gl_wrap(sampler.wrap_t));
    glSamplerParameteri(object.get(), GL_TEXTURE_MAG_FILTER, gl_filter(sampler.mag_filter, true));
    glSamplerParameteri(object.get(), GL_TEXTURE_MIN_FILTER, gl_filter(sampler.min_filter, false));
    samplers_.emplace_back(sampler, std::move(object));
    return samplers_.back().second.get();
}

}  // namespace oer
