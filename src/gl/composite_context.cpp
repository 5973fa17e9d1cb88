#include "composite_context.h"

namespace mvr::gl::detail {

CompositeContext& compositeContext() {
    static CompositeContext& c = *[] {
        auto* ccp = new CompositeContext;
        CompositeContext& cc = *ccp;
        auto ctx = EglContext::create();
        if (!ctx) {
            cc.status = ctx.status();
            return ccp;
        }
        cc.context = std::move(ctx).value();
        cc.vao = createVertexArray();
        return ccp;
    }();
    return c;
}

std::mutex& compositeMutex() {
    static std::mutex m;
    return m;
}

CompositeScope::CompositeScope()
    : mDisplay(eglGetCurrentDisplay()),
      mContext(eglGetCurrentContext()),
      mDraw(eglGetCurrentSurface(EGL_DRAW)),
      mRead(eglGetCurrentSurface(EGL_READ)) {}

CompositeScope::~CompositeScope() {
    const CompositeContext& cc = compositeContext();
    if (!cc.context || !cc.context->isCurrent()) return;  // never made current: nothing to undo
    const EGLContext now = eglGetCurrentContext();
    if (mContext != EGL_NO_CONTEXT && mContext != now) {
        eglMakeCurrent(mDisplay, mDraw, mRead, mContext);  // what the caller had
    } else {
        // Nothing before, or the composite context itself (left current by an earlier call).
        eglMakeCurrent(eglGetCurrentDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
}

}  // namespace mvr::gl::detail
