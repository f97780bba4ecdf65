#pragma once
// What the renderer itself needs of a request before any GL call: its pointers set, its
// numbers finite, the light switches matching the rig, and sizes (the frame's, its samples',
// the shadow maps', the meshes' textures') within FrameLimits and what the device can hold. The
// rules of what a client may ask for (the sample counts offered, shadow resolutions as powers of
// two, JPEG quality) are the API's (api/src/render_request.cpp).
#include "oer/scene/frame_request.hpp"

namespace oer {

// Throws oer::Error: InvalidInput naming the member, LimitExceeded past the limits.
void validate_frame_request(const FrameRequest& request, const FrameLimits& limits,
                            int max_texture_size);

}  // namespace oer
