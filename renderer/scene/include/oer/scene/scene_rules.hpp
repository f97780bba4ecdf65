#pragma once
// The rules a frame's scene imposes on what it needs, written once for the renderer, the
// service and the command line.
#include <string>

#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_transfer.hpp"

namespace oer {

// Whether the frame needs FrameRequest::specular, the rig's prefiltered residual: some
// object's mesh draws a primitive with a glossy material (Material::glossy) and the rig's model
// is Hdr (the thesis model has no specular term). A Lambertian scene never computes, loads or
// uploads the cube. The renderer requires the cube exactly then and uses it exactly then; the
// service and the command line prefilter or load it exactly then.
bool needs_specular(const FrameRequest& request);

// Why `transfer` was not baked for `request`'s scene (the bounce, the ground, one receiver set
// per object and primitive with a point per vertex), or empty when it was. One check for the
// renderer's validation and the service's reading of stored transfers.
std::string transfer_misfit(const SceneTransfer& transfer, const FrameRequest& request);

}  // namespace oer
