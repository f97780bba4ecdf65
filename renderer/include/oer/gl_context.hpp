#pragma once
// A headless OpenGL 4.5 core context through EGL, with no window system: a GPU through
// EGL_EXT_platform_device first (so an NVIDIA machine uses its GPU with no code change), then
// Mesa's surfaceless platform (llvmpipe on machines without a GPU). Rendering goes to
// framebuffer objects; the context has no default framebuffer.
#include <memory>
#include <string>

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
};

class GlContext {
  public:
    // Creates a context and makes it current on the calling thread. Throws oer::Error (kind
    // Unsupported) listing what each platform attempt answered when none works.
    static std::unique_ptr<GlContext> create();
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    // Makes the context current on the calling thread (a context is current in one thread).
    void make_current();
    const GlInfo& info() const { return info_; }

  private:
    GlContext() = default;
    struct Egl;
    std::unique_ptr<Egl> egl_;
    GlInfo info_;
};

// Drains glGetError and the debug-output log (GL_KHR_debug, enabled by create()); throws
// oer::Error (Internal) naming `where` and every error found.
void check_gl_errors(const char* where);

}  // namespace oer
