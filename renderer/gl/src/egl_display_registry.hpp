#pragma once
// Private to the EGL code: the EGL displays this process has initialised.
//
// EGL returns the same EGLDisplay for the same platform and device, and eglTerminate is not
// reference counted (EGL 1.5 without EGL_KHR_display_reference): one eglTerminate would end
// the display under every other context on it. So a display is initialised once, the first
// time a context needs it, and stays initialised until the process exits; contexts come and
// go on it in any order, on any thread.
//
// Why never terminate rather than count references and terminate with the last context:
// Mesa's eglTerminate unloads the driver (swrast_dri.so, with LLVM), and loading it again for
// the next context costs time; memory then owned only by the unloaded driver's statics is
// reported by LeakSanitizer as leaks of an unknown module, which no suppression can name. An
// idle initialised display holds the driver's screen, not a context's buffers or threads.
#include <EGL/egl.h>

#include <string>

namespace oer::egl_detail {

// Initialises display unless this process already has: true when it is ready to use; false,
// with the reason in `error` ("eglInitialize: EGL_NOT_INITIALIZED"), otherwise.
bool initialise_display(EGLDisplay display, std::string& error);

}  // namespace oer::egl_detail
