// src/gl/gl_objects.h — move-only RAII owners of GL object names. The empty state (name 0)
// makes no GL call; release() hands the name over. Destruction needs the owning context
// current (the backend makes it current before it drops objects).
#pragma once

#include <utility>

#include <epoxy/gl.h>

namespace mvr::gl::detail {

template <void (*Delete)(GLuint)>
class GlHandle {
public:
    GlHandle() = default;
    explicit GlHandle(GLuint name) : mName(name) {}
    ~GlHandle() { reset(); }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;
    GlHandle(GlHandle&& o) noexcept : mName(std::exchange(o.mName, 0)) {}
    GlHandle& operator=(GlHandle&& o) noexcept {
        if (this != &o) {
            reset();
            mName = std::exchange(o.mName, 0);
        }
        return *this;
    }
    GLuint get() const { return mName; }
    explicit operator bool() const { return mName != 0; }
    GLuint release() { return std::exchange(mName, 0); }
    void reset() {
        if (mName) Delete(mName);
        mName = 0;
    }

private:
    GLuint mName = 0;
};

inline void deleteBuffer(GLuint n) { glDeleteBuffers(1, &n); }
inline void deleteVertexArray(GLuint n) { glDeleteVertexArrays(1, &n); }
inline void deleteTexture(GLuint n) { glDeleteTextures(1, &n); }
inline void deleteFramebuffer(GLuint n) { glDeleteFramebuffers(1, &n); }
inline void deleteProgram(GLuint n) { glDeleteProgram(n); }
inline void deleteShader(GLuint n) { glDeleteShader(n); }
inline void deleteQuery(GLuint n) { glDeleteQueries(1, &n); }
inline void deleteSampler(GLuint n) { glDeleteSamplers(1, &n); }

using Buffer = GlHandle<deleteBuffer>;
using VertexArray = GlHandle<deleteVertexArray>;
using Texture = GlHandle<deleteTexture>;
using Framebuffer = GlHandle<deleteFramebuffer>;
using Program = GlHandle<deleteProgram>;
using Shader = GlHandle<deleteShader>;
using Query = GlHandle<deleteQuery>;
using Sampler = GlHandle<deleteSampler>;

inline Buffer createBuffer() {
    GLuint n = 0;
    glCreateBuffers(1, &n);
    return Buffer(n);
}
inline VertexArray createVertexArray() {
    GLuint n = 0;
    glCreateVertexArrays(1, &n);
    return VertexArray(n);
}
inline Texture createTexture(GLenum target) {
    GLuint n = 0;
    glCreateTextures(target, 1, &n);
    return Texture(n);
}
inline Framebuffer createFramebuffer() {
    GLuint n = 0;
    glCreateFramebuffers(1, &n);
    return Framebuffer(n);
}
inline Sampler createSampler() {
    GLuint n = 0;
    glCreateSamplers(1, &n);
    return Sampler(n);
}
inline Query createQuery(GLenum target) {
    GLuint n = 0;
    glCreateQueries(target, 1, &n);
    return Query(n);
}

}  // namespace mvr::gl::detail
