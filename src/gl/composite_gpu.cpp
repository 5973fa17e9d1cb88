// Every image format of the composite module on the GPU (composite_gpu.h): the views as one
// RGBA8 array texture, one full-screen pass per format family (two colour-masked passes for
// sorbier2008's anaglyph-color) into an RGBA8 target (tiled when the output is larger than a
// render target may be), read back.
#include "mvr/gl/composite_gpu.h"

#include <algorithm>
#include <utility>
#include <optional>

#include <fmt/format.h>

#include "composite_context.h"
#include "egl_context.h"
#include "gl_objects.h"
#include "mvr/composite/anaglyph.h"
#include "mvr/composite/layout.h"
#include "mvr/composite/lenticular.h"
#include "shaders.h"

namespace mvr::gl {
namespace {

// Pixel-moving layouts of the LAYOUT family (uMode).
enum LayoutMode : int {
    kSbs = 0,
    kSbsHalf = 1,
    kTb = 2,
    kTbHalf = 3,
    kRows = 4,
    kColumns = 5,
    kCheckerboard = 6,
    kHdmi = 7,
    kQuilt = 8,
    kCopy = 9,  // one view as it is (uFirst): the passes of the colour-mask anaglyph
};

// One source for every family; a family is a #define. Pixel p is the output pixel with row 0 at
// the TOP: image row 0 is uploaded to texture row 0 and the target is read back without a flip.
const char* const kFragment = R"glsl(
layout(binding = 0) uniform sampler2DArray uViews;
layout(location = 0) out vec4 oColor;
layout(location = 0) uniform ivec2 uOrigin;     // this tile's first output pixel
layout(location = 1) uniform int uMode;         // LAYOUT: LayoutMode
layout(location = 2) uniform int uViewCount;
layout(location = 3) uniform ivec2 uViewSize;
layout(location = 4) uniform int uFirst;        // layer of the left / top / first view
layout(location = 5) uniform int uSecond;       // layer of the right / bottom / second view
layout(location = 6) uniform ivec2 uGrid;       // quilt columns, rows
layout(location = 7) uniform int uGap;          // HDMI active-space lines
layout(location = 8) uniform dvec4 uLens;       // lenticular pitchU, tilt, subp, center
layout(location = 9) uniform ivec2 uScreen;     // lenticular output size
layout(location = 10) uniform ivec4 uLensFlags; // ri, bi, invertViews, 0
layout(location = 11) uniform ivec2 uFlip;      // lenticular flipX, flipY

const uvec4 kBlank = uvec4(0u, 0u, 0u, 255u);

// The 8-bit values, exactly: an RGBA8 texel reads as c / 255, and round() undoes that.
uvec4 fetch(int layer, ivec2 p) {
    return uvec4(round(texelFetch(uViews, ivec3(p, layer), 0) * 255.0));
}
// layout.h's 2:1 squeeze: (a + b + 1) / 2 per 8-bit channel, rounding half up.
uvec4 average(uvec4 a, uvec4 b) { return (a + b + 1u) / 2u; }

#ifdef FAMILY_LAYOUT
uvec4 composite(ivec2 p) {
    const int W = uViewSize.x, H = uViewSize.y;
    switch (uMode) {
    case 0:  // sbs: first | second, 2W x H
        return p.x < W ? fetch(uFirst, p) : fetch(uSecond, ivec2(p.x - W, p.y));
    case 1: {  // sbs-half: W x H, each view squeezed to W/2 columns
        const int halfSize = W / 2;
        const int layer = p.x < halfSize ? uFirst : uSecond;
        const int sx = p.x < halfSize ? p.x : p.x - halfSize;
        return average(fetch(layer, ivec2(2 * sx, p.y)), fetch(layer, ivec2(2 * sx + 1, p.y)));
    }
    case 2:  // tb: top over bottom, W x 2H
        return p.y < H ? fetch(uFirst, p) : fetch(uSecond, ivec2(p.x, p.y - H));
    case 3: {  // tb-half: W x H, each view squeezed to H/2 rows
        const int halfSize = H / 2;
        const int layer = p.y < halfSize ? uFirst : uSecond;
        const int sy = p.y < halfSize ? p.y : p.y - halfSize;
        return average(fetch(layer, ivec2(p.x, 2 * sy)), fetch(layer, ivec2(p.x, 2 * sy + 1)));
    }
    case 4:  // rows: row y from view y mod N
        return fetch(p.y % uViewCount, p);
    case 5:  // columns: column x from view x mod N
        return fetch(p.x % uViewCount, p);
    case 6:  // checkerboard: (x + y) even from the first view
        return ((p.x + p.y) & 1) == 0 ? fetch(uFirst, p) : fetch(uSecond, p);
    case 7:  // HDMI frame packing: left, uGap blank lines, right
        if (p.y < H) return fetch(uFirst, p);
        if (p.y < H + uGap) return kBlank;
        return fetch(uSecond, ivec2(p.x, p.y - H - uGap));
    case 9:  // one view as it is (each pass of the colour-mask anaglyph)
        return fetch(uFirst, p);
    default: {  // quilt: view i in tile column i mod C, tile row i / C from the BOTTOM
        const int tx = p.x / W, tyFromTop = p.y / H;
        const int i = (uGrid.y - 1 - tyFromTop) * uGrid.x + tx;
        if (i >= uViewCount) return kBlank;
        return fetch(i, ivec2(p.x - tx * W, p.y - tyFromTop * H));
    }
    }
}
#endif

#ifdef FAMILY_ANAGLYPH
// mvrAnaglyph() comes from composite::anaglyphGlsl(method), prepended to this source.
uvec4 composite(ivec2 p) {
    const vec3 l = vec3(fetch(uFirst, p).rgb) / 255.0;
    const vec3 r = vec3(fetch(uSecond, p).rgb) / 255.0;
    const vec3 o = clamp(mvrAnaglyph(l, r), 0.0, 1.0);
    return uvec4(uvec3(o * 255.0 + 0.5), 255u);  // round to nearest, as the CPU encodes
}
#endif

#ifdef FAMILY_LENTICULAR
// composite::lenticularView(), operation for operation in double precision; `precise` keeps
// the compiler from fusing multiply-adds, so the result is the CPU's bit for bit.
int lenticularView(int px, int py, int subpixel) {
    precise double u = (double(px) + 0.5LF) / double(uScreen.x);
    precise double v = 1.0LF - (double(py) + 0.5LF) / double(uScreen.y);
    precise double z = (u + double(subpixel) * uLens.z + v * uLens.y) * uLens.x - uLens.w;
    z = z - floor(z);
    if (uLensFlags.z != 0) z = 1.0LF - z;
    precise double scaled = z * double(uViewCount);
    return clamp(int(floor(scaled)), 0, uViewCount - 1);
}

uvec4 composite(ivec2 p) {
    const int vw = uViewSize.x, vh = uViewSize.y;
    // Nearest view pixel: min(v - 1, floor((p + 0.5) * v / screen)), in exact integers.
    const int vx0 = min(vw - 1, ((2 * p.x + 1) * vw) / (2 * uScreen.x));
    const int vy0 = min(vh - 1, ((2 * p.y + 1) * vh) / (2 * uScreen.y));
    const ivec2 s = ivec2(uFlip.x != 0 ? vw - 1 - vx0 : vx0, uFlip.y != 0 ? vh - 1 - vy0 : vy0);
    const int viewR = lenticularView(p.x, p.y, uLensFlags.x);
    const int viewG = lenticularView(p.x, p.y, 1);
    const int viewB = lenticularView(p.x, p.y, uLensFlags.y);
    return uvec4(fetch(viewR, s).r, fetch(viewG, s).g, fetch(viewB, s).b, 255u);
}
#endif

void main() {
    // k / 255 goes back to exactly k in the RGBA8 target (UNORM conversion rounds to nearest).
    oColor = vec4(composite(ivec2(gl_FragCoord.xy) + uOrigin)) / 255.0;
}
)glsl";

// What one composite draws: the family's fragment source, the output size and the uniforms.
struct Plan {
    std::string source;  ///< fragment shader (defines + kFragment)
    int width = 0, height = 0;
    int mode = 0, first = 0, second = 1, gap = 0, gridColumns = 1, gridRows = 1;
    bool colorMask = false;  ///< sorbier2008 §4.3: red from `first`, green/blue from `second`
    bool customMix = false;  ///< the source holds GpuComposeOptions::anaglyphMix
    bool lenticular = false;
    composite::LenticularShaderParams lens;
    bool flipX = false, flipY = false;
};

// The plan of format `info` for `views` (already validated for count and size); its size and
// size checks are composite::outputSize()'s, i.e. compose()'s.
Result<Plan> makePlan(const composite::FormatInfo& info, std::span<const Image> views,
                      const composite::ComposeOptions& options, const GpuComposeOptions& gpu,
                      const std::string& who) {
    const int n = static_cast<int>(views.size());
    const int w = views[0].width, h = views[0].height;
    Result<composite::Size> size = composite::outputSize(info, n, w, h, options, who);
    if (!size) return size.status();
    Plan plan;
    plan.width = size->width;
    plan.height = size->height;
    plan.source = "#define FAMILY_LAYOUT 1\n" + std::string(kFragment);
    using composite::GpuPlan;
    const GpuPlan kind = info.gpu;

    if (kind == GpuPlan::Anaglyph) {
        const std::optional<composite::AnaglyphMethod> method =
            composite::anaglyphMethod(info.name);
        if (!method) return internalError(fmt::format("{}: an anaglyph plan for a format that "
                                                      "is no anaglyph", who));
        if (!gpu.anaglyphMix.empty()) {
            plan.source = "#define FAMILY_ANAGLYPH 1\n" + gpu.anaglyphMix + "\n" + kFragment;
            plan.customMix = true;
        } else if (*method == composite::AnaglyphMethod::Color) {
            plan.mode = kCopy;
            plan.colorMask = true;
        } else {
            plan.source =
                "#define FAMILY_ANAGLYPH 1\n" + composite::anaglyphGlsl(*method) + "\n" + kFragment;
        }
        return plan;
    }
    if (kind == GpuPlan::SideBySide || kind == GpuPlan::SideBySideHalf) {
        if (options.crossEyed) std::swap(plan.first, plan.second);
        plan.mode = kind == GpuPlan::SideBySide ? kSbs : kSbsHalf;
        return plan;
    }
    if (kind == GpuPlan::TopBottom || kind == GpuPlan::TopBottomHalf) {
        plan.mode = kind == GpuPlan::TopBottom ? kTb : kTbHalf;
        return plan;
    }
    if (kind == GpuPlan::Rows) {
        plan.mode = kRows;
        return plan;
    }
    if (kind == GpuPlan::Columns) {
        plan.mode = kColumns;
        return plan;
    }
    if (kind == GpuPlan::Checkerboard) {
        plan.mode = kCheckerboard;
        return plan;
    }
    if (kind == GpuPlan::FramePacking) {
        plan.mode = kHdmi;
        plan.gap = plan.height - 2 * h;  // composite::hdmiActiveSpaceLines()
        return plan;
    }
    if (kind == GpuPlan::Quilt) {
        plan.mode = kQuilt;
        plan.gridColumns = plan.width / w;
        plan.gridRows = plan.height / h;
        return plan;
    }
    if (kind == GpuPlan::Lenticular) {
        const composite::LenticularCalibration& cal = options.lenticular;
        Result<composite::LenticularShaderParams> params =
            composite::lenticularShaderParams(cal, plan.width, plan.height);
        if (!params) return params.status();
        plan.lens = *params;
        plan.lenticular = true;
        plan.flipX = cal.flipX;
        plan.flipY = cal.flipY;
        plan.source = "#define FAMILY_LENTICULAR 1\n" + std::string(kFragment);
        return plan;
    }
    return internalError(fmt::format("{}: format without a GPU implementation", who));
}

// The GL part: the composite context is current. Every GL object lives inside this function.
Result<Image> draw(detail::CompositeContext& c, const Plan& plan, std::span<const Image> views,
                   bool reverse) {
    const int n = static_cast<int>(views.size());
    const int w = views[0].width, h = views[0].height;
    GLint maxSize = 0, maxLayers = 0, maxRenderbuffer = 0;
    GLint maxViewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRenderbuffer);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    if (w > maxSize || h > maxSize)
        return unsupportedError(
            fmt::format("mvr::gl::composeGpu(): views of {}x{} exceed GL_MAX_TEXTURE_SIZE = {}", w,
                        h, maxSize));
    if (n > maxLayers)
        return unsupportedError(
            fmt::format("mvr::gl::composeGpu(): {} views exceed GL_MAX_ARRAY_TEXTURE_LAYERS = {}",
                        n, maxLayers));

