// The JSON types of the glTF properties we use (see gltf_schema.hpp), after the glTF 2.0
// JSON schema. Properties the loader ignores are not checked, except names and extensions,
// which are cheap to check everywhere.
#include "gltf_schema.hpp"

#include <initializer_list>
#include <string_view>

#include "mesh_errors.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/error.hpp"
#include "oer/core/one_line.hpp"

namespace oer::mesh_detail {

namespace {

using checked_json::Json;

// The JSON a glTF may hold, checked while it is parsed, before tinygltf parses it again (into
// its own DOM, and extras into tinygltf::Value, some 300 bytes a member). The samples of
// assimp-testmodels hold at most 3865 values (2CylinderEngine) and nest 9 levels
// (TextureTransformTest); glmark2's models converted by assimp, fewer: a glTF's arrays of
// numbers (vertices, indices) are in its buffers, not its JSON. 2^17 values leave room for
// scenes of several thousand nodes and meshes (about 20 values each), and the costliest
// document within them (65000 one-member objects in extras) loads with under 64 MiB of
// resident growth (tests/mesh/hostile_meshes_test.cpp; 2^18 took 73 MiB). Nesting as before:
// glTF's schema nests under 10 levels, extras and extensions may nest more; tinygltf recurses
// into them.
constexpr checked_json::JsonBounds kGltfJsonBounds{std::size_t(1) << 17, 128};

// The glTF loader's wording: "invalid glTF: <path> must be <kind>, not <what it is>".
struct GltfWording {
    const std::string& asset;

    [[noreturn]] void fail(const std::string& path, const std::string& message) const {
        mesh_detail::fail(ErrorKind::InvalidInput, asset, "invalid glTF: " + path + " " + message);
    }
    std::string wrong_type(const std::string& expected, const Json& value) const {
        return "must be " + expected + ", not " +
               (value.is_number() || value.is_boolean()
                    ? detail::one_line(value.dump(), 40)
                    : std::string(checked_json::kind_of(value)));
    }
    std::string missing() const { return "is required"; }
};

class SchemaChecker {
  public:
    explicit SchemaChecker(const std::string& asset)
        : read_(GltfWording{asset}, checked_json::PathStyle::Dotted) {}

    void check(const Json& root) {
        read_.object(root, "the glTF");
        check_common(root, "");
        optional_index(root, "scene", "");
        each(root, "scenes", [&](const Json& scene, const std::string& path) {
            index_array(scene, "nodes", path);
        });
        each(root, "nodes", [&](const Json& node, const std::string& path) {
            index_array(node, "children", path);
            optional_index(node, "mesh", path);
            number_array(node, "matrix", path, 16);
            number_array(node, "translation", path, 3);
            number_array(node, "rotation", path, 4);
            number_array(node, "scale", path, 3);
        });
        each(root, "meshes", [&](const Json& mesh, const std::string& path) {
            const std::string primitives_path = read_.child(path, "primitives");
            const Json* primitives = checked_json::find(mesh, "primitives");
            if (primitives == nullptr) {
                read_.fail(primitives_path, "must be a non-empty array");
            }
            read_.expect(*primitives, primitives->is_array() && !primitives->empty(),
                         primitives_path, "a non-empty array");
            for (std::size_t p = 0; p < primitives->size(); ++p) {
                const Json& primitive = (*primitives)[p];
                const std::string at = read_.child(primitives_path, p);
                read_.object(primitive, at);
                check_common(primitive, at);
                const std::string attributes_path = read_.child(at, "attributes");
                const Json* attributes = checked_json::find(primitive, "attributes");
                if (attributes == nullptr) {
                    read_.fail(attributes_path, "must be an object");
                }
                for (const auto& [name, value] :
                     read_.object(*attributes, attributes_path).items()) {
                    read_.index(value, read_.child(attributes_path, name));
                }
                optional_index(primitive, "indices", at);
                optional_index(primitive, "material", at);
                optional_index(primitive, "mode", at);
            }
        });
        each(root, "materials", [&](const Json& material, const std::string& path) {
            if (const auto pbr = optional_object(material, "pbrMetallicRoughness", path)) {
                const std::string at = path + ".pbrMetallicRoughness";
                number_array(*pbr, "baseColorFactor", at, 4);
                optional_number(*pbr, "metallicFactor", at);
                optional_number(*pbr, "roughnessFactor", at);
                texture_info(*pbr, "baseColorTexture", at);
                texture_info(*pbr, "metallicRoughnessTexture", at);
            }
            texture_info(material, "normalTexture", path);
            texture_info(material, "occlusionTexture", path);
            texture_info(material, "emissiveTexture", path);
            number_array(material, "emissiveFactor", path, 3);
            optional_string(material, "alphaMode", path);
            optional_number(material, "alphaCutoff", path);
            optional_boolean(material, "doubleSided", path);
            if (const Json* strength = extension(material, "KHR_materials_emissive_strength")) {
                optional_number(*strength, "emissiveStrength",
                                path + ".extensions.KHR_materials_emissive_strength");
            }
            check_material_layers(material, path);
        });
        each(root, "textures", [&](const Json& texture, const std::string& path) {
            optional_index(texture, "source", path);
            optional_index(texture, "sampler", path);
        });
        each(root, "images", [&](const Json& image, const std::string& path) {
            optional_string(image, "uri", path);
            optional_string(image, "mimeType", path);
            optional_index(image, "bufferView", path);
        });
        each(root, "accessors", [&](const Json& accessor, const std::string& path) {
            optional_index(accessor, "bufferView", path);
            optional_index(accessor, "byteOffset", path);
            optional_index(accessor, "componentType", path);
            optional_index(accessor, "count", path);
            optional_string(accessor, "type", path);
            if (const Json* sparse = optional_object(accessor, "sparse", path)) {
                const std::string at = path + ".sparse";
                read_.index(read_.member(*sparse, at, "count"), at + ".count");
                for (const char* part : {"indices", "values"}) {
                    const std::string part_path = at + "." + part;
                    const Json& object = read_.member(*sparse, at, part);
                    read_.index(read_.member(object, part_path, "bufferView"),
                                part_path + ".bufferView");
                    optional_index(object, "byteOffset", part_path);
                    optional_index(object, "componentType", part_path);
                }
            }
            optional_boolean(accessor, "normalized", path);
        });
        each(root, "bufferViews", [&](const Json& view, const std::string& path) {
            optional_index(view, "buffer", path);
            optional_index(view, "byteOffset", path);
            optional_index(view, "byteLength", path);
            optional_index(view, "byteStride", path);
        });
        each(root, "buffers", [&](const Json& buffer, const std::string& path) {
            optional_index(buffer, "byteLength", path);
            optional_string(buffer, "uri", path);
        });
        each(root, "samplers", [&](const Json& sampler, const std::string& path) {
            for (const char* key : {"magFilter", "minFilter", "wrapS", "wrapT"}) {
                optional_index(sampler, key, path);
            }
        });
        // Names of everything else too.
        for (const char* section : {"animations", "cameras", "skins"}) {
            each(root, section, [](const Json&, const std::string&) {});
        }
    }

