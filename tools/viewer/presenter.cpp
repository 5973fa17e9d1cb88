#include "presenter.h"

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/core.h>

namespace mvr::viewer {
namespace {

const char* const kPresentVs = R"(#version 330 core
void main() {
    // One triangle covering the viewport.
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// Pixel (x, y) of the window shows texel (x − offset.x, fbHeight − 1 − y − offset.y): the image
// is uploaded row 0 first (its TOP row, image.h) and drawn 1:1 with its top-left corner at
// `offset` from the window's top-left; outside it, black.
const char* const kPresentFs = R"(#version 330 core
uniform sampler2D uImage;
uniform ivec2 uOffset;
uniform int uFbHeight;
out vec4 oColor;
void main() {
    ivec2 p = ivec2(int(gl_FragCoord.x), uFbHeight - 1 - int(gl_FragCoord.y)) - uOffset;
    ivec2 size = textureSize(uImage, 0);
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) {
        oColor = vec4(0.0, 0.0, 0.0, 1.0);
    } else {
        oColor = vec4(texelFetch(uImage, p, 0).rgb, 1.0);
    }
}
)";

// The GPU composite of the anaglyphs: the two eyes as two textures mixed per pixel by
// composite::anaglyphGlsl(method), the same formula as the CPU composite (within 1/255: GPU pow
// vs the CPU's sRGB tables; see src/composite/README.md).
const char* const kAnaglyphFsHead = R"(#version 330 core
uniform sampler2D uImage;
uniform sampler2D uRight;
uniform ivec2 uOffset;
uniform int uFbHeight;
out vec4 oColor;
)";
const char* const kAnaglyphFsMain = R"(
void main() {
    ivec2 p = ivec2(int(gl_FragCoord.x), uFbHeight - 1 - int(gl_FragCoord.y)) - uOffset;
    ivec2 size = textureSize(uImage, 0);
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) {
        oColor = vec4(0.0, 0.0, 0.0, 1.0);
    } else {
        oColor = vec4(mvrAnaglyph(texelFetch(uImage, p, 0).rgb, texelFetch(uRight, p, 0).rgb), 1.0);
    }
}
)";

/// Compiles one stage. Errors: Internal with the log.
Status compile(GLenum stage, const char* source, GLuint& out) {
    out = glCreateShader(stage);
    glShaderSource(out, 1, &source, nullptr);
    glCompileShader(out);
    GLint ok = 0;
    glGetShaderiv(out, GL_COMPILE_STATUS, &ok);
    if (ok) return Status::ok();
    char log[2048] = {};
    glGetShaderInfoLog(out, sizeof log, nullptr, log);
    glDeleteShader(out);
    return internalError(fmt::format("mvr view: present shader does not compile: {}", log));
}

/// Links the full-screen-triangle vertex shader with fragment shader `fsSource`.
Status link(const char* fsSource, GLuint& out) {
    GLuint vs = 0, fs = 0;
    if (Status s = compile(GL_VERTEX_SHADER, kPresentVs, vs); !s) return s;
    if (Status s = compile(GL_FRAGMENT_SHADER, fsSource, fs); !s) {
        glDeleteShader(vs);
        return s;
    }
    out = glCreateProgram();
    glAttachShader(out, vs);
    glAttachShader(out, fs);
    glLinkProgram(out);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(out, GL_LINK_STATUS, &ok);
    if (ok) return Status::ok();
    char log[2048] = {};
    glGetProgramInfoLog(out, sizeof log, nullptr, log);
    glDeleteProgram(out);
    out = 0;
    return internalError(fmt::format("mvr view: present shader does not link: {}", log));
}

}  // namespace

Presenter::~Presenter() {
    if (mProgram) glDeleteProgram(mProgram);
    for (auto& [method, program] : mAnaglyphPrograms) {
        if (program.id) glDeleteProgram(program.id);
    }
    if (mVao) glDeleteVertexArrays(1, &mVao);
    glDeleteTextures(2, mTextures);
}

Status Presenter::init() {
    if (Status s = link(kPresentFs, mProgram); !s) return s;
    mOffsetLoc = glGetUniformLocation(mProgram, "uOffset");
    mFbHeightLoc = glGetUniformLocation(mProgram, "uFbHeight");
    glGenVertexArrays(1, &mVao);
    glGenTextures(2, mTextures);
    for (GLuint t : mTextures) {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    return Status::ok();
}

void Presenter::upload(int slot, const Image& image) {
    glBindTexture(GL_TEXTURE_2D, mTextures[slot]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (mSizes[slot] != glm::ivec2(image.width, image.height)) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, image.rgba.data());
        mSizes[slot] = {image.width, image.height};
    } else {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.width, image.height, GL_RGBA,
                        GL_UNSIGNED_BYTE, image.rgba.data());
    }
}

void Presenter::draw(int slot, glm::ivec2 fb, GLenum drawBuffer) {
    drawWith(mProgram, mOffsetLoc, mFbHeightLoc, slot, fb, drawBuffer);
}

Status Presenter::drawAnaglyph(composite::AnaglyphMethod method, glm::ivec2 fb, GLenum drawBuffer) {
    auto it = mAnaglyphPrograms.find(method);
    if (it == mAnaglyphPrograms.end()) {
        MixProgram program;
        const std::string fs = kAnaglyphFsHead + composite::anaglyphGlsl(method) + kAnaglyphFsMain;
        if (Status s = link(fs.c_str(), program.id); !s) return s;
        program.offsetLoc = glGetUniformLocation(program.id, "uOffset");
        program.fbHeightLoc = glGetUniformLocation(program.id, "uFbHeight");
        glUseProgram(program.id);
        glUniform1i(glGetUniformLocation(program.id, "uImage"), 0);
        glUniform1i(glGetUniformLocation(program.id, "uRight"), 1);
        it = mAnaglyphPrograms.emplace(method, program).first;
    }
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, mTextures[1]);
    drawWith(it->second.id, it->second.offsetLoc, it->second.fbHeightLoc, 0, fb, drawBuffer);
    return Status::ok();
}

Image Presenter::readBack(glm::ivec2 fb, GLenum readBuffer) {
    Image image(fb.x, fb.y);
    std::vector<std::uint8_t> rows(std::size_t(fb.x) * fb.y * 4);
    glReadBuffer(readBuffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fb.x, fb.y, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    for (int y = 0; y < fb.y; ++y) {
        const std::uint8_t* src = rows.data() + std::size_t(fb.y - 1 - y) * fb.x * 4;
        std::copy(src, src + std::size_t(fb.x) * 4, image.row(y));
    }
    for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;
    return image;
}

void Presenter::drawWith(GLuint program, GLint offsetLoc, GLint fbHeightLoc, int slot,
                         glm::ivec2 fb, GLenum drawBuffer) {
    glDrawBuffer(drawBuffer);
    glViewport(0, 0, fb.x, fb.y);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(program);
    const glm::ivec2 o = offset(slot, fb);
    glUniform2i(offsetLoc, o.x, o.y);
    glUniform1i(fbHeightLoc, fb.y);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, mTextures[slot]);
    glBindVertexArray(mVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace mvr::viewer
