#pragma once
// A linked GLSL program with its uniform locations looked up once.
#include <GL/glcorearb.h>

#include <string>
#include <string_view>
#include <unordered_map>

namespace oer::gl {

class Program {
  public:
    // defines: lines inserted after the #version line ("#define SH_ORDER 3\n...").
    Program(std::string_view vertex_source, std::string_view fragment_source,
            const std::string& defines, const std::string& name);
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
