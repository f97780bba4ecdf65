#pragma once
// The rules a frame's scene imposes on what it needs, written once for the renderer, the
// service and the command line.
#include <string>

#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_transfer.hpp"

namespace oer {

// Why `transfer` was not baked for `request`'s scene (the bounce, the ground, one receiver set
// per object and primitive with a point per vertex), or empty when it was. One check for the
// renderer's validation and the service's reading of stored transfers.
std::string transfer_misfit(const SceneTransfer& transfer, const FrameRequest& request);

}  // namespace oer
