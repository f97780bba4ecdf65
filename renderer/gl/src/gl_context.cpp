// The headless EGL context (see oer/gl_context.hpp). Platforms are tried in this order:
//  1. EGL_EXT_platform_device, hardware devices only (a device that announces
//     EGL_MESA_device_software is kept for step 3), so a GPU wins wherever there is one;
//  2. Mesa's EGL_PLATFORM_SURFACELESS_MESA (llvmpipe on machines without a GPU);
//  3. the software devices of step 1.
// Each attempt either gives a current OpenGL >= 4.5 core context or one line saying why not.
#include "oer/gl/gl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "egl_display_registry.hpp"
#include "egl_errors.hpp"
#include "gl_errors.hpp"
#include "oer/core/error.hpp"

namespace oer {

using egl_detail::last_egl_error;

struct GlContext::Egl {
    EGLDisplay display = EGL_NO_DISPLAY;  // initialised for the life of the process
    EGLContext context = EGL_NO_CONTEXT;
};

namespace {

constexpr int required_major = 4;
constexpr int required_minor = 5;

bool has_extension(const char* list, std::string_view name) {
    if (list == nullptr) {
        return false;
    }
    std::string_view rest(list);
    while (!rest.empty()) {
        const std::size_t start = rest.find_first_not_of(' ');
        if (start == std::string_view::npos) {
            break;
        }
        rest.remove_prefix(start);
        const std::size_t end = std::min(rest.find(' '), rest.size());
        if (rest.substr(0, end) == name) {
            return true;
        }
        rest.remove_prefix(end);
    }
    return false;
}

std::string egl_string(EGLDisplay display, EGLint name) {
    const char* value = eglQueryString(display, name);
    return value != nullptr ? value : "";
}

std::string gl_string(GLenum name) {
    const auto* value = reinterpret_cast<const char*>(glGetString(name));
    return value != nullptr ? value : "";
}

// The client entry points of the extensions used here (eglGetProcAddress: they need not be
// exported by libEGL).
struct ClientEgl {
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = nullptr;
    PFNEGLQUERYDEVICESEXTPROC query_devices = nullptr;
    PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string = nullptr;
    bool platform_device = false;
    bool platform_surfaceless = false;

    ClientEgl() {
        // EGL_NO_DISPLAY: the client extensions (EGL_EXT_client_extensions).
        const char* extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (extensions == nullptr) {
            eglGetError();  // EGL_BAD_DISPLAY without EGL_EXT_client_extensions: none
            return;
        }
        if (has_extension(extensions, "EGL_EXT_platform_base")) {
            get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
                eglGetProcAddress("eglGetPlatformDisplayEXT"));
        }
        if (has_extension(extensions, "EGL_EXT_device_enumeration") ||
            has_extension(extensions, "EGL_EXT_device_base")) {
            query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(
                eglGetProcAddress("eglQueryDevicesEXT"));
        }
        if (has_extension(extensions, "EGL_EXT_device_query") ||
            has_extension(extensions, "EGL_EXT_device_base")) {
            query_device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
                eglGetProcAddress("eglQueryDeviceStringEXT"));
        }
        platform_device = get_platform_display != nullptr && query_devices != nullptr &&
                          has_extension(extensions, "EGL_EXT_platform_device");
        platform_surfaceless = get_platform_display != nullptr &&
                               has_extension(extensions, "EGL_MESA_platform_surfaceless");
    }
};

struct Device {
    EGLDeviceEXT handle;
    std::string label;  // "device 0 (/dev/dri/renderD128)"
    bool software;
};

std::vector<Device> list_devices(const ClientEgl& client, std::string& error) {
    EGLint count = 0;
    if (!client.query_devices(0, nullptr, &count)) {
        error = "eglQueryDevicesEXT: " + last_egl_error();
        return {};
    }
    std::vector<EGLDeviceEXT> handles(std::size_t(count > 0 ? count : 0));
    if (count > 0 && !client.query_devices(count, handles.data(), &count)) {
        error = "eglQueryDevicesEXT: " + last_egl_error();
        return {};
    }
    handles.resize(std::size_t(count));
    std::vector<Device> devices;
    for (std::size_t i = 0; i < handles.size(); ++i) {
        Device device{handles[i], "device " + std::to_string(i), false};
        if (client.query_device_string != nullptr) {
            const char* extensions = client.query_device_string(handles[i], EGL_EXTENSIONS);
            device.software = has_extension(extensions, "EGL_MESA_device_software");
            const char* file = nullptr;
            if (has_extension(extensions, "EGL_EXT_device_drm_render_node")) {
                file = client.query_device_string(handles[i], EGL_DRM_RENDER_NODE_FILE_EXT);
            }
            if (file == nullptr && has_extension(extensions, "EGL_EXT_device_drm")) {
                file = client.query_device_string(handles[i], EGL_DRM_DEVICE_FILE_EXT);
            }
            eglGetError();  // a device without a node answers EGL_BAD_PARAMETER or the like
            if (file != nullptr) {
                device.label += std::string(" (") + file + ")";
            } else if (device.software) {
                device.label += " (software)";
            }
        }
        devices.push_back(std::move(device));
    }
    return devices;
}

