// The JSON types of the glTF properties we use (see gltf_schema.hpp), after the glTF 2.0
// JSON schema. Properties the loader ignores are not checked, except names and extensions,
// which are cheap to check everywhere.
#include "gltf_schema.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <initializer_list>

#include "mesh_errors.hpp"
#include "oer/core/error.hpp"

namespace oer::mesh_detail {

namespace {

using nlohmann::json;

const char* kind_of(const json& value) {
    switch (value.type()) {
        case json::value_t::null:
            return "null";
        case json::value_t::object:
            return "an object";
        case json::value_t::array:
            return "an array";
        case json::value_t::string:
            return "a string";
        case json::value_t::boolean:
            return "a boolean";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned:
        case json::value_t::number_float:
            return "a number";
        default:
            return "another kind of value";
    }
}

class SchemaChecker {
  public:
    explicit SchemaChecker(const std::string& asset) : asset_(asset) {}

    void check(const json& root) {
        expect_object(root, "the glTF");
        check_common(root, "");
        optional_index(root, "scene", "");
        each(root, "scenes", [&](const json& scene, const std::string& path) {
            index_array(scene, "nodes", path);
        });
        each(root, "nodes", [&](const json& node, const std::string& path) {
            index_array(node, "children", path);
            optional_index(node, "mesh", path);
            number_array(node, "matrix", path, 16);
            number_array(node, "translation", path, 3);
            number_array(node, "rotation", path, 4);
            number_array(node, "scale", path, 3);
        });
        each(root, "meshes", [&](const json& mesh, const std::string& path) {
            const auto primitives = mesh.find("primitives");
            if (primitives == mesh.end() || !primitives->is_array() || primitives->empty()) {
                fail_at(path + ".primitives", "must be a non-empty array",
                        primitives == mesh.end() ? nullptr : &*primitives);
            }
            for (std::size_t p = 0; p < primitives->size(); ++p) {
                const json& primitive = (*primitives)[p];
                const std::string at = path + ".primitives[" + std::to_string(p) + "]";
                expect_object(primitive, at);
                check_common(primitive, at);
                const auto attributes = primitive.find("attributes");
                if (attributes == primitive.end() || !attributes->is_object()) {
                    fail_at(at + ".attributes", "must be an object",
                            attributes == primitive.end() ? nullptr : &*attributes);
                }
                for (const auto& [name, value] : attributes->items()) {
                    if (!is_index(value)) {
                        fail_at(at + ".attributes." + name, "must be a non-negative integer",
                                &value);
                    }
                }
                optional_index(primitive, "indices", at);
                optional_index(primitive, "material", at);
                optional_index(primitive, "mode", at);
            }
        });
        each(root, "materials", [&](const json& material, const std::string& path) {
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
        });
        each(root, "textures", [&](const json& texture, const std::string& path) {
            optional_index(texture, "source", path);
            optional_index(texture, "sampler", path);
        });
        each(root, "images", [&](const json& image, const std::string& path) {
            optional_string(image, "uri", path);
            optional_string(image, "mimeType", path);
            optional_index(image, "bufferView", path);
        });
        each(root, "accessors", [&](const json& accessor, const std::string& path) {
            optional_index(accessor, "bufferView", path);
            optional_index(accessor, "byteOffset", path);
            optional_index(accessor, "componentType", path);
            optional_index(accessor, "count", path);
            optional_string(accessor, "type", path);
            optional_object(accessor, "sparse", path);
            if (const auto normalized = accessor.find("normalized");
                normalized != accessor.end() && !normalized->is_boolean()) {
                fail_at(path + ".normalized", "must be a boolean", &*normalized);
            }
        });
        each(root, "bufferViews", [&](const json& view, const std::string& path) {
            optional_index(view, "buffer", path);
            optional_index(view, "byteOffset", path);
            optional_index(view, "byteLength", path);
            optional_index(view, "byteStride", path);
        });
        each(root, "buffers", [&](const json& buffer, const std::string& path) {
            optional_index(buffer, "byteLength", path);
            optional_string(buffer, "uri", path);
        });
        // Names of everything else too.
        for (const char* section : {"animations", "cameras", "samplers", "skins"}) {
            each(root, section, [](const json&, const std::string&) {});
        }
    }

  private:
    [[noreturn]] void fail_at(const std::string& path, const std::string& rule,
                              const json* value) const {
        std::string message = "invalid glTF: " + path + " " + rule;
        if (value != nullptr) {
            message += ", not ";
            message += value->is_number() || value->is_boolean() ? one_line(value->dump(), 40)
                                                                 : std::string(kind_of(*value));
        }
        fail(ErrorKind::InvalidInput, asset_, message);
    }

    static bool is_index(const json& value) {
        if (value.is_number_unsigned()) {
            return true;
        }
        if (value.is_number_integer()) {
            return value.get<std::int64_t>() >= 0;
        }
        if (value.is_number_float()) {
            const double v = value.get<double>();
            return v >= 0.0 && v == std::floor(v) && v < 9.007199254740992e15;
        }
        return false;
    }

