#include "material_uniforms.hpp"

#include <array>

#include <glm/gtc/type_ptr.hpp>

#include "gl_bindings.hpp"

namespace oer {

namespace {

using gl_bindings::kMaterialTextures;
constexpr int kReferences = int(kMaterialTextures.size());
static_assert(kMaterialTextures.size() == kMaterialTextureCount,
              "a unit for every reference of Material::texture_references");

// material.glsl's u_metallic: the metallic factor, or the code of a model without the
// metallic-roughness BRDF, -1 Lambertian and -2 unlit (surface_shading.glsl).
float metallic_code(const Material& material) {
    switch (material.model) {
        case ShadingModel::Lambertian:
            return -1.0f;
        case ShadingModel::Unlit:
            return -2.0f;
        case ShadingModel::MetallicRoughness:
            break;
    }
    return material.metallic;
}

// The layers' uniforms of material.glsl (MATERIAL_LAYERS 1).
void set_layer_uniforms(gl::Program& program, const Material& material) {
    glUniform1f(program.uniform("u_ior"), material.ior);
    glUniform1f(program.uniform("u_specular_factor"), material.specular.factor);
    glUniform3fv(program.uniform("u_specular_color"), 1, glm::value_ptr(material.specular.color));
    glUniform1f(program.uniform("u_clearcoat"), material.clearcoat.factor);
    glUniform1f(program.uniform("u_clearcoat_roughness"), material.clearcoat.roughness);
    glUniform1f(program.uniform("u_clearcoat_normal_scale"), material.clearcoat.normal_scale);
    glUniform3fv(program.uniform("u_sheen_color"), 1, glm::value_ptr(material.sheen.color));
    glUniform1f(program.uniform("u_sheen_roughness"), material.sheen.roughness);
    glUniform1f(program.uniform("u_transmission"), material.transmission.factor);
    glUniform1f(program.uniform("u_thickness"), material.volume.thickness);
    // KHR_materials_volume's attenuation coefficient, -ln(attenuationColor) / attenuationDistance
    // (0 at the default infinite distance); a black channel absorbs everything: a coefficient
    // large enough that any thickness a float holds leaves nothing.
    glm::vec3 coefficient(0.0f);
    for (int c = 0; c < 3; ++c) {
        const float color = material.volume.attenuation_color[c];
        coefficient[c] =
            color > 0.0f ? -std::log(color) / material.volume.attenuation_distance : 1e30f;
    }
    glUniform3fv(program.uniform("u_attenuation_coefficient"), 1, glm::value_ptr(coefficient));
}

}  // namespace

void set_material_uniforms(gl::Program& program, RendererState& state, const GpuMesh& gpu,
                           const Material& material,
                           const std::optional<glm::vec3>& base_override) {
    // In material.glsl's order.
    const auto references = material.texture_references();
    std::array<glm::mat3, kReferences> transforms{};
    GLint present = 0;
    GLint uv_sets = 0;
    for (int i = 0; i < kReferences; ++i) {
        const TextureReference& reference = *references[std::size_t(i)].reference;
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
    glUniform1f(program.uniform("u_metallic"), metallic_code(material));
    glUniform1f(program.uniform("u_roughness"), material.roughness);
    glUniform1f(program.uniform("u_normal_scale"), material.normal_scale);
    glUniform1f(program.uniform("u_occlusion_strength"), material.occlusion_strength);
    const glm::vec3 emissive = material.emissive * material.emissive_strength;
    glUniform3fv(program.uniform("u_emissive"), 1, glm::value_ptr(emissive));
    glUniform1f(program.uniform("u_alpha_cutoff"),
                material.alpha_mode == AlphaMode::Blend ? 0.5f : material.alpha_cutoff);
    if (material.layered()) {
        set_layer_uniforms(program, material);
    }
}

void unbind_material_samplers() {
    for (const gl_bindings::Binding& texture : kMaterialTextures) {
        glBindSampler(texture.index, 0);
    }
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
    return material.uses_textures() || !primitive.colors.empty();
}

}  // namespace oer
