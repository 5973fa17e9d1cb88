// antialias.cpp — N sub-pixel passes resolved (mvr/core/antialias.h).
#include "mvr/core/antialias.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

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
    for (std::size_t v = 0; v < views; ++v) {
        const std::uint8_t* __restrict c = out.color[v].rgba.data();
        std::uint16_t* __restrict sum = sums.data() + v * bytes;
        for (std::size_t i = 0; i < bytes; ++i) sum[i] = c[i];
    }
    one.output = nullptr;
    StageTimes stages = out.stages;
    for (int k = 1; k < n; ++k) {
        const Rig moved = offsetRig(rig, samplePositions(n)[std::size_t(k)], w, h);
        if (Status s = backend.renderInto(scene, moved, one, method, pass); !s) return s;
        if (Status s = check(pass); !s) return s;
        for (std::size_t v = 0; v < views; ++v) {
            const std::uint8_t* __restrict c = pass.color[v].rgba.data();
            std::uint16_t* __restrict sum = sums.data() + v * bytes;
            for (std::size_t i = 0; i < bytes; ++i) sum[i] = std::uint16_t(sum[i] + c[i]);
        }
        for (std::size_t v = 0; v < std::min(out.depth.size(), pass.depth.size()); ++v) {
            float* __restrict d = out.depth[v].depth.data();
            const float* __restrict p = pass.depth[v].depth.data();
            for (std::size_t i = 0; i < bytes / 4; ++i) d[i] = std::min(d[i], p[i]);
        }
        for (std::size_t v = 0; v < std::min(out.depthRange.size(), pass.depthRange.size()); ++v) {
            DepthRange& r = out.depthRange[v];
            r.nearest = std::min(r.nearest, pass.depthRange[v].nearest);
            r.farthest = std::max(r.farthest, pass.depthRange[v].farthest);
        }
        stages.vertexMs += pass.stages.vertexMs;
        stages.setupMs += pass.stages.setupMs;
        stages.rasterMs += pass.stages.rasterMs;
        stages.fillMs += pass.stages.fillMs;
    }
    out.stages = stages;
    // n is a power of two: (sum + n/2) / n as a shift (vectorised; a division is not).
    const unsigned half = unsigned(n) / 2, shift = n == 2 ? 1 : n == 4 ? 2 : 3;
    for (std::size_t v = 0; v < views; ++v) {
        std::uint8_t* __restrict c = out.color[v].rgba.data();
        const std::uint16_t* __restrict sum = sums.data() + v * bytes;
        for (std::size_t i = 0; i < bytes; ++i) c[i] = std::uint8_t((sum[i] + half) >> shift);
    }
    return {};
}

}  // namespace mvr
