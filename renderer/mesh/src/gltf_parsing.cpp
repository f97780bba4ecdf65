// tinygltf run on bytes only (see gltf_parsing.hpp).
#include "gltf_parsing.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gltf_schema.hpp"
#include "mesh_errors.hpp"
#include "oer/core/checked_json.hpp"
#include "texture_decoding.hpp"

namespace oer::mesh_detail {

namespace {

void refuse(const std::string& path, void* user) {
    auto& context = *static_cast<ParseContext*>(user);
    if (std::find(context.refused_uris.begin(), context.refused_uris.end(), path) ==
        context.refused_uris.end()) {
        context.refused_uris.push_back(path);
    }
}

// The file's canonical path when it lies inside the context's folder, or nothing: no folder,
// a scheme or an absolute path, a path that leaves the folder (by "..", or by a symbolic link
// whose target is outside it), or no such file.
std::optional<std::filesystem::path> confined(const std::string& path,
                                              const ParseContext& context) {
    if (!context.folder || path.empty() || path.rfind("data:", 0) == 0 ||
        path.find("://") != std::string::npos) {
        return std::nullopt;
    }
    std::error_code error;
    const std::filesystem::path file = std::filesystem::canonical(path, error);
    if (error || !std::filesystem::is_regular_file(file, error)) {
        return std::nullopt;
    }
    const auto [end, rest] =
        std::mismatch(context.folder->begin(), context.folder->end(), file.begin(), file.end());
    if (end != context.folder->end()) {
        return std::nullopt;
    }
    return file;
}

bool file_exists(const std::string& path, void* user) {
    auto& context = *static_cast<ParseContext*>(user);
    if (confined(path, context)) {
        return true;
    }
    refuse(path, user);
    return false;
}

std::string keep_path(const std::string& path, void*) {
    return path;
}

bool read_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
               void* user) {
    auto& context = *static_cast<ParseContext*>(user);
    const std::optional<std::filesystem::path> file = confined(path, context);
    if (!file) {
        refuse(path, user);
        if (err != nullptr) {
            *err += "reading files is not allowed\n";
        }
        return false;
    }
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(*file, error);
    if (error || size > context.limits->max_bytes - context.file_bytes_read) {
        context.oversized_file = path;
        if (err != nullptr) {
            *err += "the file is over the limit\n";
        }
        return false;
    }
    std::ifstream stream(*file, std::ios::binary);
    out->resize(std::size_t(size));
    stream.read(reinterpret_cast<char*>(out->data()), std::streamsize(size));
    if (!stream || stream.gcount() != std::streamsize(size)) {
        if (err != nullptr) {
            *err += "the file could not be read whole\n";
        }
        return false;
    }
    context.file_bytes_read += size;
    return true;
}

bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err != nullptr) {
        *err += "writing files is not allowed\n";
    }
    return false;
}

// tinygltf hands an image in a bufferView over without checking the view against its buffer:
// check that first, then the header against the limit; keep the encoded bytes.
bool keep_encoded_image(tinygltf::Image* image, const int index, std::string* err, std::string*,
                        int, int, const unsigned char* bytes, int size, void* user) {
    auto& context = *static_cast<ParseContext*>(user);
    const std::string label = image_label(context.asset, index, image->name);
    try {
        if (image->bufferView >= 0) {
            const auto& views = context.model->bufferViews;
            const auto& buffers = context.model->buffers;
            if (std::size_t(image->bufferView) >= views.size()) {
                throw Error(ErrorKind::InvalidInput, label + ": its bufferView does not exist");
            }
            const tinygltf::BufferView& view = views[std::size_t(image->bufferView)];
            if (view.buffer < 0 || std::size_t(view.buffer) >= buffers.size()) {
                throw Error(ErrorKind::InvalidInput, label + ": its buffer does not exist");
            }
            const std::size_t buffer_size = buffers[std::size_t(view.buffer)].data.size();
            if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset ||
                view.byteLength != std::size_t(size)) {
                throw Error(ErrorKind::InvalidInput,
                            label + ": its bufferView runs past the end of its buffer");
            }
        }
        if (size <= 0 || bytes == nullptr) {
            throw Error(ErrorKind::InvalidInput, label + ": the image is empty");
        }
        const std::span<const std::byte> encoded(reinterpret_cast<const std::byte*>(bytes),
                                                 std::size_t(size));
        const ImageHeader header =
            check_image_header(encoded, context.limits->max_texture_pixels, label);
        image->width = header.width;
        image->height = header.height;
        context.encoded_images[index].assign(encoded.begin(), encoded.end());
        return true;
    } catch (const Error& error) {
        context.image_error = error;
    } catch (const std::bad_alloc&) {
        context.image_error = Error(ErrorKind::LimitExceeded, label + ": out of memory");
    } catch (const std::exception& error) {
        context.image_error = Error(ErrorKind::Internal, label + ": " + error.what());
    }
    if (err != nullptr) {
        *err += std::string(context.image_error->what()) + "\n";
    }
    return false;
}

