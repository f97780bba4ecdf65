#pragma once
// The stored form of a scene's transfer (oer/scene/scene_transfer.hpp): the asset store's derived
// entry, which the store seals with its digest.
#include <string>
#include <string_view>

#include "oer/scene/scene_transfer.hpp"

namespace oer {

// Magic "OERPRT" and a version byte, then SceneTransfer's fields with their counts,
// little-endian.
std::string encode_transfer(const SceneTransfer& transfer);
// Throws oer::Error (InvalidInput) naming what is wrong: a bad magic or version, a count that
// does not fit the bytes (checked before anything is allocated), a non-finite value.
SceneTransfer decode_transfer(std::string_view bytes);

}  // namespace oer
