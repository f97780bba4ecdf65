#pragma once
// A primitive's material as material.glsl reads it (the geometry pass, the shadow pass's alpha
// test and the transparent pass): its factors as uniforms, its textures bound to gl_bindings.hpp's
// kMaterialTextures with the sampler object of each reference, and each reference's uv transform.
#include <optional>

#include <glm/vec3.hpp>

#include "gl_program.hpp"
#include "gpu_mesh.hpp"
#include "oer/mesh/mesh.hpp"
#include "renderer_state.hpp"

namespace oer {

// Sets the material's uniforms on `program` (in use) and binds its textures. base_override
// (SceneObject::base_color) replaces the base colour and the texture's RGB, keeping the
// material's alpha and the texture's, so that its MASK and BLEND cut-outs stay where they are.
void set_material_uniforms(gl::Program& program, RendererState& state, const GpuMesh& gpu,
                           const Material& material, const std::optional<glm::vec3>& base_override);

// Unbinds the samplers of kMaterialTextures (a pass that set materials leaves none behind).
void unbind_material_samplers();

// Whether the material's alpha can cut its surface: MASK and BLEND materials with a base-colour
// texture or an alpha under 1. The geometry pass tests MASK ones at alpha_cutoff, the shadow
// pass both (BLEND at 0.5, u_alpha_cutoff as set_material_uniforms sets it).
bool alpha_tested(const Material& material);
// The same for the material on `primitive`, whose vertex colours' alpha (COLOR_0) can cut it too.
bool alpha_tested(const Material& material, const Primitive& primitive);

// Whether the geometry pass reads the material's textures or the primitive's vertex colours
// (MATERIAL_TEXTURES 1).
bool reads_textures_or_colors(const Material& material, const Primitive& primitive);

}  // namespace oer
