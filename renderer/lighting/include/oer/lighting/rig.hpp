#pragma once
// A light rig: everything the renderer and clients need from one environment map
// (docs/design.md section 7): the lights found in it and the SH radiance of the whole map and of
// each light's own pixels, with the choices made (light count, SH order, window) and why.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "oer/core/image.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/light_location.hpp"
#include "oer/lighting/sh_projection.hpp"

namespace oer {

enum class LightingModel {
    Hdr,     // physically based: linear radiance, diffuse = albedo / pi * E
    Thesis,  // tone map + normalise before projection, attenuation factors, E * albedo
};
std::string to_string(LightingModel model);
LightingModel lighting_model_from_string(const std::string& name);  // throws oer::Error
std::string to_string(Clustering clustering);
Clustering clustering_from_string(const std::string& name);  // throws oer::Error

enum class WindowChoice { None, Hanning, Lanczos, Auto };

struct RigOptions {
    std::optional<int> light_count;  // empty: auto (visible shadows only, up to max_lights)
    int max_lights = 4;
    double shadow_visibility_threshold = 0.05;  // auto: keep a light whose darkening reaches this
    std::optional<int> sh_order;                // empty: auto (lowest order under sh_tolerance)
    int max_sh_order = 9;
    double sh_tolerance = 0.01;  // relative RMS irradiance error against the reference
    WindowChoice window = WindowChoice::None;
    double window_cutoff = 0.0;  // for Hanning / Lanczos; 0 means default_window_cutoff
    LightingModel model = LightingModel::Hdr;
    LightLocationOptions location;
};

struct Rig {
    int source_width = 0;
    int source_height = 0;
    RepairCounts repaired;
    DynamicRange source_range = DynamicRange::High;  // set by whoever decoded the map
    RigOptions options;                              // as given
    LightingModel model = LightingModel::Hdr;
    std::vector<Light> lights;
    std::string light_count_reason;
    int order = 3;
    std::string order_reason;
    ShWindow window;
    std::string window_reason;
    // Unwindowed radiance: whole map and per light (of the tone-mapped map in the thesis model),
    // and the same above the horizon only: with the ground as lighting (docs/design.md section 2),
    // what a point above the plane sees of the map and of each light (a light near the horizon is
    // partly hidden by the plane).
    ShProjection sh;
    double reference_error =
        -1.0;  // relative RMS irradiance error of the chosen order, if measured
    std::map<std::string, double> timings_ms;
};

// The cutoff build_rig gives a Hanning or Lanczos window when RigOptions::window_cutoff is 0:
// Hanning 2 x order, Lanczos 1.5 x order. Measured by bench/lighting_sweep (cutoffs 1 to 8
// times the order, every Blender world and on/off subset): the error falls as the cutoff grows
// on every world and order, but the weakest window that keeps every subset non-negative varies
// with the map (city, courtyard, forest, interior, night, sunset need none at orders 3 to 9;
// studio and sunrise need Hanning at most 2.18 x order at order 3). These are the largest
// multiples of the grid that keep every subset of every world non-negative at the orders the
// auto order picks (3, 5, 7, 9): Hanning 3 x rings on studio at order 3 (-0.86 %), Lanczos
// 2 x does too (-0.33 %). A window on a map that does not ring only adds error (city, order 3:
// 3.48 % without, 7.25 % with Hanning 2 x): that is what WindowChoice::Auto is for. Throws
// oer::Error (InvalidInput) for WindowKind::None or an order below 1.
double default_window_cutoff(WindowKind kind, int order);

Rig build_rig(const HdrImage& image, const RepairCounts& repaired, const RigOptions& options);
// A decoded map's rig, which records the map's repairs and dynamic range.
Rig build_rig(const LoadedImage& loaded, const RigOptions& options);

}  // namespace oer
