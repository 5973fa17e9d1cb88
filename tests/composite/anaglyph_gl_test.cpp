// The GPU anaglyph must equal the CPU one within rounding: anaglyphGlsl() compiled on whatever
// GL the machine has (Mesa llvmpipe on CPU-only machines) against anaglyphPixel().
// Skips itself when no EGL display / GL 4.5 context can be made.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "mvr/composite/anaglyph.h"

namespace mvr::composite {
namespace {

class AnaglyphGl : public ::testing::Test {
protected:
    void SetUp() override {
        mDisplay =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (mDisplay == EGL_NO_DISPLAY || !eglInitialize(mDisplay, nullptr, nullptr))
            GTEST_SKIP() << "no EGL display: EGL error 0x" << std::hex << eglGetError();
        eglBindAPI(EGL_OPENGL_API);
        const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                     4,
                                     EGL_CONTEXT_MINOR_VERSION,
                                     5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
        mContext = eglCreateContext(mDisplay, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
        if (mContext == EGL_NO_CONTEXT ||
            !eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext))
            GTEST_SKIP() << "no surfaceless GL 4.5 core context: EGL error 0x" << std::hex
                         << eglGetError();
    }
    void TearDown() override {
        if (mContext != EGL_NO_CONTEXT) {
            eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(mDisplay, mContext);
        }
        if (mDisplay != EGL_NO_DISPLAY) eglTerminate(mDisplay);
    }

    static GLuint compile(GLenum stage, const std::string& source, std::string& log) {
        const GLuint shader = glCreateShader(stage);
        const char* text = source.c_str();
        glShaderSource(shader, 1, &text, nullptr);
        glCompileShader(shader);
        GLint ok = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char buffer[4096] = {};
            glGetShaderInfoLog(shader, sizeof buffer, nullptr, buffer);
            log = buffer;
        }
        return shader;
    }

    EGLDisplay mDisplay = EGL_NO_DISPLAY;
    EGLContext mContext = EGL_NO_CONTEXT;
};

TEST_F(AnaglyphGl, MatchesTheCpuAnaglyphForEveryMethod) {
    constexpr int kW = 64, kH = 64;
    std::vector<std::uint8_t> left(kW * kH * 4), right(kW * kH * 4);
    for (int i = 0; i < kW * kH; ++i)
        for (int c = 0; c < 4; ++c) {
            left[i * 4 + c] = static_cast<std::uint8_t>(i * 7 + c * 91);
            right[i * 4 + c] = static_cast<std::uint8_t>(i * 13 + c * 37 + 5);
        }
    GLuint textures[3];
    glGenTextures(3, textures);
    for (int t = 0; t < 2; ++t) {
        glBindTexture(GL_TEXTURE_2D, textures[t]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, kW, kH);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kW, kH, GL_RGBA, GL_UNSIGNED_BYTE,
                        t == 0 ? left.data() : right.data());
    }
    glBindTexture(GL_TEXTURE_2D, textures[2]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, kW, kH);
    GLuint fbo = 0, vao = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, textures[2], 0);
    ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glViewport(0, 0, kW, kH);
    glBindTextureUnit(0, textures[0]);
    glBindTextureUnit(1, textures[1]);

    const std::string vertex = R"glsl(#version 450 core
void main() {
    vec2 p = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
}
)glsl";
    const AnaglyphMethod methods[] = {
        AnaglyphMethod::Color,          AnaglyphMethod::HalfColor,
        AnaglyphMethod::Gray,           AnaglyphMethod::True,
        AnaglyphMethod::Dubois,         AnaglyphMethod::DuboisGreenMagenta,
        AnaglyphMethod::DuboisAmberBlue};
    for (AnaglyphMethod method : methods) {
        const std::string fragment = "#version 450 core\n" + anaglyphGlsl(method) +
                                     R"glsl(layout(binding = 0) uniform sampler2D uLeft;
layout(binding = 1) uniform sampler2D uRight;
out vec4 oColor;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    oColor = vec4(mvrAnaglyph(texelFetch(uLeft, p, 0).rgb, texelFetch(uRight, p, 0).rgb), 1.0);
}
)glsl";
        std::string log;
        const GLuint vs = compile(GL_VERTEX_SHADER, vertex, log);
        const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, log);
        ASSERT_TRUE(log.empty()) << log << "\n" << fragment;
        const GLuint program = glCreateProgram();
        glAttachShader(program, vs);
        glAttachShader(program, fs);
        glLinkProgram(program);
        GLint linked = 0;
        glGetProgramiv(program, GL_LINK_STATUS, &linked);
        ASSERT_TRUE(linked);
        glUseProgram(program);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        std::vector<std::uint8_t> gpu(kW * kH * 4);
        glReadPixels(0, 0, kW, kH, GL_RGBA, GL_UNSIGNED_BYTE, gpu.data());
        ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        int worst = 0;
        for (int i = 0; i < kW * kH; ++i) {
            const Rgba8 cpu =
                anaglyphPixel(anaglyphMatrices(method),
                              {left[i * 4], left[i * 4 + 1], left[i * 4 + 2], left[i * 4 + 3]},
                              {right[i * 4], right[i * 4 + 1], right[i * 4 + 2], right[i * 4 + 3]});
            worst = std::max({worst, std::abs(cpu.r - gpu[i * 4]), std::abs(cpu.g - gpu[i * 4 + 1]),
                              std::abs(cpu.b - gpu[i * 4 + 2])});
        }
        // One step: float pow() of a GPU and of the CPU may round to the two sides of a code.
        EXPECT_LE(worst, 1) << "method " << static_cast<int>(method) << " on "
                            << reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        glDeleteProgram(program);
        glDeleteShader(vs);
        glDeleteShader(fs);
    }
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(3, textures);
}

}  // namespace
}  // namespace mvr::composite
