#pragma once
// Private to the glTF loader: the numbers of a glTF's JSON as the loader stores them, each
// checked, and numbers as text in messages. `what` names the number ("material 'M':
// alphaCutoff"); every failure is an oer::Error (InvalidInput) naming `asset`.
#include <tiny_gltf.h>

#include <cstdint>
#include <optional>
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

// Compressed geometry decodes to at most a few times its bytes, beyond a floor under which any
// ratio is accepted: a small stream that claims far more is a decompression bomb.
// EXT_meshopt_compression's codec encodes a run of zeros in 1/64 of its size, while real files
// decode to 2 to 8 times theirs (gltfpack's and glTF-Transform's of 2CylinderEngine: 3 to 4);
// Draco's connectivity alone reaches 50 times, and real streams decode to 5 to 30 times theirs
// (glTF-Transform's of 2CylinderEngine: 7). The mesh the loader builds from decoded data takes
// a few times more again.
inline constexpr std::uint64_t kMeshoptDecodingRatio = 32;
inline constexpr std::uint64_t kDracoDecodingRatio = 64;
inline constexpr std::uint64_t kDecodingFloor = 16ull << 20;

// Whether `decoded` bytes from `compressed` bytes stay within `ratio` times (or the floor).
inline bool within_decoding_ratio(std::uint64_t decoded, std::uint64_t compressed,
                                  std::uint64_t ratio) {
    return decoded <= kDecodingFloor || decoded / ratio <= compressed;
}

// Member `key` of an extension's JSON object (`object`, named `what`): a non-negative integer
// below 2^53 (a count, an offset, an index), or `fallback` when absent; absent without one,
// or of another kind: InvalidInput.
std::uint64_t integer_member(const std::string& asset, const tinygltf::Value& object,
                             const char* key, const std::string& what,
                             std::optional<std::uint64_t> fallback = std::nullopt);

// Likewise a string member.
std::string string_member(const std::string& asset, const tinygltf::Value& object, const char* key,
                          const std::string& what,
                          std::optional<std::string> fallback = std::nullopt);

}  // namespace oer::mesh_detail
