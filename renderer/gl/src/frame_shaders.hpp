#pragma once
// GLSL sources of the frame passes (#version 450 core). Specialised by defines at link time:
// SH_ORDER (bands 0 .. SH_ORDER-1), LIGHTS_ON (lights that are on this frame), SHADOWS (0: no
// shadow maps, every light reaches every point), PCF (0: the thesis's hard test, 1: filtered),
// ENVIRONMENT_BACKGROUND (1: the map behind the scene, 0: nothing, alpha 0) and DISPLAY_OUTPUT
// (1: tone-mapped sRGB, 0: linear radiance).
#include <string>

namespace oer::shaders {

extern const char* const kMeshVertex;                // positions to clip space, world normal, uv
extern const char* const kDepthFragment;             // shadow pass: depth only
extern const char* const kGeometryFragment;          // G-buffer: position, normal, albedo
extern const char* const kFullscreenVertex;          // one triangle covering the viewport
extern const char* const kShadeFragment;             // SH irradiance, shadows, specular
extern const char* const kGroundVisibilityFragment;  // a light's visibility on the ground
extern const char* const kResolveFragment;           // supersample mean, then display output

// The source with its shared parts (#include_lighting, #include_display) spliced in.
std::string compose(const char* source);

}  // namespace oer::shaders
