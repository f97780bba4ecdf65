#pragma once
// Private to the glTF loader: glTF 2.0 samplers (section 5.26), their WebGL enums as
// oer::TextureSampler; an absent filter keeps the default, an unknown enum is refused.
#include <tiny_gltf.h>

#include <string>

#include "oer/mesh/mesh.hpp"

namespace oer::mesh_detail {

// Sampler `index` of the model (-1: the default sampler). `texture` names its user in messages
// ("material 'M': normalTexture: texture 2"); failures are oer::Errors naming `asset`.
TextureSampler read_sampler(const tinygltf::Model& model, int index, const std::string& texture,
                            const std::string& asset);

}  // namespace oer::mesh_detail