  private:
    // The numbers and textureInfos of the material extensions the loader reads
    // (gltf_materials.hpp), by each extension's JSON schema.
    void check_material_layers(const Json& material, const std::string& path) const {
        struct Layer {
            const char* name;
            std::initializer_list<const char*> numbers;
            std::initializer_list<const char*> colors;  // arrays of 3 numbers
            std::initializer_list<const char*> textures;
        };
        for (const Layer& layer : std::initializer_list<Layer>{
                 {"KHR_materials_ior", {"ior"}, {}, {}},
                 {"KHR_materials_specular",
                  {"specularFactor"},
                  {"specularColorFactor"},
                  {"specularTexture", "specularColorTexture"}},
                 {"KHR_materials_clearcoat",
                  {"clearcoatFactor", "clearcoatRoughnessFactor"},
                  {},
                  {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"}},
                 {"KHR_materials_sheen",
                  {"sheenRoughnessFactor"},
                  {"sheenColorFactor"},
                  {"sheenColorTexture", "sheenRoughnessTexture"}},
                 {"KHR_materials_transmission",
                  {"transmissionFactor"},
                  {},
                  {"transmissionTexture"}},
                 {"KHR_materials_volume",
                  {"thicknessFactor", "attenuationDistance"},
                  {"attenuationColor"},
                  {"thicknessTexture"}}}) {
            const Json* object = extension(material, layer.name);
            if (object == nullptr) {
                continue;
            }
            const std::string at = path + ".extensions." + layer.name;
            for (const char* key : layer.numbers) {
                optional_number(*object, key, at);
            }
            for (const char* key : layer.colors) {
                number_array(*object, key, at, 3);
            }
            for (const char* key : layer.textures) {
                texture_info(*object, key, at);
            }
        }
    }

    // "name" a string, "extensions" an object of objects.
    void check_common(const Json& object, const std::string& path) const {
        optional_string(object, "name", path);
        if (const Json* extensions = checked_json::find(object, "extensions")) {
            const std::string at = read_.child(path, "extensions");
            for (const auto& [name, value] : read_.object(*extensions, at).items()) {
                read_.object(value, read_.child(at, name));
            }
        }
    }

    template <typename Visit>
    void each(const Json& root, const char* section, Visit visit) const {
        const Json* items = checked_json::find(root, section);
        if (items == nullptr) {
            return;
        }
        read_.array(*items, section);
        for (std::size_t i = 0; i < items->size(); ++i) {
            const std::string path = read_.child(section, i);
            const Json& item = (*items)[i];
            read_.object(item, path);
            check_common(item, path);
            visit(item, path);
        }
    }

    void optional_index(const Json& object, const char* key, const std::string& path) const {
        if (const Json* value = checked_json::find(object, key)) {
            read_.index(*value, read_.child(path, key));
        }
    }

    void optional_number(const Json& object, const char* key, const std::string& path) const {
        if (const Json* value = checked_json::find(object, key)) {
            read_.number(*value, read_.child(path, key));
        }
    }

    void optional_boolean(const Json& object, const char* key, const std::string& path) const {
        if (const Json* value = checked_json::find(object, key)) {
            read_.boolean(*value, read_.child(path, key));
        }
    }

    // The object of one extension (check_common has checked that it is an object), or null.
    static const Json* extension(const Json& object, const char* name) {
        const Json* extensions = checked_json::find(object, "extensions");
        return extensions == nullptr ? nullptr : checked_json::find(*extensions, name);
    }

    void optional_string(const Json& object, const char* key, const std::string& path) const {
        if (const Json* value = checked_json::find(object, key)) {
            read_.string(*value, read_.child(path, key));
        }
    }

    const Json* optional_object(const Json& object, const char* key,
                                const std::string& path) const {
        const Json* value = checked_json::find(object, key);
        if (value == nullptr) {
            return nullptr;
        }
        read_.object(*value, read_.child(path, key));
        check_common(*value, read_.child(path, key));
        return value;
    }

    void index_array(const Json& object, const char* key, const std::string& path) const {
        const Json* value = checked_json::find(object, key);
        if (value == nullptr) {
            return;
        }
        const std::string at = read_.child(path, key);
        read_.array(*value, at);
        for (std::size_t i = 0; i < value->size(); ++i) {
            read_.index((*value)[i], read_.child(at, i));
        }
    }

    void number_array(const Json& object, const char* key, const std::string& path,
                      std::size_t size) const {
        const Json* value = checked_json::find(object, key);
        if (value == nullptr) {
            return;
        }
        const std::string at = read_.child(path, key);
        const std::string expected = "an array of " + std::to_string(size) + " numbers";
        read_.expect(*value, value->is_array(), at, expected);
        if (value->size() != size) {
            read_.fail(at, "must be " + expected);
        }
        for (std::size_t i = 0; i < size; ++i) {
            read_.number((*value)[i], read_.child(at, i));
        }
    }

    // A textureInfo: an object with a non-negative integer "index" (required) and "texCoord",
    // and KHR_texture_transform's offset and scale (2 numbers), rotation and texCoord.
    const Json* texture_info(const Json& object, const char* key, const std::string& path) const {
        const Json* info = optional_object(object, key, path);
        if (info == nullptr) {
            return nullptr;
        }
        const std::string at = read_.child(path, key);
        optional_number(*info, "scale", at);     // normalTexture
        optional_number(*info, "strength", at);  // occlusionTexture
        read_.index(read_.member(*info, at, "index"), read_.child(at, "index"));
        optional_index(*info, "texCoord", at);
        if (const Json* transform = extension(*info, "KHR_texture_transform")) {
            const std::string transform_path = at + ".extensions.KHR_texture_transform";
            number_array(*transform, "offset", transform_path, 2);
            optional_number(*transform, "rotation", transform_path);
            number_array(*transform, "scale", transform_path, 2);
            optional_index(*transform, "texCoord", transform_path);
        }
        return info;
    }

    checked_json::Reader<GltfWording> read_;
};

}  // namespace

Json check_gltf_schema(std::span<const std::byte> text, const std::string& asset) {
    Json root;
    try {
        root = checked_json::parse_bounded(
            std::string_view(reinterpret_cast<const char*>(text.data()), text.size()),
            kGltfJsonBounds);
    } catch (const checked_json::JsonParseError& error) {
        switch (error.cause()) {
            case checked_json::JsonParseError::Cause::Syntax:
                fail(ErrorKind::InvalidInput, asset,
                     std::string("not valid JSON: ") + error.what());
            case checked_json::JsonParseError::Cause::TooDeep:
                fail(ErrorKind::InvalidInput, asset, error.what());
            case checked_json::JsonParseError::Cause::TooMany:
                fail(ErrorKind::LimitExceeded, asset,
                     std::string(error.what()) + ", over the limit for a glTF's JSON");
        }
    }
    SchemaChecker(asset).check(root);
    return root;
}

}  // namespace oer::mesh_detail
