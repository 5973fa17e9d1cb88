// src/gl/readback.cpp — the views' pixels from the GPU to the caller's images (startRead /
// finishRead: straight reads on software rasterisers, a pixel-pack buffer and a fence that
// overlap the next pass's draw on hardware), and, when the caller asked for no depth images,
// each view's depth range reduced on the GPU (reduceDepthRanges / readDepthRanges).
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "renderer.h"

namespace mvr::gl::detail {

namespace {
constexpr std::uint32_t kOneBits = 0x3F800000u;  // the bits of 1.0f
}  // namespace

namespace {

// The caller's memory for view `view` of `views` (RenderSettings::output), or nullptr (heap).
OutputBlock* blockFor(const RenderSettings& s, std::size_t views, int w, int h) {
    OutputBlock* b = s.output;
    return b && std::size_t(b->views()) == views && b->width() == w && b->height() == h ? b
                                                                                        : nullptr;
}
std::pmr::memory_resource* colorMemory(OutputBlock* b, std::size_t view) {
    return b ? b->colorMemory(int(view)) : nullptr;
}
std::pmr::memory_resource* depthMemory(OutputBlock* b, std::size_t view) {
    return b ? b->depthMemory(int(view)) : nullptr;
}


}  // namespace

std::vector<Renderer::ViewRegion> Renderer::viewRegions(const Frame& f) const {
    std::vector<ViewRegion> regions(static_cast<std::size_t>(f.views));
    for (int v = 0; v < f.views; ++v) {
        ViewRegion& r = regions[static_cast<std::size_t>(v)];
        switch (f.method->target) {
            case TargetKind::Layered:
                r = {mGpu->layered.color.get(), mGpu->layered.depth.get(), 0, 0, v};
                break;
            case TargetKind::Tiled: {
                const glm::ivec2 o = f.tiles->origin(v);
                r = {mGpu->tiled.color.get(), mGpu->tiled.depth.get(), o.x, o.y, 0};
                break;
            }
            case TargetKind::Mrt: r = {mGpu->mrt.color[v].get(), 0, 0, 0, 0}; break;
        }
    }
    return regions;
}

std::optional<PendingRead> Renderer::startRead(const Frame& f, RenderOutput& out, int pass) {
    const int w = f.tiles ? f.tiles->width : f.settings->width;
    const int h = f.tiles ? f.tiles->height : f.settings->height;
    const bool mrt = f.method->target == TargetKind::Mrt;
    const bool depth = f.settings->depth && !mrt;
    if (mrt) out.color.resize(2);
    const std::vector<ViewRegion> regions = viewRegions(f);
    const std::size_t pixels = static_cast<std::size_t>(w) * h;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    if (mCaps.softwareRenderer()) {
        OutputBlock* block = blockFor(*f.settings, out.color.size(), w, h);
        for (int v = 0; v < f.views; ++v) {
            const ViewRegion& r = regions[static_cast<std::size_t>(v)];
            const auto i = static_cast<std::size_t>(f.firstView + v);
            Image& img = out.color[i];
            img.reuseOrReset(w, h, colorMemory(block, i));
            glGetTextureSubImage(r.color, 0, r.x, r.y, r.layer, w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                                 static_cast<GLsizei>(pixels * 4), img.rgba.data());
            if (!depth) {
                if (i < out.depthRange.size()) out.depthRange[i] = scratchDepthRange(r, w, h);
                continue;
            }
            DepthImage& d = out.depth[i];
            d.reuseOrReset(w, h, depthMemory(block, i));
            glGetTextureSubImage(r.depth, 0, r.x, r.y, r.layer, w, h, 1, GL_DEPTH_COMPONENT,
                                 GL_FLOAT, static_cast<GLsizei>(pixels * sizeof(float)),
                                 d.depth.data());
        }
        return std::nullopt;
    }
    PendingRead pending{f.firstView, f.views, w, h, depth, pass % 2, nullptr};
    ReadBuffer& rb = mGpu->reads[pending.buffer];
    const std::size_t bytes = pixels * 4 * static_cast<std::size_t>(f.views) * (depth ? 2 : 1);
    if (rb.bytes < bytes) {
        rb.buffer = createBuffer();
        glNamedBufferStorage(rb.buffer.get(), static_cast<GLsizeiptr>(bytes), nullptr,
                             GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT);
        rb.bytes = bytes;
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, rb.buffer.get());
    const std::size_t colorBytes = pixels * 4 * static_cast<std::size_t>(f.views);
    auto at = [](std::size_t offset) { return reinterpret_cast<void*>(offset); };
    if (f.method->target == TargetKind::Layered) {
        // One call per image kind for the whole pass: layers are the views, back to back.
        glGetTextureSubImage(regions[0].color, 0, 0, 0, 0, w, h, f.views, GL_RGBA, GL_UNSIGNED_BYTE,
                             static_cast<GLsizei>(colorBytes), at(0));
        if (depth) {
            glGetTextureSubImage(regions[0].depth, 0, 0, 0, 0, w, h, f.views, GL_DEPTH_COMPONENT,
                                 GL_FLOAT, static_cast<GLsizei>(colorBytes), at(colorBytes));
        }
    } else {
        for (int v = 0; v < f.views; ++v) {
            const ViewRegion& r = regions[static_cast<std::size_t>(v)];
            const std::size_t o = pixels * 4 * static_cast<std::size_t>(v);
            glGetTextureSubImage(r.color, 0, r.x, r.y, r.layer, w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                                 static_cast<GLsizei>(pixels * 4), at(o));
            if (depth) {
                glGetTextureSubImage(r.depth, 0, r.x, r.y, r.layer, w, h, 1, GL_DEPTH_COMPONENT,
                                     GL_FLOAT, static_cast<GLsizei>(pixels * 4),
                                     at(colorBytes + o));
            }
        }
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    pending.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();  // the copies start now, while the next pass is drawn
    return pending;
}

void Renderer::finishRead(PendingRead& r, RenderOutput& out, const RenderSettings& s) {
    if (r.fence) {
        while (glClientWaitSync(r.fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000) ==
               GL_TIMEOUT_EXPIRED) {
        }
        glDeleteSync(r.fence);
        r.fence = nullptr;
    }
    const std::size_t pixels = static_cast<std::size_t>(r.width) * r.height;
    const std::size_t colorBytes = pixels * 4 * static_cast<std::size_t>(r.views);
    const std::size_t bytes = colorBytes * (r.depth ? 2 : 1);
    ReadBuffer& rb = mGpu->reads[r.buffer];
    const auto* src = static_cast<const std::uint8_t*>(
        glMapNamedBufferRange(rb.buffer.get(), 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT));
    if (!src) return;  // checkGlError reports the failed map
    OutputBlock* block = blockFor(s, out.color.size(), r.width, r.height);
    for (int v = 0; v < r.views; ++v) {
        const auto i = static_cast<std::size_t>(r.firstView + v);
        const std::size_t o = pixels * 4 * static_cast<std::size_t>(v);
        out.color[i].reuseOrReset(r.width, r.height, colorMemory(block, i));
        std::memcpy(out.color[i].rgba.data(), src + o, pixels * 4);
        if (!r.depth) continue;
        out.depth[i].reuseOrReset(r.width, r.height, depthMemory(block, i));
        std::memcpy(out.depth[i].depth.data(), src + colorBytes + o, pixels * sizeof(float));
    }
    glUnmapNamedBuffer(rb.buffer.get());
}

// ---- depth ranges ----------------------------------------------------------------------------

namespace {

// One invocation a column of kRowsPerInvocation pixels (min / max in registers), z the view of
// the pass; a workgroup folds its columns in shared memory, then one atomic a workgroup on the
// view's pair. Few atomics: llvmpipe runs a shared atomic per pixel ~10x slower than reading
// the depth image back.
constexpr int kColumnsPerGroup = 64;
constexpr int kRowsPerInvocation = 32;
constexpr const char* kDepthRangeSource = R"glsl(
layout(local_size_x = 64) in;
const int kRows = 32;
layout(binding = 0) uniform sampler2DArray uLayers;
layout(binding = 1) uniform sampler2D uTiled;
uniform bool uLayered;
uniform ivec2 uSize;     // one view's, in texels
uniform int uColumns;    // views across (tiled target)
uniform int uFirstView;  // the request's index of the pass's view 0
layout(std430, binding = 0) buffer Ranges { uint range[]; };
shared uint sNearest, sFarthest;
void main() {
    if (gl_LocalInvocationIndex == 0u) {
        sNearest = 0x3F800000u;  // 1.0: nothing drawn
        sFarthest = 0u;
    }
    barrier();
    const int x = int(gl_GlobalInvocationID.x);
    const int y0 = int(gl_WorkGroupID.y) * kRows;
    const int v = int(gl_GlobalInvocationID.z);
    const ivec2 origin = uLayered ? ivec2(0) : ivec2(v % uColumns, v / uColumns) * uSize;
    float nearest = 1.0, farthest = -1.0;
    if (x < uSize.x) {
        const int y1 = min(y0 + kRows, uSize.y);
        for (int y = y0; y < y1; ++y) {
            const float d = uLayered ? texelFetch(uLayers, ivec3(x, y, v), 0).r
                                     : texelFetch(uTiled, origin + ivec2(x, y), 0).r;
            if (d < 1.0) {
                nearest = min(nearest, d);
                farthest = max(farthest, d);
            }
        }
    }
    if (farthest >= 0.0 || nearest < 1.0) {
        atomicMin(sNearest, nearest > 0.0 ? floatBitsToUint(nearest) : 0u);
        atomicMax(sFarthest, farthest > 0.0 ? floatBitsToUint(farthest) : 0u);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && sNearest <= sFarthest) {
        atomicMin(range[2 * (uFirstView + v)], sNearest);
        atomicMax(range[2 * (uFirstView + v) + 1], sFarthest);
    }
}
)glsl";

}  // namespace

bool Renderer::gpuDepthRanges() const {
    const char* force = std::getenv("MVR_GL_DEPTH_RANGES");  // tests: the GPU path on llvmpipe
    return !mCaps.softwareRenderer() || (force && std::string_view(force) == "gpu");
}

DepthRange Renderer::scratchDepthRange(const ViewRegion& r, int w, int h) {
    const std::size_t pixels = std::size_t(w) * h;
    mDepthScratch.resize(pixels);
    glGetTextureSubImage(r.depth, 0, r.x, r.y, r.layer, w, h, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                         static_cast<GLsizei>(pixels * sizeof(float)), mDepthScratch.data());
    return depthRangeOfImage(mDepthScratch);
}

Status Renderer::beginDepthRanges(int views) {
    if (!mGpu->depthRangeProgram) {
        auto p = buildComputeProgram(kDepthRangeSource);
        if (!p) return p.status();
        mGpu->depthRangeProgram = std::move(p).value();
    }
    if (!mGpu->depthRanges) {
        mGpu->depthRanges = createBuffer();
        glNamedBufferStorage(mGpu->depthRanges.get(), 2 * kMaxViews * sizeof(std::uint32_t),
                             nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    std::vector<std::uint32_t> init(2 * std::size_t(views));
    for (std::size_t i = 0; i < init.size(); i += 2) init[i] = kOneBits;
    glNamedBufferSubData(mGpu->depthRanges.get(), 0, GLsizeiptr(init.size() * sizeof(init[0])),
                         init.data());
    return checkGlError("setting up the depth ranges");
}

Status Renderer::reduceDepthRanges(const Frame& f) {
    const GLuint prog = mGpu->depthRangeProgram.get();
    const bool layered = f.method->target == TargetKind::Layered;
    const int w = f.tiles ? f.tiles->width : f.settings->width;
    const int h = f.tiles ? f.tiles->height : f.settings->height;
    const ViewRegion r = viewRegions(f).front();
    glUseProgram(prog);
    glProgramUniform1i(prog, glGetUniformLocation(prog, "uLayered"), layered ? 1 : 0);
    glProgramUniform2i(prog, glGetUniformLocation(prog, "uSize"), w, h);
    glProgramUniform1i(prog, glGetUniformLocation(prog, "uColumns"),
                       f.tiles ? f.tiles->columns : 1);
    glProgramUniform1i(prog, glGetUniformLocation(prog, "uFirstView"), f.firstView);
    // Both samplers need a texture of their kind; the one not read gets the other target's
    // (or none: an unread incomplete binding is harmless).
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    glBindTextureUnit(0, layered ? r.depth : mGpu->layered.depth.get());
    glBindTextureUnit(1, layered ? mGpu->tiled.depth.get() : r.depth);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, mGpu->depthRanges.get());
    glDispatchCompute(GLuint((w + kColumnsPerGroup - 1) / kColumnsPerGroup),
                      GLuint((h + kRowsPerInvocation - 1) / kRowsPerInvocation), GLuint(f.views));
    glBindTextureUnit(0, 0);
    glBindTextureUnit(1, 0);
    return checkGlError("reducing the depth ranges");
}

Status Renderer::readDepthRanges(RenderOutput& out, int views) {
    std::vector<std::uint32_t> bits(2 * std::size_t(views));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(mGpu->depthRanges.get(), 0, GLsizeiptr(bits.size() * sizeof(bits[0])),
                            bits.data());
    out.depthRange.assign(std::size_t(views), DepthRange{});
    for (std::size_t v = 0; v < out.depthRange.size(); ++v) {
        if (bits[2 * v] > bits[2 * v + 1]) continue;  // nothing drawn
        std::memcpy(&out.depthRange[v].nearest, &bits[2 * v], sizeof(float));
        std::memcpy(&out.depthRange[v].farthest, &bits[2 * v + 1], sizeof(float));
    }
    return checkGlError("reading the depth ranges");
}

}  // namespace mvr::gl::detail
