#pragma once
// A headless OpenGL 4.5 core context through EGL, with no window system: a GPU through
// EGL_EXT_platform_device first (so an NVIDIA machine uses its GPU with no code change), then
// Mesa's surfaceless platform (llvmpipe on machines without a GPU), then, as a last resort, a
// software device of EGL_EXT_platform_device. Rendering goes to framebuffer objects; the
// context has no default framebuffer (it is made current with no surface).
//
// Contexts on one EGL display share it: the display is initialised by the first context and
// stays initialised until the process exits (eglTerminate is not reference counted), so that
// any number of contexts can be created and destroyed in any order, on any threads.
#include <memory>
#include <string>
#include <vector>

namespace oer {

struct GlInfo {
    std::string platform;     // "device" or "surfaceless"
    std::string egl_vendor;   // EGL_VENDOR
    std::string egl_version;  // EGL_VERSION
    std::string vendor;       // GL_VENDOR
    std::string renderer;     // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version;      // GL_VERSION
    int max_texture_size = 0;
    int max_samples = 0;
    // What each platform tried before the one chosen answered, in order, e.g.
    // "device platform: no hardware device (1 software device(s), kept for last)".
    std::vector<std::string> attempts;
};

class GlContext {
  public:
    // Creates a context and makes it current on the calling thread. Throws oer::Error (kind
    // Unsupported) listing what each platform attempt answered when none works.
    static std::unique_ptr<GlContext> create();
    // Releases the context from the calling thread if it is current there, and destroys it.
    // Destroy it on the thread where it is current (or on any thread when it is current
    // nowhere).
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    // Makes the context current on the calling thread (a context is current in one thread:
    // throws oer::Error (Internal) if it is current in another one).
    void make_current();
    const GlInfo& info() const { return info_; }

  private:
    GlContext() = default;
    struct Egl;
    std::unique_ptr<Egl> egl_;
    GlInfo info_;
};

// Drains glGetError and the debug-output log of the calling thread (GL_KHR_debug, enabled by
// create(): messages of type error or of high severity); throws oer::Error (Internal) naming
// `where` and every error found, e.g. "upload mesh: OpenGL reported GL_INVALID_ENUM; debug
// error 1: GL_INVALID_ENUM in glBindTexture(target)".
void check_gl_errors(const char* where);

}  // namespace oer