std::uint32_t little_endian_u32(std::span<const std::byte> bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        value |= std::uint32_t(bytes[at + i]) << (8 * i);
    }
    return value;
}

// The GLB container, checked before tinygltf reads it (its check of the BIN chunk's length
// forgets the chunk header). Returns the JSON chunk.
std::span<const std::byte> check_glb(std::span<const std::byte> bytes, const std::string& asset) {
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) {
        fail(ErrorKind::InvalidInput, asset, "not a binary glTF (.glb) file: no 'glTF' header");
    }
    const std::uint32_t version = little_endian_u32(bytes, 4);
    if (version != 2) {
        fail(ErrorKind::Unsupported, asset,
             "binary glTF version " + std::to_string(version) + " is not supported (only 2)");
    }
    const std::uint64_t length = little_endian_u32(bytes, 8);
    if (length > bytes.size() || length < 20) {
        fail(ErrorKind::InvalidInput, asset,
             "the .glb header says " + std::to_string(length) + " bytes, the file has " +
                 std::to_string(bytes.size()));
    }
    const std::uint64_t json_length = little_endian_u32(bytes, 12);
    if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0 || json_length == 0 ||
        20 + json_length > length) {
        fail(ErrorKind::InvalidInput, asset,
             "the .glb file's first chunk is not a valid JSON chunk");
    }
    const std::uint64_t bin_start = 20 + json_length;
    if (bin_start < length) {
        if (bin_start + 8 > length) {
            fail(ErrorKind::InvalidInput, asset, "the .glb file's second chunk is truncated");
        }
        const std::uint64_t bin_length = little_endian_u32(bytes, std::size_t(bin_start));
        if (bin_start + 8 + bin_length > length) {
            fail(ErrorKind::InvalidInput, asset,
                 "the .glb file's BIN chunk runs past the end of the file");
        }
    }
    return bytes.subspan(20, std::size_t(json_length));
}

// What tinygltf 2.7 cannot parse, rewritten in the JSON before it does, and undone after.
struct TinygltfWorkarounds {
    // EXT_meshopt_compression's fallback buffers ("fallback": true, no uri): tinygltf takes a
    // .glb's buffer without a uri for the BIN chunk (and refuses one longer than it), and
    // refuses it in a .gltf. Each is given one byte as a data: URI, emptied after parsing.
    std::vector<std::size_t> fallback_buffers;
    // Index accessors without a bufferView (KHR_draco_mesh_compression's, whose data is in the
    // Draco stream; sparse ones on zeros): tinygltf refuses them as "invalid bufferView". Each is
    // given bufferView 0 to parse, and none again after parsing.
    std::vector<std::size_t> viewless_indices;

    bool empty() const { return fallback_buffers.empty() && viewless_indices.empty(); }
};

TinygltfWorkarounds work_around_tinygltf(checked_json::Json& root) {
    TinygltfWorkarounds workarounds;
    if (const auto buffers = root.find("buffers"); buffers != root.end()) {
        for (std::size_t b = 0; b < buffers->size(); ++b) {
            checked_json::Json& buffer = (*buffers)[b];
            const checked_json::Json* extensions = checked_json::find(buffer, "extensions");
            const checked_json::Json* meshopt =
                extensions == nullptr ? nullptr
                                      : checked_json::find(*extensions, "EXT_meshopt_compression");
            const checked_json::Json* fallback =
                meshopt == nullptr ? nullptr : checked_json::find(*meshopt, "fallback");
            if (fallback != nullptr && *fallback == true && !buffer.contains("uri")) {
                buffer["uri"] = "data:application/octet-stream;base64,AA==";
                buffer["byteLength"] = 1;
                workarounds.fallback_buffers.push_back(b);
            }
        }
    }
    const auto accessors = root.find("accessors");
    const checked_json::Json* meshes = checked_json::find(root, "meshes");
    const checked_json::Json* views = checked_json::find(root, "bufferViews");
    if (accessors == root.end() || meshes == nullptr || views == nullptr || views->empty()) {
        return workarounds;
    }
    for (const auto& mesh : *meshes) {
        for (const auto& primitive : mesh["primitives"]) {  // checked by the schema
            const checked_json::Json* indices = checked_json::find(primitive, "indices");
            if (indices == nullptr || indices->get<std::uint64_t>() >= accessors->size()) {
                continue;
            }
            const auto index = std::size_t(indices->get<std::uint64_t>());
            checked_json::Json& accessor = (*accessors)[index];
            if (accessor.is_object() && !accessor.contains("bufferView")) {
                accessor["bufferView"] = 0;
                workarounds.viewless_indices.push_back(index);
            }
        }
    }
    return workarounds;
}

