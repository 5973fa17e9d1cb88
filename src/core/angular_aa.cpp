// src/core/angular_aa.cpp — the depth-dependent box prefilter of mvr/core/angular_aa.h.
#include "mvr/core/angular_aa.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <thread>

#include <fmt/core.h>

#include "mvr/core/stereo_surfaces.h"

namespace mvr {

namespace {

// Views whose other shear differs by less than this share a row (or a column).
constexpr float kSameShear = 1e-5f;

// The mean of the gaps from shear `s` along `axis` to the nearest shears on either side among
// those on the same line (the other axis' shear within kSameShear); 0 without one.
float meanGap(glm::vec2 s, std::span<const glm::vec2> shears, int axis) {
    const int other = 1 - axis;
    float below = std::numeric_limits<float>::infinity(), above = below;
    for (const glm::vec2 t : shears) {
        if (std::abs(t[other] - s[other]) > kSameShear) continue;
        const float d = t[axis] - s[axis];
        if (d > kSameShear) above = std::min(above, d);
        if (d < -kSameShear) below = std::min(below, -d);
    }
    const bool a = std::isfinite(above), b = std::isfinite(below);
    if (a && b) return 0.5f * (above + below);
    return a ? above : b ? below : 0.0f;
}

std::uint32_t pixel(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

// One line of n pixels (RGBA8, `stride` bytes apart; `in` and `out` distinct), kernel widths
// `k` (`kStride` floats apart): the overlap-weighted box of angular_aa.h. `runs`: scratch.
void filterLine(const std::uint8_t* in, std::uint8_t* out, std::ptrdiff_t stride, const float* k,
                std::ptrdiff_t kStride, int n, std::vector<int>& runs) {
    // The run of equal pixels around each pixel (first, last): a kernel inside its run is a
    // copy (a background, a flat colour), whatever its width.
    runs.resize(2 * std::size_t(n));
    for (int x = 0; x < n; ++x)
        runs[2 * x] =
            x > 0 && pixel(in + x * stride) == pixel(in + (x - 1) * stride) ? runs[2 * (x - 1)] : x;
    for (int x = n - 1; x >= 0; --x)
        runs[2 * x + 1] = x + 1 < n && pixel(in + x * stride) == pixel(in + (x + 1) * stride)
                              ? runs[2 * (x + 1) + 1]
                              : x;
    for (int x = 0; x < n; ++x) {
        const float kx = k[x * kStride];
        const std::uint8_t* src = in + x * stride;
        std::uint8_t* dst = out + x * stride;
        if (kx <= 1e-6f) {
            std::memcpy(dst, src, 4);
            continue;
        }
        const float c = float(x) + 0.5f, lo = c - 0.5f * kx, hi = c + 0.5f * kx;
        const int j0 = std::max(0, int(std::floor(lo)));
        const int j1 = std::min(n - 1, int(std::ceil(hi)) - 1);
        if (runs[2 * x] <= j0 && runs[2 * x + 1] >= j1) {
            std::memcpy(dst, src, 4);
            continue;
        }
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

// One view: the kernel widths from its depth, then the horizontal and the vertical pass.
void filterView(const Rig& rig, int v, std::span<const glm::vec2> shears, Image& img,
                const DepthImage& depth, float scale, std::vector<float>& kx,
                std::vector<float>& ky, std::vector<std::uint8_t>& copy, std::vector<int>& runs) {
    const int w = img.width, h = img.height;
    if (img.empty()) return;
    const View& view = rig.views[v];
    const glm::vec2 step = adjacentShearStep(rig, v, shears);
    const std::size_t n = std::size_t(w) * h;
    kx.assign(n, 0.0f);
    ky.assign(n, 0.0f);
    bool anyX = false, anyY = false;
    for (std::size_t i = 0; i < n; ++i) {
        const float dist = eyeDistance(view, depth.depth[i]);
        kx[i] = angularKernelWidth(step.x, w, rig.convergence, dist, scale);
        ky[i] = angularKernelWidth(step.y, h, rig.convergence, dist, scale);
        anyX = anyX || kx[i] > 0.0f;
        anyY = anyY || ky[i] > 0.0f;
    }
    const std::ptrdiff_t rowBytes = std::ptrdiff_t(w) * 4;
    if (anyX) {
        copy.assign(img.rgba.begin(), img.rgba.end());
        for (int y = 0; y < h; ++y)
            filterLine(copy.data() + y * rowBytes, img.row(y), 4, kx.data() + std::size_t(y) * w, 1,
                       w, runs);
    }
    if (anyY) {
        copy.assign(img.rgba.begin(), img.rgba.end());
        for (int x = 0; x < w; ++x)
            filterLine(copy.data() + x * 4, img.rgba.data() + x * 4, rowBytes, ky.data() + x, w, h,
                       runs);
    }
}

}  // namespace

glm::vec2 adjacentShearStep(const Rig& rig, int view, std::span<const glm::vec2> shears) {
    std::vector<glm::vec2> own;
    if (shears.empty()) {
        for (const View& v : rig.views) own.push_back(*v.clipShear);
        shears = own;
    }
    const glm::vec2 s = *rig.views[view].clipShear;
    glm::vec2 step(meanGap(s, shears, 0), meanGap(s, shears, 1));
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
                      const std::vector<DepthImage>& depth, float scale,
                      std::span<const glm::vec2> shears) {
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
    std::vector<glm::vec2> own;
    if (shears.empty()) {
        for (const View& view : rig.views) own.push_back(*view.clipShear);
        shears = own;
    }
    // Views are independent: one worker per core takes the next view.
    std::atomic<int> next{0};
    auto work = [&] {
        std::vector<float> kx, ky;
        std::vector<std::uint8_t> copy;
        std::vector<int> runs;
        for (int v = next++; v < rig.viewCount(); v = next++)
            filterView(rig, v, shears, color[v], depth[v], scale, kx, ky, copy, runs);
    };
    const int workers =
        std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, rig.viewCount()));
    std::vector<std::thread> pool;
    for (int t = 1; t < workers; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    return {};
}

}  // namespace mvr
