// src/core/angular_aa.cpp — the depth-dependent box prefilter of mvr/core/angular_aa.h.
#include "mvr/core/angular_aa.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <fmt/core.h>

#include "mvr/core/stereo_surfaces.h"

namespace mvr {

namespace {

// Views whose other shear differs by less than this share a row (or a column).
constexpr float kSameShear = 1e-5f;

// The mean of the gaps from `v`'s shear along `axis` to the nearest views on either side among
// the views on the same line (the other axis' shear within kSameShear); 0 without one.
float meanGap(const Rig& rig, int v, int axis) {
    const glm::vec2 s = *rig.views[v].clipShear;
    const int other = 1 - axis;
    float below = std::numeric_limits<float>::infinity(), above = below;
    for (int u = 0; u < rig.viewCount(); ++u) {
        const glm::vec2 t = *rig.views[u].clipShear;
        if (u == v || std::abs(t[other] - s[other]) > kSameShear) continue;
        const float d = t[axis] - s[axis];
        if (d > kSameShear) above = std::min(above, d);
        if (d < -kSameShear) below = std::min(below, -d);
    }
    const bool a = std::isfinite(above), b = std::isfinite(below);
    if (a && b) return 0.5f * (above + below);
    return a ? above : b ? below : 0.0f;
}

// One line of n pixels (RGBA8, `stride` bytes apart; `in` and `out` distinct), kernel widths
// `k` (`kStride` floats apart): the overlap-weighted box of angular_aa.h.
void filterLine(const std::uint8_t* in, std::uint8_t* out, std::ptrdiff_t stride, const float* k,
                std::ptrdiff_t kStride, int n) {
    for (int x = 0; x < n; ++x) {
        const float kx = k[x * kStride];
        const std::uint8_t* src = in + x * stride;
        std::uint8_t* dst = out + x * stride;
        if (kx <= 1e-6f) {
            std::memcpy(dst, src, 4);
            continue;
        }
        const float c = float(x) + 0.5f, lo = c - 0.5f * kx, hi = c + 0.5f * kx;
        const int j0 = std::max(0, int(std::floor(lo))), j1 = std::min(n - 1, int(std::ceil(hi)) - 1);
        float sum[4] = {0, 0, 0, 0}, weight = 0.0f;
        for (int j = j0; j <= j1; ++j) {
            // A neighbour takes part only where its own kernel reaches this pixel.
            if (j != x && float(std::abs(j - x)) >= 0.5f * k[j * kStride] + 0.5f) continue;
            const float wj = std::min(float(j + 1), hi) - std::max(float(j), lo);
            if (wj <= 0.0f) continue;
            const std::uint8_t* p = in + j * stride;
            for (int ch = 0; ch < 4; ++ch) sum[ch] += wj * float(p[ch]);
            weight += wj;
        }
        for (int ch = 0; ch < 4; ++ch)
            dst[ch] = std::uint8_t(std::clamp(std::lround(sum[ch] / weight), 0L, 255L));
    }
}

}  // namespace

glm::vec2 adjacentShearStep(const Rig& rig, int view) {
    glm::vec2 step(meanGap(rig, view, 0), meanGap(rig, view, 1));
    const float tanHalf = std::tan(glm::radians(rig.camera.fovYDegrees) * 0.5f);
    if (step.x == 0.0f && rig.columns > 1 && rig.screenWidth() > 0.0f)
        step.x = 2.0f * rig.interaxial / rig.screenWidth();
    if (step.y == 0.0f && rig.rows > 1 && rig.convergence * tanHalf > 0.0f)
        step.y = rig.interaxialY / (rig.convergence * tanHalf);
    return step;
}

float angularKernelWidth(float shearStep, int extentPx, float convergence, float distance,
                         float scale) {
    if (!(distance > 0.0f) || !std::isfinite(distance)) return 0.0f;
    const float step =
        0.5f * float(extentPx) * std::abs(shearStep) * std::abs(1.0f - convergence / distance);
    return std::min(std::max(0.0f, step - 1.0f) * scale, float(extentPx));
}

Status applyAngularAA(const Rig& rig, std::vector<Image>& color,
                      const std::vector<DepthImage>& depth, float scale) {
    if (!std::isfinite(scale) || scale <= 0.0f) {
        return usageError(fmt::format(
            "applyAngularAA(): scale {} is out of range (expected a finite scale > 0)", scale));
    }
    if (depth.empty()) {
        return Status(ErrorCode::Unsupported, "angular anti-aliasing needs a depth buffer");
    }
    if (color.size() != rig.views.size() || depth.size() != rig.views.size()) {
        return usageError(fmt::format("applyAngularAA(): {} color and {} depth images for {} views",
                                      color.size(), depth.size(), rig.views.size()));
    }
    for (int v = 0; v < rig.viewCount(); ++v) {
        if (!rig.views[v].clipShear) {
            return Status(ErrorCode::Unsupported,
                          fmt::format("angular anti-aliasing needs an off-axis rig (view {} has no "
                                      "clip shear: toe-in, parallel, screen and list rigs)",
                                      v));
        }
        if (color[v].width != depth[v].width || color[v].height != depth[v].height) {
            return usageError(fmt::format("applyAngularAA(): view {}: color {}x{}, depth {}x{}", v,
                                          color[v].width, color[v].height, depth[v].width,
                                          depth[v].height));
        }
    }
    std::vector<float> kx, ky;
    std::vector<std::uint8_t> copy;
    for (int v = 0; v < rig.viewCount(); ++v) {
        Image& img = color[v];
        const int w = img.width, h = img.height;
        if (img.empty()) continue;
        const View& view = rig.views[v];
        const glm::vec2 step = adjacentShearStep(rig, v);
        const std::size_t n = std::size_t(w) * h;
        kx.assign(n, 0.0f);
        ky.assign(n, 0.0f);
        bool anyX = false, anyY = false;
        for (std::size_t i = 0; i < n; ++i) {
            const float dist = eyeDistance(view, depth[v].depth[i]);
            kx[i] = angularKernelWidth(step.x, w, rig.convergence, dist, scale);
            ky[i] = angularKernelWidth(step.y, h, rig.convergence, dist, scale);
            anyX = anyX || kx[i] > 0.0f;
            anyY = anyY || ky[i] > 0.0f;
        }
        const std::ptrdiff_t rowBytes = std::ptrdiff_t(w) * 4;
        if (anyX) {
            copy.assign(img.rgba.begin(), img.rgba.end());
            for (int y = 0; y < h; ++y)
                filterLine(copy.data() + y * rowBytes, img.row(y), 4, kx.data() + std::size_t(y) * w,
                           1, w);
        }
        if (anyY) {
            copy.assign(img.rgba.begin(), img.rgba.end());
            for (int x = 0; x < w; ++x)
                filterLine(copy.data() + x * 4, img.rgba.data() + x * 4, rowBytes, ky.data() + x, w,
                           h);
        }
    }
    return {};
}

}  // namespace mvr
