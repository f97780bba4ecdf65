#include "material_uniforms.hpp"

#include <array>

#include <glm/gtc/type_ptr.hpp>

#include "gl_bindings.hpp"

namespace oer {

namespace {

using gl_bindings::kMaterialTextures;
constexpr int kReferences = int(kMaterialTextures.size());

}  // namespace

void set_material_uniforms(gl::Program& program, RendererState& state, const GpuMesh& gpu,
                           const Material& material,
                           const std::optional<glm::vec3>& base_override) {
    // In material.glsl's order.
    const std::array<const TextureReference*, kReferences> references{
        &material.base_color_texture, &material.metallic_roughness_texture,
        &material.normal_texture, &material.occlusion_texture, &material.emissive_texture};
    std::array<glm::mat3, kReferences> transforms{};
    GLint present = 0;
    GLint uv_sets = 0;
    for (int i = 0; i < kReferences; ++i) {
        const TextureReference& reference = *references[std::size_t(i)];
        transforms[std::size_t(i)] = reference.uv_transform();
        if (!reference.present()) {
            continue;
        }
        present |= 1 << i;
        if (reference.texcoord == 1) {
            uv_sets |= 1 << i;
        }
        const GLuint unit = kMaterialTextures[std::size_t(i)].index;
        glBindTextureUnit(unit, gpu.textures.at(std::size_t(reference.texture)).get());
        glBindSampler(unit, state.sampler(reference.sampler));
    }
    glUniform1i(program.uniform("u_textures"), present);
    glUniform1i(program.uniform("u_uv_sets"), uv_sets);
    glUniformMatrix3fv(program.uniform("u_uv_transform"), kReferences, GL_FALSE,
                       glm::value_ptr(transforms[0]));
    const glm::vec4 base =
        base_override ? glm::vec4(*base_override, material.base_color.a) : material.base_color;
    glUniform4fv(program.uniform("u_base_color"), 1, glm::value_ptr(base));
    glUniform1f(program.uniform("u_base_texture_color"), base_override ? 0.0f : 1.0f);
    glUniform1f(program.uniform("u_metallic"),
                material.model == ShadingModel::Lambertian ? -1.0f : material.metallic);
    glUniform1f(program.uniform("u_roughness"), material.roughness);
    glUniform1f(program.uniform("u_normal_scale"), material.normal_scale);
    glUniform1f(program.uniform("u_occlusion_strength"), material.occlusion_strength);
    const glm::vec3 emissive = material.emissive * material.emissive_strength;
    glUniform3fv(program.uniform("u_emissive"), 1, glm::value_ptr(emissive));
    glUniform1f(program.uniform("u_alpha_cutoff"),
                material.alpha_mode == AlphaMode::Blend ? 0.5f : material.alpha_cutoff);
}

void unbind_material_samplers() {
    for (const gl_bindings::Binding& texture : kMaterialTextures) {
        glBindSampler(texture.index, 0);
    }
}

bool has_textures(const Material& material) {
    return material.base_color_texture.present() || material.metallic_roughness_texture.present() ||
           material.normal_texture.present() || material.occlusion_texture.present() ||
           material.emissive_texture.present();
}

bool alpha_tested(const Material& material) {
    return material.alpha_mode != AlphaMode::Opaque &&
           (material.base_color_texture.present() || material.base_color.a < 1.0f);
}

bool alpha_tested(const Material& material, const Primitive& primitive) {
    return alpha_tested(material) ||
           (material.alpha_mode != AlphaMode::Opaque && !primitive.colors.empty());
}

bool reads_textures_or_colors(const Material& material, const Primitive& primitive) {
    return has_textures(material) || !primitive.colors.empty();
}

}  // namespace oer
