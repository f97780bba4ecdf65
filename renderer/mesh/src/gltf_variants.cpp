// KHR_materials_variants (see gltf_variants.hpp). Specification:
// https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Khronos/KHR_materials_variants
#include "gltf_variants.hpp"

#include <set>

#include "gltf_values.hpp"
#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

constexpr const char* kExtension = "KHR_materials_variants";

// An array member `key` of `object` (named `what`), required.
const tinygltf::Value& array_member(const std::string& asset, const tinygltf::Value& object,
                                    const char* key, const std::string& what) {
    if (!object.IsObject() || !object.Has(key) || !object.Get(key).IsArray()) {
        fail(ErrorKind::InvalidInput, asset, what + "." + key + " must be an array");
    }
    return object.Get(key);
}

}  // namespace

std::vector<std::string> read_variants(const tinygltf::Model& model, const std::string& asset) {
    const auto extension = model.extensions.find(kExtension);
    if (extension == model.extensions.end()) {
        return {};
    }
    const std::string what = kExtension;
    const tinygltf::Value& list = array_member(asset, extension->second, "variants", what);
    if (list.ArrayLen() > kMaxVariants) {
        fail(ErrorKind::LimitExceeded, asset,
             what + " declares " + std::to_string(list.ArrayLen()) +
                 " variants, more than the limit of " + std::to_string(kMaxVariants));
    }
    std::vector<std::string> names;
    std::set<std::string> seen;
    for (std::size_t i = 0; i < list.ArrayLen(); ++i) {
        const std::string variant = what + ".variants[" + std::to_string(i) + "]";
        const tinygltf::Value& entry = list.Get(int(i));
        if (!entry.IsObject() || !entry.Has("name") || !entry.Get("name").IsString()) {
            fail(ErrorKind::InvalidInput, asset, variant + ".name must be a string");
        }
        std::string name = entry.Get("name").Get<std::string>();
        if (name.empty()) {
            fail(ErrorKind::InvalidInput, asset, variant + ".name is empty");
        }
        if (!seen.insert(name).second) {
            fail(ErrorKind::InvalidInput, asset,
                 variant + ".name '" + one_line(name, 80) +
                     "' names an earlier variant too (a request chooses a variant by its name)");
        }
        names.push_back(std::move(name));
    }
    return names;
}

std::vector<int> variant_material_indices(const tinygltf::Primitive& source,
                                          std::size_t variant_count, std::size_t material_count,
                                          const std::string& asset, const std::string& primitive) {
    const auto extension = source.extensions.find(kExtension);
    if (extension == source.extensions.end()) {
        return variant_count == 0 ? std::vector<int>{}
                                  : std::vector<int>(variant_count, kUnmappedVariant);
    }
    const std::string what = primitive + ": " + kExtension;
    if (variant_count == 0) {
        fail(ErrorKind::InvalidInput, asset,
             what + " maps variants, but the asset declares none (the root's " + kExtension +
                 ".variants)");
    }
    std::vector<int> indices(variant_count, kUnmappedVariant);
    const tinygltf::Value& mappings = array_member(asset, extension->second, "mappings", what);
    for (std::size_t m = 0; m < mappings.ArrayLen(); ++m) {
        const std::string mapping = what + ".mappings[" + std::to_string(m) + "]";
        const tinygltf::Value& entry = mappings.Get(int(m));
        const std::uint64_t material = integer_member(asset, entry, "material", mapping);
        if (material >= material_count) {
            fail(ErrorKind::InvalidInput, asset,
                 mapping + ".material " + std::to_string(material) + " does not exist (" +
                     std::to_string(material_count) + " materials)");
        }
        const tinygltf::Value& variants = array_member(asset, entry, "variants", mapping);
        for (std::size_t v = 0; v < variants.ArrayLen(); ++v) {
            const tinygltf::Value& index = variants.Get(int(v));
            const double number = index.IsNumber() ? index.GetNumberAsDouble() : -1.0;
            if (!(number >= 0.0 && number < double(variant_count)) ||
                double(std::size_t(number)) != number) {
                fail(ErrorKind::InvalidInput, asset,
                     mapping + ".variants[" + std::to_string(v) +
                         "] is not the index of a declared variant (0 to " +
                         std::to_string(variant_count - 1) + ")");
            }
            int& mapped = indices[std::size_t(number)];
            if (mapped != kUnmappedVariant) {
                fail(ErrorKind::InvalidInput, asset,
                     mapping + " maps variant " + std::to_string(std::size_t(number)) +
                         ", which an earlier mapping of the primitive maps already");
            }
            mapped = int(material);
        }
    }
    return indices;
}

}  // namespace oer::mesh_detail
