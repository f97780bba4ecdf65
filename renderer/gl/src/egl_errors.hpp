#pragma once
// Private to the EGL code: EGL error codes by name, for messages ("EGL_BAD_MATCH", not 12297).
#include <EGL/egl.h>

#include <string>

namespace oer::egl_detail {

// "EGL_BAD_MATCH"; an unknown code as "EGL error 0x3100".
std::string egl_error_name(EGLint code);

// The error of the last EGL call on this thread, by name (eglGetError, which also clears it).
inline std::string last_egl_error() {
    return egl_error_name(eglGetError());
}

}  // namespace oer::egl_detail