// The .glb `bytes` with the JSON chunk `json` instead of its own.
std::vector<std::byte> replace_glb_json(std::span<const std::byte> bytes,
                                        std::span<const std::byte> old_json, std::string json) {
    while (json.size() % 4 != 0) {
        json += ' ';  // chunks are 4-byte aligned; JSON pads with spaces
    }
    const std::size_t rest = 20 + old_json.size();
    const std::size_t total = 20 + json.size() + (bytes.size() - rest);
    std::vector<std::byte> out;
    out.reserve(total);
    const auto u32 = [&out](std::size_t value) {
        for (int i = 0; i < 4; ++i) {
            out.push_back(std::byte((value >> (8 * i)) & 0xff));
        }
    };
    out.insert(out.end(), bytes.begin(), bytes.begin() + 8);  // magic, version
    u32(total);
    u32(json.size());
    out.insert(out.end(), bytes.begin() + 16, bytes.begin() + 20);  // "JSON"
    const auto* text = reinterpret_cast<const std::byte*>(json.data());
    out.insert(out.end(), text, text + json.size());
    out.insert(out.end(), bytes.begin() + std::ptrdiff_t(rest), bytes.end());
    return out;
}

// The error for a local asset's file that is not read: tinygltf names it as the folder joined
// with the URI, which the message gives back as the URI.
[[noreturn]] void refuse_outside_file(const std::string& path, const std::filesystem::path& folder,
                                      const std::string& asset) {
    const std::string prefix = folder.string() + "/";
    const std::string uri = path.rfind(prefix, 0) == 0 ? path.substr(prefix.size()) : path;
    const std::string named = "the file '" + one_line(uri, 200) + "' it references ";
    std::error_code error;
    if (uri.find("://") != std::string::npos) {
        fail(ErrorKind::InvalidInput, asset, named + "is a URL, not a file name");
    }
    if (!uri.empty() && uri.front() == '/') {
        fail(ErrorKind::InvalidInput, asset,
             named + "is an absolute path: files are named relative to " + folder.string());
    }
    if (std::filesystem::exists(path, error)) {
        fail(ErrorKind::InvalidInput, asset,
             named + "lies outside " + folder.string() +
                 " (no file outside the asset's own folder is read, whether named by '..' or "
                 "reached by a symbolic link)");
    }
    fail(ErrorKind::Io, asset, named + "does not exist in " + folder.string());
}

}  // namespace

std::string image_label(const std::string& asset, int index, const std::string& name) {
    return asset + ": image " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
}

std::string what_to_do_without(const std::string& extension) {
    if (extension == "KHR_texture_basisu") {
        return "its KTX2 (Basis Universal) textures have no PNG, JPEG or WebP fallback; export "
               "them as WebP (glTF-Transform: gltf-transform webp in.glb out.glb) or with a "
               "fallback image";
    }
    if (extension == "KHR_draco_mesh_compression" || extension == "EXT_meshopt_compression") {
        return "export it uncompressed or with the other compression";
    }
    return "export it without the extension, or with it optional (listed in extensionsUsed "
           "only, with a fallback)";
}

bool supported_extension(const std::string& name) {
    for (const char* supported :
         {"KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_mesh_quantization",
          "EXT_meshopt_compression", "KHR_draco_mesh_compression", "EXT_mesh_gpu_instancing",
          "EXT_texture_webp", "EXT_texture_avif", "KHR_materials_variants", "KHR_materials_unlit",
          "KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat",
          "KHR_materials_sheen", "KHR_materials_transmission", "KHR_materials_volume"}) {
        if (name == supported) {
            return true;
        }
    }
    return false;
}

