// glTF samplers as oer::TextureSampler (see gltf_samplers.hpp).
#include "gltf_samplers.hpp"

#include <cstddef>

#include "mesh_errors.hpp"

namespace oer::mesh_detail {

namespace {

TextureWrap wrap(int value, const std::string& what, const std::string& asset) {
    switch (value) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return TextureWrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return TextureWrap::MirroredRepeat;
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
            return TextureWrap::Repeat;
        default:
            fail(ErrorKind::InvalidInput, asset,
                 what + " " + std::to_string(value) +
                     " is not one of CLAMP_TO_EDGE (33071), MIRRORED_REPEAT (33648) and "
                     "REPEAT (10497)");
    }
}

// The mipmap filters are accepted for minification only.
TextureFilter filter(int value, bool minification, const std::string& what,
                     const std::string& asset) {
    switch (value) {
        case TINYGLTF_TEXTURE_FILTER_NEAREST:
            return TextureFilter::Nearest;
        case TINYGLTF_TEXTURE_FILTER_LINEAR:
            return TextureFilter::Linear;
        default:
            break;
    }
    if (minification) {
        switch (value) {
            case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
                return TextureFilter::NearestMipmapNearest;
            case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
                return TextureFilter::LinearMipmapNearest;
            case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
                return TextureFilter::NearestMipmapLinear;
            case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR:
                return TextureFilter::LinearMipmapLinear;
            default:
                break;
        }
    }
    fail(ErrorKind::InvalidInput, asset,
         what + " " + std::to_string(value) +
             (minification ? " is not one of NEAREST (9728), LINEAR (9729) and the mipmap "
                             "filters 9984 to 9987"
                           : " is not one of NEAREST (9728) and LINEAR (9729)"));
}

}  // namespace

TextureSampler read_sampler(const tinygltf::Model& model, int index, const std::string& texture,
                            const std::string& asset) {
    TextureSampler result;
    if (index < 0) {
        return result;
    }
    if (std::size_t(index) >= model.samplers.size()) {
        fail(ErrorKind::InvalidInput, asset,
             texture + " refers to sampler " + std::to_string(index) + ", which does not exist");
    }
    const tinygltf::Sampler& source = model.samplers[std::size_t(index)];
    const std::string what = "sampler " + std::to_string(index) + ": ";
    result.wrap_s = wrap(source.wrapS, what + "wrapS", asset);
    result.wrap_t = wrap(source.wrapT, what + "wrapT", asset);
    if (source.magFilter >= 0) {
        result.mag_filter = filter(source.magFilter, false, what + "magFilter", asset);
    }
    if (source.minFilter >= 0) {
        result.min_filter = filter(source.minFilter, true, what + "minFilter", asset);
    }
    return result;
}

}  // namespace oer::mesh_detail
