#pragma once
// The GLSL files of renderer/gl/shaders, embedded in the binary at build time: the build runs
// cmake/embed_files.cmake, which writes shader_files.cpp with one raw string per file listed
// in renderer/gl/CMakeLists.txt.
#include <span>
#include <string_view>

namespace oer::shaders {

struct ShaderFile {
    std::string_view name;  // as in renderer/gl/shaders: "shade.frag", "sh_lighting.glsl"
    std::string_view text;
};

// Every embedded file, in the order renderer/gl/CMakeLists.txt lists them.
std::span<const ShaderFile> shader_files();

}  // namespace oer::shaders
