#include "gl_errors.hpp"

#include <GL/glcorearb.h>

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/gl/gl_context.hpp"

namespace oer {

namespace gl_detail {

namespace {

// Messages kept per thread before check_gl_errors drains them; later ones are only counted,
// so that a loop of failing calls cannot fill the memory.
constexpr std::size_t max_logged_messages = 32;

struct DebugLog {
    std::vector<std::string> messages;
    std::size_t dropped = 0;
};

thread_local DebugLog debug_log;

std::string hex(unsigned value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%04x", value);
    return text;
}

std::string gl_error_name(GLenum code) {
    switch (code) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_CONTEXT_LOST:
            return "GL_CONTEXT_LOST";
        default:
            return "GL error " + hex(code);
    }
}

const char* type_name(GLenum type) {
    switch (type) {
        case GL_DEBUG_TYPE_ERROR:
            return "error";
        case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
            return "deprecated behaviour";
        case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
            return "undefined behaviour";
        case GL_DEBUG_TYPE_PORTABILITY:
            return "portability";
        case GL_DEBUG_TYPE_PERFORMANCE:
            return "performance";
        default:
            return "other";
    }
}

void APIENTRY on_debug_message(GLenum /*source*/, GLenum type, GLuint id, GLenum severity,
                               GLsizei length, const GLchar* message, const void* /*user*/) {
    if (type != GL_DEBUG_TYPE_ERROR && severity != GL_DEBUG_SEVERITY_HIGH) {
        return;
    }
    DebugLog& log = debug_log;
    if (log.messages.size() >= max_logged_messages) {
        ++log.dropped;
        return;
    }
    std::string text = std::string("debug ") + type_name(type) + " " + std::to_string(id) + ": ";
    if (message != nullptr) {
        text += length >= 0 ? std::string(message, std::size_t(length)) : std::string(message);
    }
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
        text.pop_back();
    }
    log.messages.push_back(std::move(text));
}

}  // namespace

void enable_debug_log() {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(on_debug_message, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr,
                          GL_FALSE);
}

}  // namespace gl_detail

void check_gl_errors(const char* where) {
    std::vector<std::string> found;
    // glGetError returns one flag per call; a context may hold several, and a lost context
    // keeps answering GL_CONTEXT_LOST, hence the bound.
    for (int i = 0; i < 16; ++i) {
        const GLenum code = glGetError();
        if (code == GL_NO_ERROR) {
            break;
        }
        found.push_back(gl_detail::gl_error_name(code));
        if (code == GL_CONTEXT_LOST) {
            break;
        }
    }
    gl_detail::DebugLog& log = gl_detail::debug_log;
    for (std::string& message : log.messages) {
        found.push_back(std::move(message));
    }
    if (log.dropped > 0) {
        found.push_back(std::to_string(log.dropped) + " more debug messages");
    }
    log.messages.clear();
    log.dropped = 0;
    if (found.empty()) {
        return;
    }
    std::string text = std::string(where != nullptr ? where : "?") + ": OpenGL reported ";
    for (std::size_t i = 0; i < found.size(); ++i) {
        text += (i == 0 ? "" : "; ") + found[i];
    }
    throw Error(ErrorKind::Internal, text);
}

}  // namespace oer
