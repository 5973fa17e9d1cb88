// src/gl/egl_context.h — a headless OpenGL 4.5 core context through EGL + libepoxy.
#pragma once

#include <memory>
#include <string>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include "mvr/core/status.h"

namespace mvr::gl::detail {

/// "EGL_BAD_MATCH" etc. (or "EGL error 0x…" for an unknown code).
std::string eglErrorName(EGLint code);
/// "GL_INVALID_OPERATION" etc.
std::string glErrorName(GLenum code);
/// Drains glGetError(); ok when there was no error, else Internal naming `what` and the codes.
Status checkGlError(const char* what);

/// Owns an EGL display connection and an OpenGL 4.5 core context with no surface.
/// Move-only; the empty state makes no EGL call.
class EglContext {
public:
    EglContext() = default;
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /// Creates the context (see gl_backend.h for the platforms tried) and makes it current.
    /// Errors: Unsupported "no EGL display: …" / "OpenGL 4.5 core context not available: …".
    static Result<std::unique_ptr<EglContext>> create();

    /// Makes this context current on the calling thread (no-op when it already is).
    Status makeCurrent() const;
    /// True when this context is current on the calling thread.
    bool isCurrent() const {
        return mContext != EGL_NO_CONTEXT && eglGetCurrentContext() == mContext;
    }

    const std::string& platform() const { return mPlatform; }  ///< "device (…)" / "surfaceless"
    const std::string& eglVersion() const { return mEglVersion; }
    const std::string& eglVendor() const { return mEglVendor; }

private:
    EGLDisplay mDisplay = EGL_NO_DISPLAY;
    EGLContext mContext = EGL_NO_CONTEXT;
    std::string mPlatform, mEglVersion, mEglVendor;
};

}  // namespace mvr::gl::detail
