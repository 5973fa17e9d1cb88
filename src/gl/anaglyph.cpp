// The red-cyan anaglyph composed on the GPU, as sorbier2008 §4.3 lists it: depth test off,
// additive blending, colour mask red + full-screen quad of the left image, colour mask
// green/blue + full-screen quad of the right image.
#include <cstring>
#include <map>
#include <mutex>

#include <fmt/format.h>

#include "composite_context.h"
#include "egl_context.h"
#include "gl_objects.h"
#include "mvr/gl/gl_backend.h"
#include "shaders.h"

namespace mvr::gl {

namespace {

using detail::CompositeContext;
using detail::compositeContext;
using detail::compositeMutex;

detail::Texture upload(const Image& img) {
    detail::Texture t = detail::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), 1, GL_RGBA8, img.width, img.height);
    // Image row 0 goes to texture row 0 and the result is read back without a flip, so the
    // orientation is kept end to end.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t.get(), 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE,
                        img.rgba.data());
    return t;
}

}  // namespace

namespace {

Status validatePair(const Image& left, const Image& right) {
    if (left.empty() || right.empty()) {
        return usageError("mvr::gl::composeAnaglyphGpu(): empty input image");
    }
    if (left.width != right.width || left.height != right.height) {
        return usageError(fmt::format(
            "mvr::gl::composeAnaglyphGpu(): left is {}x{}, right is {}x{} (expected the same size)",
            left.width, left.height, right.width, right.height));
    }
    const std::size_t bytes = static_cast<std::size_t>(left.width) * left.height * 4;
    if (left.rgba.size() != bytes || right.rgba.size() != bytes) {
        return usageError("mvr::gl::composeAnaglyphGpu(): pixel buffer size does not match "
                          "width x height x 4");
    }
    return Status::ok();
}

// Makes the composite context current and checks the size against the driver.
Status prepare(CompositeContext& c, const Image& left) {
    if (!c.status) return c.status;
    if (Status s = c.context->makeCurrent(); !s) return s;
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    if (left.width > maxSize || left.height > maxSize) {
        return unsupportedError(fmt::format(
            "mvr::gl::composeAnaglyphGpu(): {}x{} exceeds GL_MAX_TEXTURE_SIZE = {}", left.width,
            left.height, maxSize));
    }
    return Status::ok();
}

/// An RGBA8 texture of the composite's size behind a framebuffer, bound for drawing over its
/// whole area with depth test and culling off: the target of both anaglyph passes.
struct OutputTarget {
    detail::Texture texture;
    detail::Framebuffer fbo;
};

OutputTarget bindOutputTarget(int w, int h) {
    OutputTarget t{detail::createTexture(GL_TEXTURE_2D), detail::createFramebuffer()};
    glTextureStorage2D(t.texture.get(), 1, GL_RGBA8, w, h);
    glNamedFramebufferTexture(t.fbo.get(), GL_COLOR_ATTACHMENT0, t.texture.get(), 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.fbo.get());
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    return t;
}

Image readTarget(GLuint target, int w, int h) {
    Image out(w, h);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(target, 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(out.rgba.size()),
                      out.rgba.data());
    return out;
}

}  // namespace

Result<Image> composeAnaglyphGpu(const Image& left, const Image& right) {
    if (Status s = validatePair(left, right); !s) return s;
    std::lock_guard lock(compositeMutex());
    detail::CompositeScope scope;  // the composite context is current only during the call
    CompositeContext& c = compositeContext();
    if (Status s = prepare(c, left); !s) return s;

    detail::Texture texLeft = upload(left), texRight = upload(right);
    const OutputTarget out = bindOutputTarget(left.width, left.height);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);  // additive
    glUseProgram(c.program.get());
    glBindVertexArray(c.vao.get());
    glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_FALSE);  // red from the left eye
    glBindTextureUnit(0, texLeft.get());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glColorMask(GL_FALSE, GL_TRUE, GL_TRUE, GL_FALSE);   // cyan from the right eye
    glBindTextureUnit(0, texRight.get());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_BLEND);

    Image image = readTarget(out.texture.get(), left.width, left.height);
    glBindTextureUnit(0, 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    if (Status s = detail::checkGlError("composeAnaglyphGpu"); !s) return s;
    return image;
}

Result<Image> composeAnaglyphGpu(const Image& left, const Image& right,
                                 const std::string& glslMix) {
    if (Status s = validatePair(left, right); !s) return s;
    std::lock_guard lock(compositeMutex());
    detail::CompositeScope scope;  // the composite context is current only during the call
    CompositeContext& c = compositeContext();
    if (Status s = prepare(c, left); !s) return s;
    auto it = c.mixPrograms.find(glslMix);
    if (it == c.mixPrograms.end()) {
        auto p = detail::buildMixProgram(glslMix);
        if (!p) {
            return usageError("mvr::gl::composeAnaglyphGpu(): the mix GLSL does not build: " +
                              p.status().message());
        }
        it = c.mixPrograms.emplace(glslMix, std::move(p).value()).first;
    }
    detail::Texture texLeft = upload(left), texRight = upload(right);
    const OutputTarget out = bindOutputTarget(left.width, left.height);
    glDisable(GL_BLEND);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(it->second.get());
    glBindVertexArray(c.vao.get());
    glBindTextureUnit(0, texLeft.get());
    glBindTextureUnit(1, texRight.get());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    Image image = readTarget(out.texture.get(), left.width, left.height);
    glBindTextureUnit(0, 0);
    glBindTextureUnit(1, 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    if (Status s = detail::checkGlError("composeAnaglyphGpu"); !s) return s;
    return image;
}

}  // namespace mvr::gl
