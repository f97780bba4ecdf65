#pragma once
// Every texture unit and buffer binding point the frame's programs read, named once. The C++
// binds through these constants; the shaders name the same points by the `glsl` names, which
// program_source (shader_sources.hpp) defines after each stage's #version line
// (binding_defines), so that a shader declares `layout(binding = SHADOW_MAPS_UNIT)` and no
// number is matched by hand. The shader test (tests/gl/shader_sources_test.cpp) fails if a
// shader binds a point by a literal or by a name missing here, if a name here is bound by no
// shader, or if one program reads two names of the same point.
#include <GL/glcorearb.h>

#include <array>
#include <string>
#include <string_view>

namespace oer::gl_bindings {

enum class BindingKind {
    TextureUnit,    // glBindTextureUnit, a sampler's `layout(binding = ...)`
    ShaderStorage,  // glBindBufferBase(GL_SHADER_STORAGE_BUFFER), a `buffer` block's
};

struct Binding {
    std::string_view glsl;  // the define the shaders read: "SHADOW_MAPS_UNIT"
    BindingKind kind;
    GLuint index;  // the texture unit or the buffer binding point
};

// The G-buffer (render_targets.hpp) as the shading pass reads it (shade.frag).
inline constexpr Binding kGBufferPositions{"GBUFFER_POSITIONS_UNIT", BindingKind::TextureUnit, 0};
inline constexpr Binding kGBufferNormals{"GBUFFER_NORMALS_UNIT", BindingKind::TextureUnit, 1};
inline constexpr Binding kGBufferAlbedos{"GBUFFER_ALBEDOS_UNIT", BindingKind::TextureUnit, 2};
inline constexpr Binding kGBufferEmissive{"GBUFFER_EMISSIVE_UNIT", BindingKind::TextureUnit, 7};
// The occlusion frame's transferred irradiance: the G-buffer's, read for objects (SURFACE 1),
// and the ground's grid, read for the ground (SURFACE 2) and for what glossy objects reflect of
// it (SPECULAR 1), which reads both.
inline constexpr Binding kGBufferTransferred{"GBUFFER_TRANSFERRED_UNIT", BindingKind::TextureUnit,
                                             15};
inline constexpr Binding kGroundTransfer{"GROUND_TRANSFER_UNIT", BindingKind::TextureUnit, 29};
// The G-buffer's layers of materials with the extensions' layers, packed in two targets
// (layer_gbuffer.glsl), read for them (SURFACE 4).
inline constexpr Binding kGBufferLayersFirst{"GBUFFER_LAYERS_FIRST_UNIT", BindingKind::TextureUnit,
                                             27};
inline constexpr Binding kGBufferLayersSecond{"GBUFFER_LAYERS_SECOND_UNIT",
                                              BindingKind::TextureUnit, 28};
// The environment map behind the scene (shade.frag, SURFACE 0).
inline constexpr Binding kEnvironment{"ENVIRONMENT_UNIT", BindingKind::TextureUnit, 3};
// The shadow layers (shadow_layers.hpp), bound by the shadow pass for its ground-visibility
// bake and every pass after it (shadow_filter.glsl): the depth layers with a comparison sampler,
// the same layers with a nearest sampler for PCSS's blocker search, and the ground's visibility.
inline constexpr Binding kShadowMaps{"SHADOW_MAPS_UNIT", BindingKind::TextureUnit, 4};
inline constexpr Binding kShadowDepths{"SHADOW_DEPTHS_UNIT", BindingKind::TextureUnit, 6};
inline constexpr Binding kGroundVisibility{"GROUND_VISIBILITY_UNIT", BindingKind::TextureUnit, 5};
// A specular frame's prefiltered cubes, the residual's and the lights' array, and the split
// sum's DFG table (specular_lighting.glsl).
inline constexpr Binding kSpecularCube{"SPECULAR_CUBE_UNIT", BindingKind::TextureUnit, 8};
inline constexpr Binding kDfgTable{"DFG_TABLE_UNIT", BindingKind::TextureUnit, 9};
inline constexpr Binding kLightCubes{"LIGHT_CUBES_UNIT", BindingKind::TextureUnit, 26};
// A material's textures (material.glsl), in the order of its references
// (Material::texture_references): the core five, then the layers' nine (MATERIAL_LAYERS 1).
inline constexpr std::array<Binding, 14> kMaterialTextures{{
    {"BASE_COLOR_TEXTURE_UNIT", BindingKind::TextureUnit, 10},
    {"METALLIC_ROUGHNESS_TEXTURE_UNIT", BindingKind::TextureUnit, 11},
    {"NORMAL_TEXTURE_UNIT", BindingKind::TextureUnit, 12},
    {"OCCLUSION_TEXTURE_UNIT", BindingKind::TextureUnit, 13},
    {"EMISSIVE_TEXTURE_UNIT", BindingKind::TextureUnit, 14},
    {"SPECULAR_TEXTURE_UNIT", BindingKind::TextureUnit, 16},
    {"SPECULAR_COLOR_TEXTURE_UNIT", BindingKind::TextureUnit, 17},
    {"CLEARCOAT_TEXTURE_UNIT", BindingKind::TextureUnit, 18},
    {"CLEARCOAT_ROUGHNESS_TEXTURE_UNIT", BindingKind::TextureUnit, 19},
    {"CLEARCOAT_NORMAL_TEXTURE_UNIT", BindingKind::TextureUnit, 20},
    {"SHEEN_COLOR_TEXTURE_UNIT", BindingKind::TextureUnit, 21},
    {"SHEEN_ROUGHNESS_TEXTURE_UNIT", BindingKind::TextureUnit, 22},
    {"TRANSMISSION_TEXTURE_UNIT", BindingKind::TextureUnit, 23},
    {"THICKNESS_TEXTURE_UNIT", BindingKind::TextureUnit, 24},
}};
// The sheen lobe's directional albedo (surface_shading.glsl, MATERIAL_LAYERS 1).
inline constexpr Binding kSheenAlbedo{"SHEEN_ALBEDO_UNIT", BindingKind::TextureUnit, 25};
// The supersampled radiance the resolve pass averages (resolve.frag).
inline constexpr Binding kResolveRadiance{"RESOLVE_RADIANCE_UNIT", BindingKind::TextureUnit, 0};
// The frame's SH irradiance sets (sh_lighting.glsl).
inline constexpr Binding kIrradianceSets{"IRRADIANCE_SETS_BINDING", BindingKind::ShaderStorage, 0};

// Every binding above.
inline constexpr std::array<Binding, 32> kBindings{
    kGBufferPositions,     kGBufferNormals,       kGBufferAlbedos,       kGBufferEmissive,
    kGBufferTransferred,   kGroundTransfer,       kEnvironment,          kShadowMaps,
    kShadowDepths,         kGroundVisibility,     kSpecularCube,         kDfgTable,
    kMaterialTextures[0],  kMaterialTextures[1],  kMaterialTextures[2],  kMaterialTextures[3],
    kMaterialTextures[4],  kMaterialTextures[5],  kMaterialTextures[6],  kMaterialTextures[7],
    kMaterialTextures[8],  kMaterialTextures[9],  kMaterialTextures[10], kMaterialTextures[11],
    kMaterialTextures[12], kMaterialTextures[13], kSheenAlbedo,          kResolveRadiance,
    kIrradianceSets,       kLightCubes,           kGBufferLayersFirst,   kGBufferLayersSecond};

// "#define GBUFFER_POSITIONS_UNIT 0\n..." for every binding, for the shaders.
inline std::string binding_defines() {
    std::string defines;
    for (const Binding& binding : kBindings) {
        defines += "#define ";
        defines += binding.glsl;
        defines += ' ';
        defines += std::to_string(binding.index);
        defines += '\n';
    }
    return defines;
}

}  // namespace oer::gl_bindings
