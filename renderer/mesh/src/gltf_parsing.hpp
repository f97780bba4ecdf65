#pragma once
// Private to the glTF loader: tinygltf run on bytes, and on files only inside one folder. Its
// file-system callbacks refuse (and remember) every URI that is not a data: URI, so that
// nothing is ever read from disk, unless the context names a folder: then a file whose
// canonical path (symbolic links followed) lies inside that folder's is read, up to the
// limit on bytes, and every other one is refused;
// its image callback checks each image's bufferView and header against the limits and keeps
// the encoded bytes, so that only the images the materials use are decoded, later. The JSON is
// checked first: a .glb's container, then its values and nesting as it is parsed, and the
// schema (gltf_schema.hpp).
#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::mesh_detail {

// What parsing leaves beside the model.
struct ParseContext {
    std::string asset;
    const MeshLimits* limits = nullptr;
    const tinygltf::Model* model = nullptr;  // as tinygltf fills it
    // Canonical; when set, files inside it may be read (a local .gltf's buffers and images).
    std::optional<std::filesystem::path> folder;
    std::vector<std::string> refused_uris;
    std::uint64_t file_bytes_read = 0;          // by every file read, against limits->max_bytes
    std::optional<std::string> oversized_file;  // the URI that would have passed that limit
    std::optional<Error> image_error;
    std::map<int, std::vector<std::byte>> encoded_images;  // image index -> its encoded bytes
    std::string warnings;                                  // tinygltf's
};

// The model, or an oer::Error: invalid JSON or glTF, an external file (named), an image over
// the limits, a glTF version other than 2, a required extension we do not support.
tinygltf::Model parse_gltf(std::span<const std::byte> bytes, const std::string& asset, bool binary,
                           const MeshLimits& limits, ParseContext& context);

// Whether the loader implements the extension (KHR_texture_transform,
// KHR_materials_emissive_strength, EXT_texture_webp, EXT_texture_avif): one it does not is refused
// when the asset requires it and ignored with a warning when the asset only uses it (glTF 2.0,
// section 3.12).
bool supported_extension(const std::string& name);
// What a user can do about an asset that requires `extension`, which oer does not support.
std::string what_to_do_without(const std::string& extension);

// "asset: image 3 'name'", for messages.
std::string image_label(const std::string& asset, int index, const std::string& name);

}  // namespace oer::mesh_detail
