#pragma once
// Meshes ready for drawing: every glTF node transform baked into the positions, normals and
// tangents (world space of the file, no rescaling), every primitive as an indexed triangle
// list, with the materials and textures they use. Produced by the loaders (mesh_loading.hpp)
// and by code (default_product.hpp); validated before anything reaches GL.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "oer/mesh/look_at_camera.hpp"

namespace oer {

// How a texture's 8-bit values map to shading values: sRGB-encoded colour (base colour,
// emissive) or linear data (metallic-roughness, normal, occlusion), per the glTF 2.0
// specification, section 3.9.
enum class TextureEncoding { Srgb, Linear };

// An 8-bit RGBA image, row 0 at the top. One image read with both encodings is two textures.
struct Texture {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  // width * height * 4
    TextureEncoding encoding = TextureEncoding::Srgb;
};

// glTF 2.0 samplers (section 5.26), with its defaults when a texture has none: repeat, and
// linear filtering with linear mipmaps.
enum class TextureWrap { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter {
    Nearest,
    Linear,
    NearestMipmapNearest,
    LinearMipmapNearest,
    NearestMipmapLinear,
    LinearMipmapLinear,
};
struct TextureSampler {
    TextureWrap wrap_s = TextureWrap::Repeat;
    TextureWrap wrap_t = TextureWrap::Repeat;
    TextureFilter mag_filter = TextureFilter::Linear;  // Nearest or Linear only
    TextureFilter min_filter = TextureFilter::LinearMipmapLinear;
    bool operator==(const TextureSampler&) const = default;
};

// A material's use of a texture: which one, how it is sampled, and KHR_texture_transform's
// uv transform, applied as uv' = T * (u, v, 1) with T = translation(offset) * rotation(rotation)
// * scale(scale) (the extension's own order). TEXCOORD_0 and TEXCOORD_1 are read (a normal
// texture on TEXCOORD_0 only: tangents follow it): a reference to another set is dropped with a
// warning.
struct TextureReference {
    int texture = -1;  // index into Mesh::textures, or -1: none
    // The uv set it reads: 0 (Primitive::texcoords, TEXCOORD_0) or 1 (Primitive::texcoords1,
    // TEXCOORD_1); the file's texCoord, or KHR_texture_transform's.
    int texcoord = 0;
    TextureSampler sampler;
    glm::vec2 offset{0.0f};
    float rotation = 0.0f;  // radians, counter-clockwise in uv
    glm::vec2 scale{1.0f};
    bool present() const { return texture >= 0; }
    // KHR_texture_transform's matrix, translation(offset) * rotation(rotation) * scale(scale),
    // as the extension's own GLSL builds it: the rasteriser's uniform and the reference's uv.
    glm::mat3 uv_transform() const;
};

enum class ShadingModel {
    // Albedo only: E * albedo / pi, no specular term. An OBJ without a material (albedo 0.8,
    // docs/design.md section 3) and the default product's fabric.
    Lambertian,
    // The glTF 2.0 metallic-roughness BRDF (specification, Appendix B): GGX, height-correlated
    // Smith visibility, Schlick Fresnel, Lambertian diffuse, lit by the split-sum specular
    // image-based lighting of the environment and its lights; with the layers of
    // Material::layered() where the material has them.
    MetallicRoughness,
    // KHR_materials_unlit (Khronos, 2019): the base colour (factor, texture and vertex colour)
    // is the radiance sent, whatever the lighting; alpha as in the core model.
    Unlit,
};

// The glTF material extensions that layer lobes over the metallic-roughness BRDF, each with
// the specification's defaults (docs/materials.md has their formulas as shaded).

// KHR_materials_specular (Khronos, 2022): the dielectric's reflectance, f0 = min(f0(ior) *
// color, 1) * factor and f90 = factor, so that factor 0 leaves only the diffuse (or transmitted)
// lobe. Metals are unchanged.
struct SpecularLayer {
    float factor = 1.0f;             // [0, 1]
    TextureReference texture;        // linear, its A multiplies factor
    glm::vec3 color{1.0f};           // at least 0, may exceed 1 (f0 is clamped to 1)
    TextureReference color_texture;  // sRGB, its RGB multiplies color
    bool present() const {
        return factor != 1.0f || color != glm::vec3(1.0f) || texture.present() ||
               color_texture.present();
    }
};

// KHR_materials_clearcoat (Khronos, 2021): a GGX layer of f0 0.04 (an ior of 1.5) over the
// material, of weight factor (times the texture's R) and its own roughness (times the roughness
// texture's G) and normal map; the material beneath is attenuated by 1 - factor F_coat(n_c.v).
struct ClearcoatLayer {
    float factor = 0.0f;  // [0, 1]; 0: no coat
    TextureReference texture;
    float roughness = 0.0f;  // [0, 1], perceptual
    TextureReference roughness_texture;
    // Tangent-space, as normal_texture (TEXCOORD_0, the same tangents); none: the coat follows
    // the interpolated vertex normal, not the material's normal map (the specification).
    TextureReference normal_texture;
    float normal_scale = 1.0f;
};

// KHR_materials_sheen (Khronos, 2021): a Charlie sheen lobe (A. Estevez and C. Kulla,
// "Production Friendly Microfacet Sheen BRDF", 2017) of colour color (times the colour
// texture's RGB) and roughness (times the roughness texture's A) over the material, which it
// scales by 1 - max(color) E_sheen(n.v, roughness), its directional albedo.
struct SheenLayer {
    glm::vec3 color{0.0f};               // [0, 1]; black: no sheen
    TextureReference color_texture;      // sRGB
    float roughness = 0.0f;              // [0, 1], perceptual
    TextureReference roughness_texture;  // linear, A
};

// KHR_materials_transmission (Khronos, 2021): the share of the dielectric's diffuse lobe that
// is transmitted instead, factor times the texture's R; the surface is thin-walled (light leaves
// it where it enters) unless KHR_materials_volume gives it a thickness.
struct TransmissionLayer {
    float factor = 0.0f;  // [0, 1]
    TextureReference texture;
};

// KHR_materials_volume (Khronos, 2021): the medium under a transmitting surface. Only its
// Beer-Lambert attenuation is shaded, over thickness (times the texture's G): transmitted light
// is multiplied by attenuation_color^(thickness / attenuation_distance); the refraction of a
// thick volume is not (the transmitted direction stays the thin wall's).
struct VolumeLayer {
    float thickness = 0.0f;  // at least 0, in the mesh's own units; 0: thin-walled
    TextureReference thickness_texture;
    float attenuation_distance = std::numeric_limits<float>::infinity();  // above 0
    glm::vec3 attenuation_color{1.0f};                                    // [0, 1]
};

// A texture reference of a material with the name of its glTF property, for messages.
struct NamedTextureReference {
    const char* property;  // "baseColorTexture", ...
    const TextureReference* reference;
};
inline constexpr std::size_t kMaterialTextureCount = 14;

// glTF 2.0 alpha modes (section 3.9.4).
enum class AlphaMode { Opaque, Mask, Blend };

struct Material {
    std::string name;
    ShadingModel model = ShadingModel::MetallicRoughness;
    // Linear RGBA multiplier of the base color (glTF baseColorFactor).
    glm::vec4 base_color{1.0f, 1.0f, 1.0f, 1.0f};
    TextureReference base_color_texture;  // sRGB; its alpha multiplies base_color's
    // glTF defaults: metallic 1, roughness 1 (perceptual roughness; the GGX alpha is its
    // square). Their texture holds roughness in G and metallic in B, linear.
    float metallic = 1.0f;
    float roughness = 1.0f;
    TextureReference metallic_roughness_texture;
    // Tangent-space normal map (linear, (0.5, 0.5, 1) flat); its xy are scaled by normal_scale.
    TextureReference normal_texture;
    float normal_scale = 1.0f;
    // Ambient occlusion in R (linear), blended as 1 + strength * (ao - 1).
    TextureReference occlusion_texture;
    float occlusion_strength = 1.0f;
    // Emitted radiance: emissive * emissive_strength (KHR_materials_emissive_strength) times
    // the emissive texture (sRGB), in the units of the environment's radiance.
    glm::vec3 emissive{0.0f};
    float emissive_strength = 1.0f;
    TextureReference emissive_texture;
    AlphaMode alpha_mode = AlphaMode::Opaque;
    float alpha_cutoff = 0.5f;  // Mask only
    bool double_sided = false;

