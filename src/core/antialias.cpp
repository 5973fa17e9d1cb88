// antialias.cpp — N sub-pixel passes resolved (mvr/core/antialias.h).
#include "mvr/core/antialias.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include "parallel.h"

namespace mvr {

namespace {
// Direct3D's standard patterns, 1/16 pixel, y down (the header).
constexpr std::array<glm::vec2, 1> k1{glm::vec2(0, 0)};
constexpr std::array<glm::vec2, 2> k2{glm::vec2(4, 4), glm::vec2(-4, -4)};
constexpr std::array<glm::vec2, 4> k4{glm::vec2(-2, -6), glm::vec2(6, -2), glm::vec2(-6, 2),
                                      glm::vec2(2, 6)};
constexpr std::array<glm::vec2, 8> k8{glm::vec2(1, -3), glm::vec2(-1, 3),  glm::vec2(5, 1),
                                      glm::vec2(-3, -5), glm::vec2(-5, 5), glm::vec2(-7, -1),
                                      glm::vec2(3, 7),   glm::vec2(7, -7)};

template <std::size_t N>
std::span<const glm::vec2> scaled(const std::array<glm::vec2, N>& sixteenths) {
    static const std::array<glm::vec2, N> px = [&] {
        std::array<glm::vec2, N> a{};
        for (std::size_t i = 0; i < N; ++i) a[i] = sixteenths[i] / 16.0f;
        return a;
    }();
    return px;
}
}  // namespace

bool validSampleCount(int samples) {
    return samples == 1 || samples == 2 || samples == 4 || samples == 8;
}

std::span<const glm::vec2> samplePositions(int samples) {
    switch (samples) {
        case 2: return scaled(k2);
        case 4: return scaled(k4);
        case 8: return scaled(k8);
        default: return scaled(k1);
    }
}

Rig offsetRig(const Rig& rig, glm::vec2 offsetPx, int width, int height) {
    // The pixel centre samples centre + offset when the image moves by −offset: NDC x by
    // −2·dx/W; NDC y is up while rows go down, so by +2·dy/H. Per unit w (clip.xy += j·w).
    const glm::vec2 j(-2.0f * offsetPx.x / float(width), 2.0f * offsetPx.y / float(height));
    const glm::mat4 move = glm::translate(glm::mat4(1.0f), glm::vec3(j, 0.0f));
    Rig moved = rig;
    for (View& v : moved.views) v.clipFromView = move * v.clipFromView;
    moved.clipJitter = rig.clipJitter + j;
    return moved;
}

void accumulateSamples(const std::uint8_t* bytes, std::uint16_t* sums, std::size_t count) {
    const std::uint8_t* __restrict c = bytes;
    std::uint16_t* __restrict sum = sums;
    for (std::size_t i = 0; i < count; ++i) sum[i] = std::uint16_t(sum[i] + c[i]);
}

void resolveSampleSums(const std::uint16_t* sums, std::uint8_t* out, std::size_t count,
                       int samples) {
    // samples is a power of two: (sum + n/2) / n as a shift (vectorised; a division is not).
    const unsigned half = unsigned(samples) / 2,
                   shift = samples == 2 ? 1 : samples == 4 ? 2 : samples == 8 ? 3 : 0;
    const std::uint16_t* __restrict s = sums;
    std::uint8_t* __restrict c = out;
    for (std::size_t i = 0; i < count; ++i) c[i] = std::uint8_t((s[i] + half) >> shift);
}

Status renderSampled(Backend& backend, const Scene& scene, const Rig& rig,
                     const RenderSettings& settings, const std::string& method,
                     RenderOutput& out) {
    if (Status s = validateSettings(settings); !s) return s;  // the sample count among them
    RenderSettings one = settings;
    one.samples = 1;
    if (settings.samples == 1) return backend.renderInto(scene, rig, one, method, out);
    if (Status s = validateRequest(scene, rig, one); !s) return s;
    const int n = settings.samples, w = settings.width, h = settings.height;
    const std::size_t views = std::size_t(rig.viewCount());
    const std::size_t bytes = std::size_t(w) * std::size_t(h) * 4;
    // The sums and the later passes' images live on between calls (a sequence's frames, a
    // viewer's): no allocation and no page faults after the first frame of a size.
    thread_local RenderOutput pass;
    thread_local std::vector<std::uint16_t> sums;
    auto check = [&](const RenderOutput& o) {
        return o.color.size() == views ? Status() : internalError(fmt::format(
            "backend returned {} images for {} views", o.color.size(), views));
    };
    // Sample 0 straight into `out` (the caller's memory, its depth kept as the start of the
    // nearest-sample depth); the others into the scratch output, added and min-ed in.
    if (Status s = backend.renderInto(scene, offsetRig(rig, samplePositions(n)[0], w, h), one,
                                      method, out); !s)
        return s;
    if (Status s = check(out); !s) return s;
    sums.resize(views * bytes);
    // Per view on the machine's cores (the calling thread's thread_local buffers named here:
    // a worker's own would be empty).
    std::uint16_t* const sumBase = sums.data();
    RenderOutput& scratch = pass;
    const bool parallel = views * bytes >= (std::size_t(1) << 20);
    detail::parallelFor(int(views), parallel, [&](int v) {
        const std::uint8_t* __restrict c = out.color[std::size_t(v)].rgba.data();
        std::uint16_t* __restrict sum = sumBase + std::size_t(v) * bytes;
        for (std::size_t i = 0; i < bytes; ++i) sum[i] = c[i];
    });
    one.output = nullptr;
    StageTimes stages = out.stages;
    for (int k = 1; k < n; ++k) {
        const Rig moved = offsetRig(rig, samplePositions(n)[std::size_t(k)], w, h);
        if (Status s = backend.renderInto(scene, moved, one, method, scratch); !s) return s;
        if (Status s = check(scratch); !s) return s;
        const std::size_t depthViews = std::min(out.depth.size(), scratch.depth.size());
        detail::parallelFor(int(views), parallel, [&](int v) {
            accumulateSamples(scratch.color[std::size_t(v)].rgba.data(),
                              sumBase + std::size_t(v) * bytes, bytes);
            if (std::size_t(v) >= depthViews) return;
            float* __restrict d = out.depth[std::size_t(v)].depth.data();
            const float* __restrict p = scratch.depth[std::size_t(v)].depth.data();
            for (std::size_t i = 0; i < bytes / 4; ++i) d[i] = std::min(d[i], p[i]);
        });
        for (std::size_t v = 0; v < std::min(out.depthRange.size(), scratch.depthRange.size());
             ++v) {
            DepthRange& r = out.depthRange[v];
            r.nearest = std::min(r.nearest, scratch.depthRange[v].nearest);
            r.farthest = std::max(r.farthest, scratch.depthRange[v].farthest);
        }
        stages.vertexMs += scratch.stages.vertexMs;
        stages.setupMs += scratch.stages.setupMs;
        stages.rasterMs += scratch.stages.rasterMs;
        stages.fillMs += scratch.stages.fillMs;
    }
    out.stages = stages;
    detail::parallelFor(int(views), parallel, [&](int v) {
        resolveSampleSums(sumBase + std::size_t(v) * bytes, out.color[std::size_t(v)].rgba.data(),
                          bytes, n);
    });
    return {};
}

}  // namespace mvr
