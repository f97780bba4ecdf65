#include "gl_program.hpp"

#include <vector>

#include "oer/core/error.hpp"

namespace oer::gl {

namespace {

std::string info_log(GLuint object, bool is_program) {
    GLint length = 0;
    if (is_program) {
        glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    } else {
        glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    }
    std::vector<char> log(std::size_t(std::max(length, 1)), '\0');
    if (is_program) {
        glGetProgramInfoLog(object, length, nullptr, log.data());
    } else {
        glGetShaderInfoLog(object, length, nullptr, log.data());
    }
    return log.data();
}

GLuint compile(GLenum stage, const shaders::ShaderSource& source, const std::string& name) {
    const GLuint shader = glCreateShader(stage);
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = shaders::name_files(info_log(shader, false), source.files);
        glDeleteShader(shader);
        throw Error(ErrorKind::Internal, "shader '" + name + "' (" +
                                             (stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                                             ") does not compile: " + log);
    }
    return shader;
}

}  // namespace

Program::Program(const shaders::ShaderSource& vertex_source,
                 const shaders::ShaderSource& fragment_source, const std::string& name)
    : name_(name) {
    const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source, name);
    GLuint fragment = 0;
    try {
        fragment = compile(GL_FRAGMENT_SHADER, fragment_source, name);
    } catch (...) {
        glDeleteShader(vertex);
        throw;
    }
    id_ = glCreateProgram();
    glAttachShader(id_, vertex);
    glAttachShader(id_, fragment);
    glLinkProgram(id_);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    GLint ok = GL_FALSE;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = info_log(id_, true);
        glDeleteProgram(id_);
        throw Error(ErrorKind::Internal, "program '" + name + "' does not link: " + log);
    }
}

Program::~Program() {
    if (id_ != 0) {
        glDeleteProgram(id_);
    }
}

GLint Program::uniform(const std::string& name) {
    const auto found = locations_.find(name);
    if (found != locations_.end()) {
        return found->second;
    }
    const GLint location = glGetUniformLocation(id_, name.c_str());
    locations_.emplace(name, location);
    return location;
}

}  // namespace oer::gl
