#pragma once
// Shader stages assembled from the embedded files of renderer/gl/shaders (shader_files.hpp).
//
// A stage (*.vert, *.frag) starts with its #version line and includes shared parts (*.glsl)
// with the GL_GOOGLE_include_directive syntax, `#include "sh_lighting.glsl"` (declared by
// `#extension GL_GOOGLE_include_directive : require`, so that glslangValidator reads the files
// as they are). GL has no include: the parts are spliced in here, recursively and each file
// once (as if every part had an include guard), with #line directives, so that a compiler's
// "2:17" is line 17 of the file of source-string number 2.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shader_files.hpp"

namespace oer::shaders {

struct ShaderSource {
    std::string text;                // for glShaderSource
    std::vector<std::string> files;  // files[i]: the file of source-string number i
};

// The stage `file` ("shade.frag") with the texture units and buffer bindings of gl_bindings.hpp
// (binding_defines) and then `defines` ("#define SH_ORDER 3\n...") after its #version line,
// from the embedded files. Includes are resolved whatever the preprocessor
// conditionals around them. Throws oer::Error (Internal) for a file that is not embedded, a
// stage without a first #version line, a malformed #include or one of a file that is not
// embedded, with the file and line of the #include.
ShaderSource program_source(std::string_view file, std::string_view defines);

// The same from the files `files` instead of the embedded ones.
ShaderSource program_source(std::string_view file, std::string_view defines,
                            std::span<const ShaderFile> files);

// The text of the file `name` of `files`; throws oer::Error (Internal) naming the files there
// are if there is none.
std::string_view shader_file(std::string_view name, std::span<const ShaderFile> files);

// A compiler's log with the source-string numbers of its positions replaced by the files' names:
// Mesa's "1:12(5): error: ..." and glslang's "ERROR: 1:12: ..." become "sh_lighting.glsl:12(5):
// error: ..." and "ERROR: sh_lighting.glsl:12: ...".
std::string name_files(std::string_view log, const std::vector<std::string>& files);

}  // namespace oer::shaders
