// src/gl/multisample.cpp — `--aa N` as hardware multisampling (issue 38): which requests draw
// into multisampled targets, and the resolve of those targets into the single-sample textures
// the read-back reads (renderer.h LayeredTarget: the ms* twins and resolveFbo).
//
// The resolve is a full-screen pass, not glBlitFramebuffer: a blit's colour resolve rounds as
// the driver likes and its depth resolve is undefined, where mvr/core/antialias.h fixes both
// (the mean colour byte rounded half up, the nearest depth), as the soft backend and the
// sub-pixel passes resolve.
#include <cstdlib>
#include <string_view>

#include <fmt/format.h>

#include "renderer.h"

namespace mvr::gl::detail {

namespace {

// TARGET_LAYERED: 2D-array targets, one layer (uLayer) a draw; else 2D (the tiled target and
// sorbier2008's two MRT colours, the second on unit 1). DEPTH: the nearest sample into gl_FragDepth. MRT: a second
// colour. SAMPLES: the sample count.
const char* const kResolveSource = R"glsl(
#ifdef TARGET_LAYERED
layout(binding = 0) uniform sampler2DMSArray uColor;
layout(binding = 1) uniform sampler2DMSArray uDepth;
layout(location = 0) uniform int uLayer;
#define FETCH(t, i) texelFetch(t, ivec3(p, uLayer), i)
#else
layout(binding = 0) uniform sampler2DMS uColor;
#ifdef MRT
layout(binding = 1) uniform sampler2DMS uColor1;
#else
layout(binding = 1) uniform sampler2DMS uDepth;
#endif
#define FETCH(t, i) texelFetch(t, p, i)
#endif
layout(location = 0) out vec4 oColor;
#ifdef MRT
layout(location = 1) out vec4 oColor1;
#endif

// The samples' bytes summed (UNORM8 reads back as byte / 255 exactly enough to round back),
// the mean rounded half up: (sum + N/2) / N, as resolveSampleSums().
#define RESOLVE(t, out_)                                                    \
    {                                                                       \
        uvec4 sum = uvec4(0u);                                              \
        for (int i = 0; i < SAMPLES; ++i)                                   \
            sum += uvec4(round(clamp(FETCH(t, i), 0.0, 1.0) * 255.0));     \
        out_ = vec4((sum + uvec4(SAMPLES / 2)) / uint(SAMPLES)) / 255.0;   \
    }

void main() {
    const ivec2 p = ivec2(gl_FragCoord.xy);
    RESOLVE(uColor, oColor)
#ifdef MRT
    RESOLVE(uColor1, oColor1)
#endif
#ifdef DEPTH
    float nearest = FETCH(uDepth, 0).r;
    for (int i = 1; i < SAMPLES; ++i) nearest = min(nearest, FETCH(uDepth, i).r);
    gl_FragDepth = nearest;
#endif
}
)glsl";

}  // namespace

bool Renderer::drawsSamples(const GlMethod& method, int samples) const {
    return method.multisample && mCaps.multisamples(samples);
}

bool Renderer::multisamples(const std::string& method, int samples) {
    const char* force = std::getenv("MVR_GL_MULTISAMPLE");
    if (force && std::string_view(force) == "off") return false;
    if (!ensureContext()) return false;
    const GlMethod* m = findMethod(method);
    // auto: the driver's counts (it measures only the methods that draw them: renderAuto).
    return m && (m->measuresExact ? mCaps.multisamples(samples) : drawsSamples(*m, samples));
}

Status Renderer::resolveSamples(const Frame& f) {
    const TargetKind kind = f.method->target;
    const int n = f.samples;
    auto& slot = mGpu->resolvePrograms[{int(kind), n}];
    if (!slot) {
        std::string defines = fmt::format("#define SAMPLES {}\n", n);
        if (kind == TargetKind::Layered) defines += "#define TARGET_LAYERED 1\n";
        if (kind == TargetKind::Mrt) defines += "#define MRT 1\n";
        if (kind != TargetKind::Mrt) defines += "#define DEPTH 1\n";
        auto p = buildFullScreenProgram(defines + kResolveSource);
        if (!p) return p.status();
        slot = std::move(p).value();
    }
    const GLuint prog = slot.get();
    // What the methods may have left on: a full-screen quad with every sample written.
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    for (int i = 0; i < 4; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glEnable(GL_DEPTH_TEST);  // writes gl_FragDepth only with the test on
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glUseProgram(prog);
    glBindVertexArray(mGpu->emptyVao.get());
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    switch (kind) {
        case TargetKind::Layered: {
            const LayeredTarget& t = mGpu->layered;
            const GLuint fbo = t.resolveFbo.get();
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
            glViewport(0, 0, t.w, t.h);
            glBindTextureUnit(0, t.msColor.get());
            glBindTextureUnit(1, t.msDepth.get());
            for (int v = 0; v < f.views; ++v) {
                glNamedFramebufferTextureLayer(fbo, GL_COLOR_ATTACHMENT0, t.color.get(), 0, v);
                glNamedFramebufferTextureLayer(fbo, GL_DEPTH_ATTACHMENT, t.depth.get(), 0, v);
                glProgramUniform1i(prog, 0, v);
                glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            }
            break;
        }
        case TargetKind::Tiled: {
            const TiledTarget& t = mGpu->tiled;
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolveFbo.get());
            // The pass's tiles: the target's top-left corner (ensureTiled).
            glViewport(0, 0, f.tiles->columns * f.tiles->width, f.tiles->rows * f.tiles->height);
            glBindTextureUnit(0, t.msColor.get());
            glBindTextureUnit(1, t.msDepth.get());
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            break;
        }
        case TargetKind::Mrt: {
            const MrtTarget& t = mGpu->mrt;
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolveFbo.get());
            glViewport(0, 0, t.w, t.h);
            glDisable(GL_DEPTH_TEST);  // no depth attachment
            glBindTextureUnit(0, t.msColor[0].get());
            glBindTextureUnit(1, t.msColor[1].get());
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            break;
        }
    }
    glBindTextureUnit(0, 0);
    glBindTextureUnit(1, 0);
    glDepthFunc(GL_LESS);
    return checkGlError("resolving the samples");
}

}  // namespace mvr::gl::detail
