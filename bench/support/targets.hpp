#pragma once
// The speed targets of docs/design.md section 8 (2-core CPU machine, llvmpipe), in one place: every
// benchmark prints its figures beside these. When that table changes, change it here.

namespace oer::bench::targets {

// Preprocessing a 2048x1024 map, 4 lights, SH order 3 (preprocess_benchmark).
inline constexpr int kPreprocessWidth = 2048;
inline constexpr int kPreprocessHeight = 1024;
inline constexpr int kPreprocessLights = 4;
inline constexpr int kPreprocessOrder = 3;
inline constexpr double kPreprocessMs = 20.0;  // at most
// At least this many times faster than a literal implementation of the thesis's algorithm
// measured in the same run (bench/support/literal_thesis.hpp).
inline constexpr double kSpeedupOverLiteral = 50.0;

// SH projection, order 3, whole map plus every light mask, on 2 cores (preprocess_benchmark).
inline constexpr double kProjectionGpixelsPerSecond = 2.0;  // at least

// Color pass + readback, bunny on a ground plane, 2 lights, shadow maps cached
// (frame_benchmark).
inline constexpr double kFrameMs512 = 10.0;  // at most, at 512x512
inline constexpr double kFps1366 = 30.0;     // at least, at 1366x768
// The colour pass with glTF PBR materials against the same scene Lambertian.
inline constexpr double kPbrColorPassRatio = 1.5;  // at most

// Over HTTP (http_benchmark), medians.
inline constexpr double kPreviewP50Ms = 10.0;   // preview frame while dragging, at the server
inline constexpr double kWarmJpegP50Ms = 40.0;  // warm 512x512 JPEG, default request
inline constexpr double kCachedFrameMs = 1.0;   // a frame already in the cache (ETag or LRU)
// A colour or floor change on a product already shown, against a normal uncached frame.
inline constexpr double kChangeOverNormalFrame = 2.0;  // at most
// A new product (about 50k triangles): from the start of its upload to its first frame (a
// preliminary one, Prefer: wait=0), and to the refined frame with its transfer.
inline constexpr double kNewProductFirstFrameS = 2.0;  // at most
inline constexpr double kNewProductRefinedS = 5.0;     // at most

// Frame error against the reference renderer (frame_sweep), on the product and on the ground:
// the default's relative RMS of luminance at most this share of plain SH irradiance's.
inline constexpr double kFrameErrorOverPlainSh = 0.5;

// The transfer bake of the bunny on the ground, one bounce, on 2 cores
// (transfer_benchmark).
inline constexpr double kTransferBakeBunnyMs = 2000.0;  // at most
// The color pass of a frame lit through the transfer, against the same frame without.
inline constexpr double kOcclusionColorPassRatio = 1.3;  // at most

}  // namespace oer::bench::targets
