#pragma once
// Private to the glTF loader: the numbers of a glTF's JSON as the loader stores them, each
// checked, and numbers as text in messages. `what` names the number ("material 'M':
// alphaCutoff"); every failure is an oer::Error (InvalidInput) naming `asset`.
#include <tiny_gltf.h>

#include <string>

#include <glm/vec2.hpp>

namespace oer::mesh_detail {

// A number as its shortest decimal text, for messages.
std::string number_text(double value);

// A factor the specification bounds to [0, 1]: it must be finite, and is clamped to that range.
float unit_factor(const std::string& asset, double value, const std::string& what);

// Any other number: it must be finite as the float it is stored in.
float finite_float(const std::string& asset, double value, const std::string& what);

// finite_float, and at least 0.
float non_negative_float(const std::string& asset, double value, const std::string& what);

// A JSON array of 2 numbers, each finite_float.
glm::vec2 finite_vec2(const std::string& asset, const tinygltf::Value& value,
                      const std::string& what);

}  // namespace oer::mesh_detail