    auto it = c.programs.find(plan.source);
    if (it == c.programs.end()) {
        auto p = detail::buildFullScreenProgram(plan.source);
        if (!p && plan.customMix)
            return usageError(
                fmt::format("mvr::gl::composeGpu(): the anaglyph mix GLSL does not "
                            "build: {}",
                            p.status().message()));
        if (!p) return p.status();
        it = c.programs.emplace(plan.source, std::move(p).value()).first;
    }
    const GLuint program = it->second.get();

    // The views: layer i = views[i], or views[n - 1 - i] for swapEyes (compose()'s reversal).
    // The storage is kept for the next call of the same size (mvr render composes several
    // formats from one set of views; fresh storage costs the driver an allocation each time).
    detail::CompositeContext::Storage& cache = c.storage;
    if (!cache.views || cache.viewsW != w || cache.viewsH != h || cache.viewsN != n) {
        cache.views.reset();
        cache.views = detail::createTexture(GL_TEXTURE_2D_ARRAY);
        glTextureStorage3D(cache.views.get(), 1, GL_RGBA8, w, h, n);
        glTextureParameteri(cache.views.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(cache.views.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        cache.viewsW = w;
        cache.viewsH = h;
        cache.viewsN = n;
    }
    const GLuint array = cache.views.get();
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    for (int i = 0; i < n; ++i) {
        const Image& v = views[static_cast<std::size_t>(reverse ? n - 1 - i : i)];
        glTextureSubImage3D(array, 0, 0, 0, i, w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE, v.rgba.data());
    }
    if (Status s = detail::checkGlError("mvr::gl::composeGpu(): uploading the views"); !s) {
        cache = {};
        return s;
    }

    glProgramUniform1i(program, 1, plan.mode);
    glProgramUniform1i(program, 2, n);
    glProgramUniform2i(program, 3, w, h);
    glProgramUniform1i(program, 4, plan.first);
    glProgramUniform1i(program, 5, plan.second);
    glProgramUniform2i(program, 6, plan.gridColumns, plan.gridRows);
    glProgramUniform1i(program, 7, plan.gap);
    if (plan.lenticular) {
        glProgramUniform4d(program, 8, plan.lens.pitchU, plan.lens.tilt, plan.lens.subp,
                           plan.lens.center);
        glProgramUniform2i(program, 9, plan.width, plan.height);
        glProgramUniform4i(program, 10, plan.lens.ri, plan.lens.bi, plan.lens.invertViews ? 1 : 0,
                           0);
        glProgramUniform2i(program, 11, plan.flipX ? 1 : 0, plan.flipY ? 1 : 0);
    }

    // The target: one tile, reused; outputs larger than it are drawn tile by tile.
    const int tileLimit =
        std::max(1, std::min({maxSize, maxRenderbuffer, maxViewport[0], maxViewport[1], 4096}));
    const int tileW = std::min(plan.width, tileLimit), tileH = std::min(plan.height, tileLimit);
    if (!cache.target || cache.targetW != tileW || cache.targetH != tileH) {
        cache.fbo.reset();
        cache.target.reset();
        cache.target = detail::createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(cache.target.get(), 1, GL_RGBA8, tileW, tileH);
        cache.fbo = detail::createFramebuffer();
        glNamedFramebufferTexture(cache.fbo.get(), GL_COLOR_ATTACHMENT0, cache.target.get(), 0);
        cache.targetW = tileW;
        cache.targetH = tileH;
    }
    if (glCheckNamedFramebufferStatus(cache.fbo.get(), GL_DRAW_FRAMEBUFFER) !=
        GL_FRAMEBUFFER_COMPLETE) {
        cache = {};
        return internalError("mvr::gl::composeGpu(): the RGBA8 target is not framebuffer complete");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, cache.fbo.get());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(program);
    glBindVertexArray(c.vao.get());
    glBindTextureUnit(0, array);

    Image out(plan.width, plan.height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, plan.width);
    for (int oy = 0; oy < plan.height; oy += tileH) {
        for (int ox = 0; ox < plan.width; ox += tileW) {
            const int tw = std::min(tileW, plan.width - ox), th = std::min(tileH, plan.height - oy);
            glViewport(0, 0, tw, th);
            glProgramUniform2i(program, 0, ox, oy);
            if (plan.colorMask) {
                // sorbier2008 §4.3: over black, additively, red from the first view, then
                // green and blue from the second; alpha keeps the clear's 1.
                glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
                glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
                glClear(GL_COLOR_BUFFER_BIT);
                glEnable(GL_BLEND);
                glBlendFunc(GL_ONE, GL_ONE);
                glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_FALSE);
                glProgramUniform1i(program, 4, plan.first);
                glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
                glColorMask(GL_FALSE, GL_TRUE, GL_TRUE, GL_FALSE);
                glProgramUniform1i(program, 4, plan.second);
                glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
                glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
                glDisable(GL_BLEND);
            } else {
                glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            }
            glReadPixels(0, 0, tw, th, GL_RGBA, GL_UNSIGNED_BYTE,
                         out.rgba.data() + (static_cast<std::size_t>(oy) * plan.width + ox) * 4);
        }
    }
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glBindTextureUnit(0, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (Status s = detail::checkGlError("mvr::gl::composeGpu()"); !s) {
        cache = {};  // e.g. out of memory: make everything afresh next time
        return s;
    }
    return out;
}

}  // namespace

bool composeGpuSupports(const std::string& format) {
    Result<composite::FormatInfo> info = composite::findFormat(format);
    return info && !info->fileOnly && info->gpu != composite::GpuPlan::None;
}

Result<Image> composeGpu(const std::string& format, std::span<const Image> views,
                         const composite::ComposeOptions& options, const GpuComposeOptions& gpu) {
    // compose()'s checks, in compose()'s order.
    Result<composite::FormatInfo> info = composite::findFormat(format);
    if (!info) return info.status();
    const std::string who = fmt::format("mvr::gl::composeGpu(): {}", info->name);
    if (Status s = composite::validateViews(views, info->minViews, info->maxViews, who.c_str()); !s)
        return s;
    if (info->fileOnly || info->gpu == composite::GpuPlan::None)
        return unsupportedError(fmt::format(
            "{}: {}, composed on the CPU only (mvr::composite::compose() / writeComposite())",
            who, info->file == composite::FileKind::Png ? "a format without a GPU plan"
                                                        : "a JPEG file"));
    Result<Plan> plan = makePlan(*info, views, options, gpu, who);
    if (!plan) return plan.status();

    std::lock_guard lock(detail::compositeMutex());
    detail::CompositeScope scope;  // before the context is made; outlives every GL object
    detail::CompositeContext& c = detail::compositeContext();
    if (!c.status) return c.status;
    if (Status s = c.context->makeCurrent(); !s) return s;
    return draw(c, *plan, views, options.swapEyes);
}

}  // namespace mvr::gl
