#include "egl_display_registry.hpp"

#include <mutex>
#include <set>

#include "egl_errors.hpp"

namespace oer::egl_detail {

namespace {

struct Registry {
    std::mutex mutex;
    std::set<EGLDisplay> initialised;
};

// Never destroyed: contexts owned by static objects may outlive every other static.
Registry& registry() {
    static Registry* const instance = new Registry;
    return *instance;
}

}  // namespace

bool initialise_display(EGLDisplay display, std::string& error) {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    if (r.initialised.count(display) != 0) {
        return true;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        error = "eglInitialize: " + last_egl_error();
        return false;
    }
    r.initialised.insert(display);
    return true;
}

}  // namespace oer::egl_detail
