#pragma once
// The one place that turns a rendered frame into the bytes of an image file: the HTTP routes,
// the frame service and the command line all encode through it, so a format means the same
// everywhere. It lives in api (not renderer/image) because it is chosen by the api's
// ImageFormat and reads the renderer's Frame, which renderer/image cannot see (gl -> image).
#include <cstdint>
#include <string>
#include <vector>

#include "oer/api/render_request.hpp"
#include "oer/scene/frame_request.hpp"

namespace oer::api {

// JPEG and PNG encode frame.display (sRGB, tone mapped), EXR frame.linear (the frame must have
// been rendered with FrameRequest::linear). quality: JPEG's 1..100, ignored by the others.
// Throws oer::Error as encode_jpeg, encode_png and encode_exr do.
std::vector<std::uint8_t> encode(const Frame& frame, ImageFormat format, int quality);

// "image/jpeg", "image/png", "image/x-exr".
std::string content_type_of(ImageFormat format);

}  // namespace oer::api
