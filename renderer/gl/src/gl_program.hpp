#pragma once
// A linked GLSL program with its uniform locations looked up once.
#include <GL/glcorearb.h>

#include <string>
#include <unordered_map>

#include "shader_sources.hpp"

namespace oer::gl {

class Program {
  public:
    // Throws oer::Error (Internal) with the compiler's log, positions named by file, if a stage
    // does not compile or the program does not link.
    Program(const shaders::ShaderSource& vertex, const shaders::ShaderSource& fragment,
            const std::string& name);
    ~Program();
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    GLuint id() const { return id_; }
    // Location of a uniform; -1 when the compiler dropped it (setting -1 is a no-op in GL).
    GLint uniform(const std::string& name);

  private:
    GLuint id_ = 0;
    std::string name_;
    std::unordered_map<std::string, GLint> locations_;
};

}  // namespace oer::gl
