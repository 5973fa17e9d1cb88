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
    if (!validSampleCount(settings.samples)) {
        return usageError(fmt::format("{} samples a pixel (expected 1, 2, 4 or 8)", settings.samples));
    }
    RenderSettings one = settings;
    one.samples = 1;
    if (settings.samples == 1) return backend.renderInto(scene, rig, one, method, out);
    if (Status s = validateRequest(scene, rig, one); !s) return s;
    one.output = nullptr;  // the passes are scratch; the resolve goes to the caller's memory
    const int n = settings.samples, w = settings.width, h = settings.height;
    const int views = rig.viewCount();
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    std::vector<std::vector<std::uint16_t>> sums(static_cast<std::size_t>(views));
    RenderOutput pass;
    for (int k = 0; k < n; ++k) {
        const Rig moved = offsetRig(rig, samplePositions(n)[std::size_t(k)], w, h);
        if (Status s = backend.renderInto(scene, moved, one, method, pass); !s) return s;
        if (int(pass.color.size()) != views) {
            return internalError(fmt::format("backend returned {} images for {} views",
                                             pass.color.size(), views));
        }
        if (k == 0) {
            out.depth.resize(pass.depth.size());
            for (std::size_t v = 0; v < pass.depth.size(); ++v) {
                out.depth[v].reuseOrReset(w, h, settings.output ? settings.output->depthMemory(int(v)) : nullptr);
                std::copy(pass.depth[v].depth.begin(), pass.depth[v].depth.end(), out.depth[v].depth.begin());
            }
            out.depthRange = pass.depthRange;
            out.method = pass.method;
            out.note = pass.note;
            out.stages = {};
        } else {
            for (std::size_t v = 0; v < std::min(out.depth.size(), pass.depth.size()); ++v) {
                float* d = out.depth[v].depth.data();
                const float* p = pass.depth[v].depth.data();
                for (std::size_t i = 0; i < pixels; ++i) d[i] = std::min(d[i], p[i]);
            }
            for (std::size_t v = 0; v < std::min(out.depthRange.size(), pass.depthRange.size()); ++v) {
                out.depthRange[v].nearest = std::min(out.depthRange[v].nearest, pass.depthRange[v].nearest);
                out.depthRange[v].farthest = std::max(out.depthRange[v].farthest, pass.depthRange[v].farthest);
            }
        }
        out.stages.vertexMs += pass.stages.vertexMs;
        out.stages.setupMs += pass.stages.setupMs;
        out.stages.rasterMs += pass.stages.rasterMs;
        out.stages.fillMs += pass.stages.fillMs;
        for (int v = 0; v < views; ++v) {
            std::vector<std::uint16_t>& sum = sums[std::size_t(v)];
            const std::uint8_t* c = pass.color[std::size_t(v)].rgba.data();
            if (k == 0) {
                sum.assign(c, c + pixels * 4);
            } else {
                for (std::size_t i = 0; i < pixels * 4; ++i) sum[i] = std::uint16_t(sum[i] + c[i]);
            }
        }
    }
    out.color.resize(std::size_t(views));
    for (int v = 0; v < views; ++v) {
        Image& img = out.color[std::size_t(v)];
        img.reuseOrReset(w, h, settings.output ? settings.output->colorMemory(v) : nullptr);
        const std::vector<std::uint16_t>& sum = sums[std::size_t(v)];
        const unsigned half = unsigned(n) / 2;
        for (std::size_t i = 0; i < pixels * 4; ++i)
            img.rgba[i] = std::uint8_t((unsigned(sum[i]) + half) / unsigned(n));
    }
    return {};
}

}  // namespace mvr