// Context attributes: OpenGL 4.5 core, with the debug flag first and without it second.
std::vector<EGLint> context_attributes(bool debug) {
    std::vector<EGLint> attributes = {
        EGL_CONTEXT_MAJOR_VERSION,       required_major,
        EGL_CONTEXT_MINOR_VERSION,       required_minor,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (debug) {
        attributes.push_back(EGL_CONTEXT_OPENGL_DEBUG);
        attributes.push_back(EGL_TRUE);
    }
    attributes.push_back(EGL_NONE);
    return attributes;
}

std::optional<EGLConfig> choose_config(EGLDisplay display, std::string& error) {
    // Pbuffer-capable first (every headless driver has those); then any surface type, since
    // only framebuffer objects are drawn to.
    for (const EGLint surface_type : {EGLint(EGL_PBUFFER_BIT), EGLint(0)}) {
        const EGLint attributes[] = {EGL_SURFACE_TYPE,
                                     surface_type,
                                     EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (!eglChooseConfig(display, attributes, &config, 1, &count)) {
            error = "eglChooseConfig: " + last_egl_error();
            return std::nullopt;
        }
        if (count > 0) {
            return config;
        }
    }
    error = "no EGLConfig renders desktop OpenGL (EGL_OPENGL_BIT)";
    return std::nullopt;
}

struct Created {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string egl_vendor, egl_version;
};

// One platform attempt: a current OpenGL >= 4.5 core context on the display that platform and
// native give, or nullopt and the reason in `error`.
std::optional<Created> try_platform(const ClientEgl& client, EGLenum platform, void* native,
                                    std::string& error) {
    const EGLDisplay display = client.get_platform_display(platform, native, nullptr);
    if (display == EGL_NO_DISPLAY) {
        error = "eglGetPlatformDisplayEXT: " + last_egl_error();
        return std::nullopt;
    }
    if (!egl_detail::initialise_display(display, error)) {
        return std::nullopt;
    }
    Created created;
    created.display = display;
    const std::string extensions = egl_string(display, EGL_EXTENSIONS);

    if (!eglBindAPI(EGL_OPENGL_API)) {
        error = "eglBindAPI(EGL_OPENGL_API): " + last_egl_error();
        return std::nullopt;
    }
    const std::optional<EGLConfig> config = choose_config(display, error);
    if (!config) {
        return std::nullopt;
    }
    std::string debug_error;
    for (const bool debug : {true, false}) {
        const std::vector<EGLint> attributes = context_attributes(debug);
        created.context = eglCreateContext(display, *config, EGL_NO_CONTEXT, attributes.data());
        if (created.context != EGL_NO_CONTEXT) {
            break;
        }
        if (debug) {
            debug_error = last_egl_error();
        }
    }
    if (created.context == EGL_NO_CONTEXT) {
        error = "eglCreateContext(OpenGL 4.5 core): " + last_egl_error() +
                " (with the debug flag: " + debug_error + ")";
        return std::nullopt;
    }
    // From here on, a failure destroys the context.
    struct DestroyOnFailure {
        Created* created;
        ~DestroyOnFailure() {
            if (created != nullptr) {
                if (eglGetCurrentContext() == created->context) {
                    eglMakeCurrent(created->display, EGL_NO_SURFACE, EGL_NO_SURFACE,
                                   EGL_NO_CONTEXT);
                }
                eglDestroyContext(created->display, created->context);
            }
        }
    } guard{&created};

    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, created.context)) {
        error = "eglMakeCurrent(no surface): " + last_egl_error();
        if (!has_extension(extensions.c_str(), "EGL_KHR_surfaceless_context")) {
            error += " (the display lacks EGL_KHR_surfaceless_context)";
        }
        return std::nullopt;
    }
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < required_major || (major == required_major && minor < required_minor)) {
        error = "OpenGL " + std::to_string(major) + "." + std::to_string(minor) + " (" +
                gl_string(GL_RENDERER) + "), 4.5 is needed";
        return std::nullopt;
    }
    // Prefiltered cube maps (the specular lighting) are filtered across their faces' edges.
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    guard.created = nullptr;
    created.egl_vendor = egl_string(display, EGL_VENDOR);
    created.egl_version = egl_string(display, EGL_VERSION);
    return created;
}

}  // namespace