    // KHR_materials_ior (Khronos, 2021): the dielectric's index of refraction, 1 or more, or 0
    // (the specification's special case: full weight to the specular layer, f0 = 1). The
    // dielectric's f0 = ((ior - 1) / (ior + 1))^2, 0.04 at the default 1.5.
    float ior = 1.5f;
    SpecularLayer specular;
    ClearcoatLayer clearcoat;
    SheenLayer sheen;
    TransmissionLayer transmission;
    VolumeLayer volume;

    // Whether the material has a specular term, so that its scene needs the specular maps.
    bool glossy() const { return model == ShadingModel::MetallicRoughness; }
    // Whether a layer extension changes what the material reflects (a factor or texture away
    // from the specification's default): such a material is shaded by the renderer's layered
    // programs, every other by the plain ones, which cost nothing more for the extensions.
    bool layered() const {
        return glossy() && (ior != 1.5f || specular.present() || clearcoat.factor > 0.0f ||
                            sheen.color != glm::vec3(0.0f) || transmission.factor > 0.0f);
    }
    // Whether a normal map (the material's or the clear coat's) needs tangents.
    bool needs_tangents() const {
        return normal_texture.present() || clearcoat.normal_texture.present();
    }
    // Every texture reference, in the order the renderer binds them (material.glsl).
    std::array<NamedTextureReference, kMaterialTextureCount> texture_references() const {
        return {{{"baseColorTexture", &base_color_texture},
                 {"metallicRoughnessTexture", &metallic_roughness_texture},
                 {"normalTexture", &normal_texture},
                 {"occlusionTexture", &occlusion_texture},
                 {"emissiveTexture", &emissive_texture},
                 {"specularTexture", &specular.texture},
                 {"specularColorTexture", &specular.color_texture},
                 {"clearcoatTexture", &clearcoat.texture},
                 {"clearcoatRoughnessTexture", &clearcoat.roughness_texture},
                 {"clearcoatNormalTexture", &clearcoat.normal_texture},
                 {"sheenColorTexture", &sheen.color_texture},
                 {"sheenRoughnessTexture", &sheen.roughness_texture},
                 {"transmissionTexture", &transmission.texture},
                 {"thicknessTexture", &volume.thickness_texture}}};
    }
    // Whether the material has any texture.
    bool uses_textures() const {
        for (const NamedTextureReference& named : texture_references()) {
            if (named.reference->present()) {
                return true;
            }
        }
        return false;
    }
    // Whether a texture of the material reads uv set `set` (TextureReference::texcoord).
    bool reads_uv_set(int set) const {
        for (const NamedTextureReference& named : texture_references()) {
            if (named.reference->present() && named.reference->texcoord == set) {
                return true;
            }
        }
        return false;
    }
};

struct Primitive {
    std::string name;                  // "mesh 'Box' primitive 0" etc., for messages
    std::vector<glm::vec3> positions;  // world space of the file
    std::vector<glm::vec3> normals;    // unit, one per position
    // Empty, or one per position; never empty when the material has a texture (a glTF
    // primitive without TEXCOORD_0 whose material has one gets (0, 0) everywhere).
    std::vector<glm::vec2> texcoords;
    // The second uv set (TEXCOORD_1): empty, or one per position; never empty when a material
    // the primitive may be drawn with has a texture on set 1 (zeros where the file has none).
    std::vector<glm::vec2> texcoords1;
    // Vertex colours (glTF COLOR_0, linear RGBA in [0, 1], RGB given alpha 1): empty, or one per
    // position; they multiply the material's base colour and alpha.
    std::vector<glm::vec4> colors;
    // Empty, or one per position: xyz the unit tangent (the direction of increasing u), w the
    // bitangent's sign (bitangent = w * cross(normal, tangent)), as glTF's TANGENT. Never empty
    // when the material has a normal texture: read from the file, or generated with MikkTSpace
    // (M. Mikkelsen, "Simulation of Wrinkled Surfaces Revisited", 2008) when it has none.
    std::vector<glm::vec4> tangents;
    std::vector<std::uint32_t> indices;  // triangle list, 3 per triangle, all < positions.size()
    int material = 0;                    // index into Mesh::materials
    // KHR_materials_variants: per variant of Mesh::variants, in order, the index into
    // Mesh::materials the primitive is drawn with under it (`material` where the file maps it
    // to none); empty when the mesh has no variants.
    std::vector<int> variant_materials;

