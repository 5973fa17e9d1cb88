// src/gl/composite_context.h — the one EGL context of the process's GPU composites
// (composeGpu()), separate from every backend's render context.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "egl_context.h"
#include "gl_objects.h"
#include "mvr/core/status.h"

namespace mvr::gl::detail {

struct CompositeContext {
    std::unique_ptr<EglContext> context;
    std::map<std::string, Program> programs;  ///< composeGpu(), by fragment source
    /// composeGpu()'s textures, kept for the next call of the same size.
    struct Storage {
        Texture views;  ///< RGBA8 2D array, one layer per view
        int viewsW = 0, viewsH = 0, viewsN = 0;
        Texture target;  ///< RGBA8 tile
        Framebuffer fbo;
        int targetW = 0, targetH = 0;
    } storage;
    VertexArray vao;
    Status status;  ///< why the context could not be made
};

/// Made on first use and deliberately never destroyed: at exit no context may be current, and
/// GL calls from static destructors would then have nothing to run on.
CompositeContext& compositeContext();

/// Held for the whole of every GPU composite (one composite at a time in the process).
std::mutex& compositeMutex();

/// For the duration of one composite: remembers what is current on the calling thread and, on
/// destruction, makes that current again — or nothing, when that was nothing or the composite
/// context itself — so the composite context is never left current on a thread and the next
/// composite may come from any thread. Declare it after taking compositeMutex() and before
/// compositeContext() (whose first call makes the new context current) and before every GL
/// object of the call, so those die while the composite context is still current.
class CompositeScope {
public:
    CompositeScope();
    ~CompositeScope();
    CompositeScope(const CompositeScope&) = delete;
    CompositeScope& operator=(const CompositeScope&) = delete;

private:
    EGLDisplay mDisplay;
    EGLContext mContext;
    EGLSurface mDraw, mRead;
};

}  // namespace mvr::gl::detail
