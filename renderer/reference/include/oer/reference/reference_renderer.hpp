#pragma once
// The ground truth of every frame-error figure (docs/accuracy.md): the frame a FrameRequest asks
// for, path traced on Embree instead of rasterised. Per pixel, the outgoing radiance of the
// Lambertian surfaces (the renderer's albedos and ground plane) under the environment map with
// true visibility (meshes and ground occlude), the map's lights scaled by the request's
// weights (a light at 0 is its pixels removed from the map), turned by the request's yaw.
//
// Monte Carlo, per shading point: one sample of the map's piecewise-constant distribution and
// one of the cosine lobe, combined by multiple importance sampling with the power heuristic
// (E. Veach, "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis, Stanford,
// 1997, section 9.2). Every pixel's random sequence depends on the seed and the pixel alone, so
// the image is the same whatever the thread count.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "oer/scene/frame_request.hpp"

namespace oer {

enum class ReferenceSampling {
    Mis,     // the map's distribution and the cosine lobe, power heuristic
    Cosine,  // the cosine lobe alone: exact under a constant map when nothing occludes
};

struct ReferenceOptions {
    Bounce bounce = Bounce::None;
    ReferenceSampling sampling = ReferenceSampling::Mis;
    int samples = 64;  // per pixel, even: two independent halves estimate the noise
    std::uint64_t seed = 1;
    int threads = 0;  // 0: every core
};

// What the ray through a pixel's centre sees.
enum class ReferenceSurface : std::uint8_t { Background, Object, Ground };

// Relative RMS noise of the image (the mean of all samples) over the pixels whose centre sees
// a surface: sqrt(sum ((Y_a - Y_b) / 2)^2 / sum Y^2), Y the luminance of the image and Y_a, Y_b
// that of its two independent half-sample images. (Y_a - Y_b) / 2 has the variance of the
// mean's error, since var(Y_a - Y_b) = 2 var(Y_half) = 4 var(Y).
struct ReferenceNoise {
    double object = 0.0;  // 0 when object_pixels is 0
    double ground = 0.0;  // 0 when ground_pixels is 0
    std::size_t object_pixels = 0;
    std::size_t ground_pixels = 0;
};

struct ReferenceFrame {
    int width = 0;
    int height = 0;
    // RGBA linear radiance, alpha the coverage and colour premultiplied by it, row 0 at the top:
    // Frame::linear's layout, so it encodes to EXR as the renderer's frames do.
    std::vector<float> linear;
    std::vector<ReferenceSurface> surfaces;  // per pixel, row 0 at the top
    ReferenceNoise noise;
    // Per pixel, (Y_a - Y_b) / 2 of its two half-sample luminances (ReferenceNoise's numerator):
    // so that the noise of any set of pixels, not only a whole surface, can be measured.
    std::vector<double> luminance_noise;
    double render_ms = 0.0;
};

// The request's scene, camera, environment (FrameRequest::environment_map, required),
// light weights, yaw, ground, base colours, size and background (the map in that direction, as
// the renderer's environment background, or zero radiance and alpha otherwise). Exposure, tone
// mapping, shadow options, samples and the lighting model are the rasteriser's and are not
// read. Throws oer::Error (InvalidInput) for a request without a map or rig, or options out
// of range (samples odd or below 2), and (Internal) when Embree fails.
ReferenceFrame render_reference(const FrameRequest& request, const ReferenceOptions& options);

}  // namespace oer
