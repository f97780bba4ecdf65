#pragma once
// Every GLSL program the frame renderer builds: its two stages (files of renderer/gl/shaders)
// and the defines that specialise it, each with the values the renderer may give it. One table
// for two readers: the renderer, which checks every define string it builds against it, and the
// shader test (tests/gl/shader_sources_test.cpp), which compiles the variants it spans with
// glslangValidator, so that no variant the renderer can ask for is left unchecked.
//
// The defines: SH_ORDER (bands 0 .. SH_ORDER-1), LIGHTS_ON (lights of weight above 0 this frame),
// SHADOWS (0: no shadow maps, every light reaches every point), PCF (0: the thesis's hard test,
// 1: filtered), ENVIRONMENT_BACKGROUND (1: the map behind the scene, 0: nothing, alpha 0),
// DISPLAY_OUTPUT (1: tone-mapped sRGB, 0: linear radiance), SURFACE (the shading pass's
// surface: 0 background, 1 objects, 2 ground plane, 3 ground plane as a shadow catcher, 4 objects
// with the extensions' layers), SPECULAR (1: glossy materials, with the
// specular cubes and DFG table; 0: every material Lambertian), ALPHA_TEST
// (1: fragments under the material's alpha cutoff are discarded), MATERIAL_TEXTURES (0: a
// material without textures, whose program reads no uv or tangent) and MATERIAL_LAYERS (1: a
// material with the extensions' layers, mesh.hpp's Material::layered).
#include <span>
#include <string_view>
#include <vector>

namespace oer::shaders {

// The most lights a frame can switch on: the largest rig the API reads (api/src/rig_from_json.cpp).
inline constexpr int kMaxFrameLights = 64;

struct DefineRange {
    std::string_view name;
    int min = 0;
    int max = 0;
};

struct FrameProgram {
    std::string_view name;  // as the renderer names it: "shade"
    std::string_view vertex;
    std::string_view fragment;
    std::vector<DefineRange> defines;
};

std::span<const FrameProgram> frame_programs();

// The program named `name`; throws oer::Error (Internal) if there is none.
const FrameProgram& frame_program(std::string_view name);

// Throws oer::Error (Internal) unless `defines`, lines "#define NAME VALUE\n", set each of the
// program's defines exactly once to an integer in its range, and nothing else.
void check_defines(const FrameProgram& program, std::string_view defines);

}  // namespace oer::shaders
