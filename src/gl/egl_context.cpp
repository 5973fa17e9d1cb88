#include "egl_context.h"

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include <fmt/format.h>

namespace mvr::gl::detail {

std::string eglErrorName(EGLint code) {
    switch (code) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
        default: return fmt::format("EGL error 0x{:04X}", static_cast<unsigned>(code));
    }
}

std::string glErrorName(GLenum code) {
    switch (code) {
        case GL_NO_ERROR: return "GL_NO_ERROR";
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
        case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
        case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
        default: return fmt::format("GL error 0x{:04X}", code);
    }
}

Status checkGlError(const char* what) {
    std::string names;
    for (int i = 0; i < 8; ++i) {  // bounded: a lost context may report errors forever
        const GLenum e = glGetError();
        if (e == GL_NO_ERROR) break;
        names += (names.empty() ? "" : ", ") + glErrorName(e);
    }
    if (names.empty()) return Status::ok();
    return internalError(fmt::format("mvr::gl: {}: {}", what, names));
}

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
        const bool startOk = p == list || p[-1] == ' ';
        const bool endOk = p[n] == ' ' || p[n] == '\0';
        if (startOk && endOk) return true;
    }
    return false;
}

struct Candidate {
    EGLDisplay display;
    std::string platform;
};

}  // namespace

EglContext::~EglContext() {
    if (mContext != EGL_NO_CONTEXT) {
        if (eglGetCurrentContext() == mContext) {
            eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(mDisplay, mContext);
    }
    // No eglTerminate(): EGL displays are shared per platform within the process, and other
    // contexts (other backends, the GPU composite) may still live on the same display.
}

Result<std::unique_ptr<EglContext>> EglContext::create() {
    const char* forced = std::getenv("MVR_EGL_PLATFORM");
    const std::string force = forced ? forced : "";
    if (!force.empty() && force != "device" && force != "surfaceless" && force != "default") {
        return usageError(fmt::format(
            "mvr::gl: MVR_EGL_PLATFORM={}: expected device, surfaceless or default", force));
    }
    const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool platformBase = hasExtension(clientExt, "EGL_EXT_platform_base");

    std::vector<Candidate> candidates;
    if ((force.empty() || force == "device") && platformBase &&
        hasExtension(clientExt, "EGL_EXT_platform_device") &&
        hasExtension(clientExt, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (eglQueryDevicesEXT(16, devices, &count)) {
            for (EGLint i = 0; i < count; ++i) {
                const char* devExt = hasExtension(clientExt, "EGL_EXT_device_query")
                                         ? eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS)
                                         : nullptr;
                // A software device is llvmpipe again: leave it to the surfaceless platform
                // unless the device platform was forced.
                if (force.empty() && hasExtension(devExt, "EGL_MESA_device_software")) continue;
                EGLDisplay d =
                    eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                if (d != EGL_NO_DISPLAY) candidates.push_back({d, fmt::format("device {}", i)});
            }
        }
    }
    if ((force.empty() || force == "surfaceless") && platformBase &&
        hasExtension(clientExt, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d != EGL_NO_DISPLAY) candidates.push_back({d, "surfaceless"});
    }
    if (force == "default" || (force.empty() && candidates.empty())) {
        EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        if (d != EGL_NO_DISPLAY) candidates.push_back({d, "default"});
    }
    if (candidates.empty()) {
        return unsupportedError(fmt::format("no EGL display: {} (client extensions: {})",
                                            eglErrorName(eglGetError()),
                                            clientExt && *clientExt ? clientExt : "none"));
    }

    std::string failures;
    for (const Candidate& c : candidates) {
        EGLint major = 0, minor = 0;
        if (!eglInitialize(c.display, &major, &minor)) {
            failures +=
                fmt::format("; {}: eglInitialize: {}", c.platform, eglErrorName(eglGetError()));
            continue;
        }
        const char* dpyExt = eglQueryString(c.display, EGL_EXTENSIONS);
        if (!eglBindAPI(EGL_OPENGL_API)) {
            failures += fmt::format("; {}: eglBindAPI(EGL_OPENGL_API): {}", c.platform,
                                    eglErrorName(eglGetError()));
            continue;
        }
        EGLConfig config = nullptr;
        const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                        EGL_OPENGL_BIT, EGL_NONE};
        EGLint numConfigs = 0;
        if (!eglChooseConfig(c.display, configAttribs, &config, 1, &numConfigs) || numConfigs < 1) {
            if (!hasExtension(dpyExt, "EGL_KHR_no_config_context")) {
                failures += fmt::format("; {}: no OpenGL config: {}", c.platform,
                                        eglErrorName(eglGetError()));
                continue;
            }
            config = nullptr;  // EGL_NO_CONFIG_KHR
        }
        const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         4,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         5,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
        EGLContext ctx = eglCreateContext(c.display, config, EGL_NO_CONTEXT, contextAttribs);
        if (ctx == EGL_NO_CONTEXT) {
            failures += fmt::format("; {}: OpenGL 4.5 core context not available: {}", c.platform,
                                    eglErrorName(eglGetError()));
            continue;
        }
        if (!hasExtension(dpyExt, "EGL_KHR_surfaceless_context") ||
            !eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
            failures += fmt::format("; {}: cannot make the context current without a surface: {}",
                                    c.platform, eglErrorName(eglGetError()));
            eglDestroyContext(c.display, ctx);
            continue;
        }
        auto out = std::make_unique<EglContext>();
        out->mDisplay = c.display;
        out->mContext = ctx;
        out->mPlatform = c.platform;
        const char* v = eglQueryString(c.display, EGL_VERSION);
        const char* vendor = eglQueryString(c.display, EGL_VENDOR);
        out->mEglVersion = v ? v : fmt::format("{}.{}", major, minor);
        out->mEglVendor = vendor ? vendor : "?";
        return out;
    }
    return unsupportedError("no EGL display: no platform gave an OpenGL 4.5 core context" +
                            failures);
}

Status EglContext::makeCurrent() const {
    if (mContext == EGL_NO_CONTEXT) return internalError("mvr::gl: no EGL context");
    if (eglGetCurrentContext() == mContext) return Status::ok();
    if (!eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext)) {
        return internalError(
            fmt::format("mvr::gl: eglMakeCurrent: {}", eglErrorName(eglGetError())));
    }
    return Status::ok();
}

}  // namespace mvr::gl::detail