tinygltf::Model parse_gltf(std::span<const std::byte> bytes, const std::string& asset, bool binary,
                           const MeshLimits& limits, ParseContext& context) {
    if (bytes.size() > std::size_t(std::numeric_limits<unsigned int>::max())) {
        fail(ErrorKind::LimitExceeded, asset, "glTF files of 4 GiB or more are not supported");
    }
    const std::span<const std::byte> json = binary ? check_glb(bytes, asset) : bytes;
    // Parsed within bounds: tinygltf never sees more.
    checked_json::Json root = check_gltf_schema(json, asset);
    const TinygltfWorkarounds workarounds = work_around_tinygltf(root);
    std::vector<std::byte> rewritten;
    if (!workarounds.empty()) {
        // Strings were UTF-8 checked by the parser; replace keeps dump from ever throwing.
        std::string text = root.dump(-1, ' ', false, checked_json::Json::error_handler_t::replace);
        if (binary) {
            rewritten = replace_glb_json(bytes, json, std::move(text));
        } else {
            const auto* first = reinterpret_cast<const std::byte*>(text.data());
            rewritten.assign(first, first + text.size());
        }
        bytes = rewritten;
    }

    tinygltf::Model model;
    context.asset = asset;
    context.limits = &limits;
    context.model = &model;
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(
        tinygltf::FsCallbacks{&file_exists, &keep_path, &read_file, &refuse_write, &context});
    loader.SetImageLoader(&keep_encoded_image, &context);
    std::string err;
    std::string warn;
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        const auto size = static_cast<unsigned int>(bytes.size());
        const std::string base = context.folder ? context.folder->string() : std::string();
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, size, base)
                    : loader.LoadASCIIFromString(&model, &err, &warn,
                                                 reinterpret_cast<const char*>(data), size, base);
    } catch (const std::bad_alloc&) {
        fail(ErrorKind::LimitExceeded, asset, "out of memory while parsing the glTF");
    } catch (const std::exception& error) {
        fail(ErrorKind::InvalidInput, asset,
             std::string("not a valid glTF 2.0 asset: ") + error.what());
    }
    if (context.image_error) {
        throw *context.image_error;
    }
    context.warnings = warn;
    if (!context.refused_uris.empty() && context.refused_uris.front().rfind("data:", 0) == 0) {
        // tinygltf takes a data: URI of a media type it does not know for a file name.
        fail(ErrorKind::Unsupported, asset,
             "unsupported data: URI '" + one_line(context.refused_uris.front(), 60) +
                 "': buffers must be application/octet-stream or application/gltf-buffer, images "
                 "image/png or image/jpeg, all base64 (tinygltf decodes no other data: URI: a "
                 "WebP, AVIF or KTX2 image goes in a bufferView or a file)");
    }
    if (context.oversized_file) {
        fail(ErrorKind::LimitExceeded, asset,
             "the file '" + one_line(*context.oversized_file, 200) +
                 "' it references would take the asset's files over the limit of " +
                 std::to_string(limits.max_bytes) + " bytes");
    }
    if (!context.refused_uris.empty() && context.folder) {
        refuse_outside_file(context.refused_uris.front(), *context.folder, asset);
    }
    if (!context.refused_uris.empty()) {
        fail(ErrorKind::Unsupported, asset,
             "external file '" + one_line(context.refused_uris.front(), 200) +
                 "' referenced by the asset is not allowed: embed buffers as data: URIs or use "
                 ".glb");
    }
    if (!ok) {
        fail(ErrorKind::InvalidInput, asset,
             "not a valid glTF 2.0 asset: " +
                 (err.empty() ? std::string("(no reason given)") : one_line(err)));
    }
    if (model.asset.version.rfind("2.", 0) != 0) {
        fail(
            ErrorKind::Unsupported, asset,
            "glTF version '" + one_line(model.asset.version, 40) + "' is not supported (only 2.0)");
    }
    for (const std::size_t buffer : workarounds.fallback_buffers) {
        model.buffers[buffer].data.clear();
    }
    for (const std::size_t accessor : workarounds.viewless_indices) {
        model.accessors[accessor].bufferView = -1;
    }
    for (const std::string& extension : model.extensionsRequired) {
        if (!supported_extension(extension)) {
            fail(ErrorKind::Unsupported, asset,
                 "the asset requires the extension " + one_line(extension, 80) +
                     ", which is not supported: " + what_to_do_without(extension));
        }
    }
    return model;
}

}  // namespace oer::mesh_detail