    void expect_object(const json& value, const std::string& path) const {
        if (!value.is_object()) {
            fail_at(path, "must be an object", &value);
        }
    }

    // "name" a string, "extensions" an object of objects.
    void check_common(const json& object, const std::string& path) const {
        const std::string prefix = path.empty() ? "" : path + ".";
        if (const auto name = object.find("name"); name != object.end() && !name->is_string()) {
            fail_at(prefix + "name", "must be a string", &*name);
        }
        if (const auto extensions = object.find("extensions"); extensions != object.end()) {
            if (!extensions->is_object()) {
                fail_at(prefix + "extensions", "must be an object", &*extensions);
            }
            for (const auto& [name, value] : extensions->items()) {
                if (!value.is_object()) {
                    fail_at(prefix + "extensions." + name, "must be an object", &value);
                }
            }
        }
    }

    template <typename Visit>
    void each(const json& root, const char* section, Visit visit) const {
        const auto items = root.find(section);
        if (items == root.end()) {
            return;
        }
        if (!items->is_array()) {
            fail_at(section, "must be an array", &*items);
        }
        for (std::size_t i = 0; i < items->size(); ++i) {
            const std::string path = std::string(section) + "[" + std::to_string(i) + "]";
            const json& item = (*items)[i];
            expect_object(item, path);
            check_common(item, path);
            visit(item, path);
        }
    }

    void optional_index(const json& object, const char* key, const std::string& path) const {
        const auto value = object.find(key);
        if (value != object.end() && !is_index(*value)) {
            fail_at(join(path, key), "must be a non-negative integer", &*value);
        }
    }

    void optional_number(const json& object, const char* key, const std::string& path) const {
        const auto value = object.find(key);
        if (value != object.end() && !value->is_number()) {
            fail_at(join(path, key), "must be a number", &*value);
        }
    }

    void optional_string(const json& object, const char* key, const std::string& path) const {
        const auto value = object.find(key);
        if (value != object.end() && !value->is_string()) {
            fail_at(join(path, key), "must be a string", &*value);
        }
    }

    const json* optional_object(const json& object, const char* key,
                                const std::string& path) const {
        const auto value = object.find(key);
        if (value == object.end()) {
            return nullptr;
        }
        expect_object(*value, join(path, key));
        check_common(*value, join(path, key));
        return &*value;
    }

    void index_array(const json& object, const char* key, const std::string& path) const {
        const auto value = object.find(key);
        if (value == object.end()) {
            return;
        }
        if (!value->is_array()) {
            fail_at(join(path, key), "must be an array", &*value);
        }
        for (std::size_t i = 0; i < value->size(); ++i) {
            if (!is_index((*value)[i])) {
                fail_at(join(path, key) + "[" + std::to_string(i) + "]",
                        "must be a non-negative integer", &(*value)[i]);
            }
        }
    }

    void number_array(const json& object, const char* key, const std::string& path,
                      std::size_t size) const {
        const auto value = object.find(key);
        if (value == object.end()) {
            return;
        }
        if (!value->is_array() || value->size() != size) {
            fail_at(join(path, key), "must be an array of " + std::to_string(size) + " numbers",
                    value->is_array() ? nullptr : &*value);
        }
        for (std::size_t i = 0; i < size; ++i) {
            if (!(*value)[i].is_number()) {
                fail_at(join(path, key) + "[" + std::to_string(i) + "]", "must be a number",
                        &(*value)[i]);
            }
        }
    }

    // A textureInfo: an object with a non-negative integer "index" (required) and "texCoord".
    const json* texture_info(const json& object, const char* key, const std::string& path) const {
        const json* info = optional_object(object, key, path);
        if (info == nullptr) {
            return nullptr;
        }
        const std::string at = join(path, key);
        optional_number(*info, "scale", at);     // normalTexture
        optional_number(*info, "strength", at);  // occlusionTexture
        const auto index = info->find("index");
        if (index == info->end()) {
            fail_at(at + ".index", "is required", nullptr);
        }
        optional_index(*info, "index", at);
        optional_index(*info, "texCoord", at);
        return info;
    }

    static std::string join(const std::string& path, const char* key) {
        return path.empty() ? std::string(key) : path + "." + key;
    }

    const std::string& asset_;
};

}  // namespace

void check_gltf_schema(std::span<const std::byte> text, const std::string& asset) {
    json root;
    try {
        const auto* begin = reinterpret_cast<const char*>(text.data());
        root = json::parse(begin, begin + text.size());
    } catch (const json::exception& error) {
        fail(ErrorKind::InvalidInput, asset, std::string("not valid JSON: ") + error.what());
    }
    SchemaChecker(asset).check(root);
}

}  // namespace oer::mesh_detail
