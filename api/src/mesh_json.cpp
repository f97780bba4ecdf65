#include "oer/api/mesh_json.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "oer/core/enum_names.hpp"

namespace oer::api {

namespace {

constexpr EnumNames<MeshFormat, 3> kMeshFormatNames = {
    {{MeshFormat::Glb, "glb"}, {MeshFormat::Gltf, "gltf"}, {MeshFormat::Obj, "obj"}}};
constexpr EnumNames<ShadingModel, 3> kShadingModelNames = {
    {{ShadingModel::Lambertian, "lambertian"},
     {ShadingModel::MetallicRoughness, "metallic_roughness"},
     {ShadingModel::Unlit, "unlit"}}};
constexpr EnumNames<AlphaMode, 3> kAlphaModeNames = {
    {{AlphaMode::Opaque, "opaque"}, {AlphaMode::Mask, "mask"}, {AlphaMode::Blend, "blend"}}};
constexpr EnumNames<CameraProjection, 2> kProjectionNames = {
    {{CameraProjection::Perspective, "perspective"},
     {CameraProjection::Orthographic, "orthographic"}}};

// A float as the double with its shortest decimal text: 0.8f shows as 0.8, not as
// 0.800000011920929 (the double nearest the float).
double shortest(float value) {
    std::array<char, 32> buffer{};
    const auto written = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    double result = value;
    std::from_chars(buffer.data(), written.ptr, result);
    return result;
}

template <typename Vector>
nlohmann::json floats_json(const Vector& v) {
    nlohmann::json list = nlohmann::json::array();
    for (int i = 0; i < Vector::length(); ++i) {
        list.push_back(shortest(v[i]));
    }
    return list;
}

// The product's variants as a configurator shows them: each variant's name, the materials it
// draws, and the base colour of its swatch: the material it draws on the most triangles among
// those it changes (on the most triangles overall when it changes none).
nlohmann::json variants_json(const Mesh& mesh) {
    nlohmann::json variants = nlohmann::json::array();
    for (std::size_t v = 0; v < mesh.variants.size(); ++v) {
        std::set<int> drawn;
        std::map<int, std::size_t> changed_triangles, all_triangles;
        for (const Primitive& primitive : mesh.primitives) {
            const int material = primitive.material_under(std::uint32_t(v));
            drawn.insert(material);
            all_triangles[material] += primitive.indices.size() / 3;
            if (material != primitive.material) {
                changed_triangles[material] += primitive.indices.size() / 3;
            }
        }
        const auto& counted = changed_triangles.empty() ? all_triangles : changed_triangles;
        const auto swatch =
            std::max_element(counted.begin(), counted.end(),
                             [](const auto& a, const auto& b) { return a.second < b.second; });
        nlohmann::json entry = {{"name", mesh.variants[v]},
                                {"materials", std::vector<int>(drawn.begin(), drawn.end())}};
        if (swatch != counted.end()) {
            const Material& material = mesh.materials.at(std::size_t(swatch->first));
            entry["swatch"] = {{"material", swatch->first},
                               {"base_color", floats_json(material.base_color)},
                               {"has_texture", material.base_color_texture.present()}};
        }
        variants.push_back(std::move(entry));
    }
    return variants;
}

nlohmann::json cameras_json(const std::vector<AssetCamera>& cameras) {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < cameras.size(); ++i) {
        const AssetCamera& camera = cameras[i];
        nlohmann::json entry = {{"index", i},
                                {"name", camera.name},
                                {"type", name_of(camera.projection, kProjectionNames)},
                                {"eye", floats_json(camera.camera.eye)},
                                {"target", floats_json(camera.camera.target)},
                                {"up", floats_json(camera.camera.up)},
                                {"znear", shortest(camera.znear)}};
        if (camera.projection == CameraProjection::Perspective) {
            entry["fov_y"] = shortest(camera.camera.fov_y);
        }
        if (camera.aspect_ratio > 0.0f) {
            entry["aspect_ratio"] = shortest(camera.aspect_ratio);
        }
        if (camera.zfar > 0.0f) {
            entry["zfar"] = shortest(camera.zfar);
        }
        list.push_back(std::move(entry));
    }
    return list;
}

}  // namespace

std::string to_string(MeshFormat format) {
    return name_of(format, kMeshFormatNames);
}

MeshFormat mesh_format_from_string(const std::string& name) {
    return value_named(name, kMeshFormatNames, "mesh format");
}

nlohmann::json mesh_to_json(const Mesh& mesh, const std::string& id,
                            std::optional<MeshFormat> format) {
    nlohmann::json materials = nlohmann::json::array();
    for (const Material& material : mesh.materials) {
        nlohmann::json entry = {
            {"name", material.name},
            {"model", name_of(material.model, kShadingModelNames)},
            {"base_color", floats_json(material.base_color)},
            {"has_texture", material.base_color_texture.present()},
            {"metallic", shortest(material.metallic)},
            {"roughness", shortest(material.roughness)},
            {"emissive", floats_json(material.emissive * material.emissive_strength)},
            {"alpha_mode", name_of(material.alpha_mode, kAlphaModeNames)},
            {"double_sided", material.double_sided},
            {"textures",
             {{"base_color", material.base_color_texture.present()},
              {"metallic_roughness", material.metallic_roughness_texture.present()},
              {"normal", material.normal_texture.present()},
              {"occlusion", material.occlusion_texture.present()},
              {"emissive", material.emissive_texture.present()}}},
            {"specular", material.glossy()}};
        if (material.alpha_mode == AlphaMode::Mask) {
            entry["alpha_cutoff"] = shortest(material.alpha_cutoff);
        }
        materials.push_back(std::move(entry));
    }
    nlohmann::json json = {
        {"id", id},
        {"counts",
         {{"triangles", mesh.triangle_count},
          {"vertices", mesh.vertex_count},
          {"primitives", mesh.primitives.size()},
          {"materials", mesh.materials.size()},
          {"textures", mesh.textures.size()}}},
        {"bounds", {{"min", floats_json(mesh.bounds.min)}, {"max", floats_json(mesh.bounds.max)}}},
        {"materials", std::move(materials)},
        {"variants", variants_json(mesh)},
        {"cameras", cameras_json(mesh.cameras)},
        {"repairs",
         {{"normals_replaced", mesh.repairs.normals_replaced},
          {"normals_renormalised", mesh.repairs.normals_renormalised}}},
        {"warnings", mesh.warnings}};
    if (format) {
        json["format"] = to_string(*format);
    }
    return json;
}

}  // namespace oer::api
