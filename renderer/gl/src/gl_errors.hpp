#pragma once
// Private to the GL code: the debug-output log behind check_gl_errors (oer/gl_context.hpp).
//
// GL_KHR_debug messages arrive, synchronously, on the thread that made the failing call;
// those that report an error (type GL_DEBUG_TYPE_ERROR, or severity GL_DEBUG_SEVERITY_HIGH)
// are kept in a log of that thread, until check_gl_errors drains it.

namespace oer::gl_detail {

// Enables synchronous debug output on the current context, with the logging callback; quiet
// notifications are filtered out in the driver.
void enable_debug_log();

}  // namespace oer::gl_detail