std::unique_ptr<GlContext> GlContext::create() {
    const ClientEgl client;
    std::vector<std::string> attempts;
    std::optional<Created> created;
    std::string platform;

    std::vector<Device> software;
    if (!client.platform_device) {
        attempts.push_back("device platform: the EGL client lacks EGL_EXT_platform_device");
    } else {
        std::string list_error;
        const std::vector<Device> devices = list_devices(client, list_error);
        if (!list_error.empty()) {
            attempts.push_back("device platform: " + list_error);
        }
        for (const Device& device : devices) {
            if (device.software) {
                software.push_back(device);
                continue;
            }
            std::string error;
            created = try_platform(client, EGL_PLATFORM_DEVICE_EXT, device.handle, error);
            if (created) {
                platform = "device";
                break;
            }
            attempts.push_back("device platform, " + device.label + ": " + error);
        }
        if (list_error.empty() && devices.empty()) {
            attempts.push_back("device platform: no device");
        } else if (list_error.empty() && software.size() == devices.size()) {
            attempts.push_back("device platform: no hardware device (" +
                               std::to_string(software.size()) +
                               " software device(s), kept for last)");
        }
    }
    if (!created) {
        if (!client.platform_surfaceless) {
            attempts.push_back(
                "surfaceless platform: the EGL client lacks EGL_MESA_platform_surfaceless");
        } else {
            std::string error;
            created =
                try_platform(client, EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, error);
            if (created) {
                platform = "surfaceless";
            } else {
                attempts.push_back("surfaceless platform: " + error);
            }
        }
    }
    for (std::size_t i = 0; !created && i < software.size(); ++i) {
        std::string error;
        created = try_platform(client, EGL_PLATFORM_DEVICE_EXT, software[i].handle, error);
        if (created) {
            platform = "device";
        } else {
            attempts.push_back("device platform, " + software[i].label + ": " + error);
        }
    }
    if (!created) {
        std::string text = "no headless OpenGL 4.5 core context through EGL: ";
        for (std::size_t i = 0; i < attempts.size(); ++i) {
            text += (i == 0 ? "" : "; ") + attempts[i];
        }
        throw Error(ErrorKind::Unsupported, text);
    }

    std::unique_ptr<GlContext> context(new GlContext);
    context->egl_ = std::make_unique<Egl>();
    context->egl_->display = created->display;
    context->egl_->context = created->context;
    gl_detail::enable_debug_log();
    GlInfo& info = context->info_;
    info.platform = platform;
    info.egl_vendor = created->egl_vendor;
    info.egl_version = created->egl_version;
    info.vendor = gl_string(GL_VENDOR);
    info.renderer = gl_string(GL_RENDERER);
    info.version = gl_string(GL_VERSION);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &info.max_texture_size);
    glGetIntegerv(GL_MAX_SAMPLES, &info.max_samples);
    info.attempts = std::move(attempts);
    check_gl_errors("GlContext::create");
    return context;
}

GlContext::~GlContext() {
    if (!egl_ || egl_->context == EGL_NO_CONTEXT) {
        return;
    }
    const EGLDisplay display = egl_->display;
    if (eglGetCurrentContext() == egl_->context) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        // Nothing else is current on this thread: its EGL state can go as well.
        if (eglGetCurrentContext() == EGL_NO_CONTEXT) {
            eglReleaseThread();
        }
    }
    eglDestroyContext(display, egl_->context);
    egl_->context = EGL_NO_CONTEXT;
    // The display stays initialised for the next context (egl_display_registry.hpp).
}

void GlContext::make_current() {
    if (!eglMakeCurrent(egl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_->context)) {
        const std::string error = last_egl_error();
        throw Error(
            ErrorKind::Internal,
            "GlContext::make_current: eglMakeCurrent: " + error +
                (error == "EGL_BAD_ACCESS" ? " (the context is current in another thread)" : ""));
    }
}

}  // namespace oer
