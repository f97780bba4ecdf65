#pragma once
// What a FrameRenderer keeps between frames: its programs, the GL copies of meshes, environment
// maps and prefiltered specular cubes (dropped once their owners are gone), the texture
// samplers of the materials, the split sum's DFG table (made on the first glossy frame), the
// shadow-map cache and its array layers, the render targets, and the fixed objects every frame
// uses. The frame passes
// (passes/frame_passes.hpp) read and fill it; it belongs to the thread of the GL context.
#include <GL/glcorearb.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "frame_context.hpp"
#include "gl_objects.hpp"
#include "gl_program.hpp"
#include "gpu_mesh.hpp"
#include "oer/core/image.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/scene/frame_request.hpp"
#include "render_targets.hpp"
#include "shadow_layers.hpp"
#include "shadow_map_cache.hpp"

namespace oer {

struct RendererState {
    explicit RendererState(const FrameLimits& limits);

    // The program `name` of frame_programs.cpp specialised by `defines`, linked on first use.
    gl::Program& program(const std::string& name, const std::string& defines);

    struct CachedMesh {
        std::weak_ptr<const Mesh> owner;
        std::uint64_t id = 0;  // unique over the renderer's life: part of the shadow-map keys
        GpuMesh gpu;
    };
    // The mesh uploaded, on first use or when its address now belongs to a new mesh.
    CachedMesh& mesh(const std::shared_ptr<const Mesh>& owner);
    // The map as a linear RGB32F texture, repeating in x, uploaded likewise.
    GLuint environment(const std::shared_ptr<const HdrImage>& owner);
    // The prefiltered cubes (specular_environment.hpp): the residual as a seamless RGB16F cube
    // map with its levels, the lights' as a cube-map array of one layer per light (none: an
    // array of one black layer, so that the sampler is complete), trilinear, uploaded likewise;
    // counted in specular_uploads.
    struct SpecularTextures {
        GLuint residual = 0;
        GLuint lights = 0;
    };
    SpecularTextures specular(const std::shared_ptr<const SpecularEnvironment>& owner);
    // The split sum's DFG table (dfg_table(32, 1024)) as an RG32F texture, bilinear and
    // clamped, computed and uploaded on first use.
    GLuint dfg();
    // The sheen lobe's directional albedo (sheen_albedo_table(32, 1024)) as an R32F texture,
    // bilinear and clamped, computed and uploaded on first use (a frame with layers).
    GLuint sheen_albedo();
    // The sampler object of a glTF sampler, made on first use.
    GLuint sampler(const TextureSampler& sampler);
    // Deletes the GL copies of cubes whose owners are gone (run once per frame), so that a
    // renderer holds no specular memory beyond the requests that still hold their cubes.
    void release_unowned_speculars();

    FrameLimits limits;
    ShadowMapCache shadows;
    TransferredIrradianceCache transferred;
    ShadowLayers shadow_layers;
    gl::Object bake_framebuffer;  // the ground-visibility bake's
    RenderTargetCache targets;

    Mesh ground_mesh;  // a unit square at y = 0 facing +Y, scaled and placed per frame
    GpuMesh ground;
    gl::Object empty_vertex_array;  // the full-screen triangle's: its vertices come from ids
    gl::Object compare_linear;      // depth-comparison samplers for the shadow layers: PCF
    gl::Object compare_nearest;     // and the hard test
    gl::Object depth_nearest;       // the layers' depths as values: PCSS's blocker search
    gl::Object irradiance_buffer;   // the frame's SH irradiance sets (shader storage)
    // Occlusion frames: the transfer's irradiance per vertex of every object's primitives
    // (FrameContext::transferred_vertices, attribute 4), and over the ground's grid (RGB32F,
    // bilinear, clamped; remade when the grid's resolution changes).
    gl::Object transferred_vertex_buffer;
    gl::Object ground_transfer;
    int ground_transfer_resolution = 0;
    int max_texture_size = 0;
    std::size_t specular_uploads = 0;  // cubes uploaded over the renderer's life, for tests

  private:
    struct CachedEnvironment {
        std::weak_ptr<const HdrImage> owner;
        gl::Object texture;
    };
    std::map<std::string, std::unique_ptr<gl::Program>> programs_;
    std::map<const Mesh*, CachedMesh> meshes_;
    std::uint64_t next_mesh_id_ = 1;
    std::map<const HdrImage*, CachedEnvironment> environments_;
    struct CachedSpecular {
        std::weak_ptr<const SpecularEnvironment> owner;
        gl::Object residual;
        gl::Object lights;
    };
    std::map<const SpecularEnvironment*, CachedSpecular> speculars_;
    gl::Object dfg_;
    gl::Object sheen_albedo_;
    std::vector<std::pair<TextureSampler, gl::Object>> samplers_;
};

}  // namespace oer
