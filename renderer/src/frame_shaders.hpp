#pragma once
// GLSL sources of the frame passes (#version 450 core). Specialised by defines at link time:
// SH_ORDER (bands 0 .. SH_ORDER-1), LIGHTS_ON (lights that are on this frame), SHADOWS (0: no
// shadow maps, every light reaches every point), PCF (0: the thesis's hard test, 1: filtered).
namespace oer::shaders {

extern const char* const kMeshVertex;          // positions to clip space, world normal and uv
extern const char* const kDepthFragment;       // shadow pass: depth only
extern const char* const kShadeFragment;       // SH irradiance, shadows, specular
extern const char* const kFullscreenVertex;    // one triangle covering the viewport
extern const char* const kBackgroundFragment;  // the environment, equirect lookup
extern const char* const kDisplayFragment;     // exposure, tone mapping, sRGB, compositing

}  // namespace oer::shaders