    // The material drawn under `variant` (an index into Mesh::variants; none: the file's
    // default, `material`).
    int material_under(std::optional<std::uint32_t> variant) const {
        return variant ? variant_materials.at(*variant) : material;
    }
    // Every material the primitive may be drawn with, `material` first, each once.
    std::vector<int> materials_drawn() const;
};

struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
    glm::vec3 centre() const { return (min + max) * 0.5f; }
};

// What the loaders repaired rather than rejected, for the API to report.
struct MeshRepairs {
    // Normals present in the file but zero-length or non-finite, computed from the triangles
    // instead (angle-weighted, as for a file without normals).
    std::uint64_t normals_replaced = 0;
    // Normals present in the file whose length was not 1 (beyond 1e-3), normalised.
    std::uint64_t normals_renormalised = 0;
};

// glTF 2.0 camera projections (section 5.12).
enum class CameraProjection { Perspective, Orthographic };

// A camera the asset brings (glTF 2.0 section 3.10), placed by its node's world transform: the
// eye at the node's origin, looking down the node's -Z with the node's +Y up. The target lies
// on that view direction at the depth of the mesh's bounds' centre (max(1, |eye|) ahead when
// the centre is not in front of the camera), so that an orbit or zoom continuing from the view
// turns about the product. Only a perspective camera can be drawn: oer renders perspective
// alone; an orthographic one is listed so that the API can say so.
struct AssetCamera {
    std::string name;  // the glTF camera's name, else its node's, else "camera N"
    CameraProjection projection = CameraProjection::Perspective;
    // eye, target, up; fov_y (degrees, the file's yfov) for a perspective camera only.
    Camera camera;
    // Informative, as the file gives them: the aspect ratio (perspective; 0: none, the frame's)
    // and the clip planes (zfar 0: infinite). The renderer keeps its own planes.
    float aspect_ratio = 0.0f;
    float znear = 0.0f;
    float zfar = 0.0f;
};

struct Mesh {
    std::vector<Primitive> primitives;
    std::vector<Material> materials;  // at least one
    std::vector<Texture> textures;
    Bounds bounds;  // of every position
    std::uint64_t triangle_count = 0;
    std::uint64_t vertex_count = 0;
    MeshRepairs repairs;
    // KHR_materials_variants: the names of the product's variants (unique), in the file's
    // order; Primitive::variant_materials maps each to its materials.
    std::vector<std::string> variants;
    // The asset's own cameras, in the order the scene's node walk meets them (a camera used by
    // two nodes is two views); empty for an OBJ and the built-in product.
    std::vector<AssetCamera> cameras;
    // What was ignored (an OBJ's mtllib, a texture on a texCoord other than 0, ...), one line
    // each, for the API to pass on.
    std::vector<std::string> warnings;
};

}  // namespace oer
