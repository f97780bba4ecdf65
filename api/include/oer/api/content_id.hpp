#pragma once
// Content addressing: SHA-256 (collision resistant, so that uploads cannot be crafted to
// collide with someone else's cached asset).
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "oer/rig.hpp"

namespace oer::api {

std::string sha256_hex(std::span<const std::byte> bytes);
std::string sha256_hex(std::string_view text);

// Id of a rig: SHA-256 over the source's digest and the canonical options.
std::string rig_id(const std::string& source_digest, const RigOptions& options);

}  // namespace oer::api
