#include "mvr/core/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <new>

#include <fmt/core.h>

#include "mvr/core/antialias.h"

namespace mvr {

Status validateSettings(const RenderSettings& s) {
    constexpr int kMaxSize = 16384;
    if (s.width < 1 || s.height < 1 || s.width > kMaxSize || s.height > kMaxSize) {
        return usageError(fmt::format("image size {}x{} is out of range (expected 1..{} each)",
                                      s.width, s.height, kMaxSize));
    }
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(s.clearColor[i])) return usageError("clear color is not finite");
    }
    if (!validSampleCount(s.samples))
        return usageError(fmt::format("{} samples a pixel (expected 1, 2, 4 or 8)", s.samples));
    return {};
}

namespace {

bool finiteMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

Status validateRig(const Rig& rig) {
    if (rig.viewCount() < 1 || rig.viewCount() > kMaxViews) {
        return usageError(
            fmt::format("the rig has {} views (expected 1..{})", rig.viewCount(), kMaxViews));
    }
    if (!std::isfinite(rig.convergence)) return usageError("the rig's convergence is not finite");
    for (int v = 0; v < rig.viewCount(); ++v) {
        const View& view = rig.views[std::size_t(v)];
        if (!finiteMatrix(view.clipFromWorld()) ||
            (view.clipShear &&
             !(std::isfinite(view.clipShear->x) && std::isfinite(view.clipShear->y)))) {
            return usageError(fmt::format("view {} has a non-finite matrix or shear", v));
        }
    }
    if (!finiteMatrix(rig.camera.clipFromView() * rig.camera.viewFromWorld())) {
        return usageError("the rig's center camera has a non-finite matrix");
    }
    return {};
}

}  // namespace

DepthRange depthRangeOfImage(std::span<const float> depth) {
    // Four lanes at a time (GCC / Clang vector extensions: one minps, one cmpltps + and, one
    // maxps a step): the nearest is the plain minimum (nothing drawn is 1.0, the start value),
    // the farthest the maximum of the depths below 1 (NaN compares false: skipped).
    using Lanes = float __attribute__((vector_size(16)));
    const Lanes ones = {1.0f, 1.0f, 1.0f, 1.0f}, zeros = {};
    Lanes lo = ones, hi = zeros;
    const float* d = depth.data();
    const std::size_t n = depth.size();
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        Lanes z;
        std::memcpy(&z, d + i, sizeof z);
        lo = z < lo ? z : lo;
        const Lanes below = z < ones ? z : zeros;
        hi = below > hi ? below : hi;
    }
    for (; i < n; ++i) {
        if (d[i] < 1.0f) lo[0] = std::min(lo[0], d[i]), hi[0] = std::max(hi[0], d[i]);
    }
    DepthRange range;
    const float nearest = std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3]));
    const float farthest = std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]));
    if (nearest < 1.0f) range = {nearest, farthest};
    return range;
}

std::optional<DepthRange> depthRangeOf(const RenderOutput& out, int view) {
    if (view < 0) return std::nullopt;
    const auto v = std::size_t(view);
    if (v < out.depth.size()) return depthRangeOfImage(out.depth[v].depth);
    if (out.depth.empty() && v < out.depthRange.size()) return out.depthRange[v];
    return std::nullopt;
}

double framebufferBytes(int views, int width, int height) {
    return 8.0 * double(width) * double(height) * double(views);
}

Status validateRequest(const Scene& scene, const Rig& rig, const RenderSettings& settings) {
    if (Status s = validateSettings(settings); !s) return s;
    if (Status s = validateScene(scene); !s) return s;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        if (!finiteMatrix(scene.instances[i].worldFromModel)) {
            return usageError(fmt::format("scene instance {} has a non-finite transform", i));
        }
    }
    if (Status s = validateRig(rig); !s) return s;
    const double bytes = framebufferBytes(rig.viewCount(), settings.width, settings.height);
    if (bytes > kMaxFramebufferBytes) {
        return unsupportedError(fmt::format(
            "{} views of {}x{} need {:.1f} GiB of color and depth images (limit {:.0f} GiB)",
            rig.viewCount(), settings.width, settings.height, bytes / 1073741824.0,
            kMaxFramebufferBytes / 1073741824.0));
    }
    return {};
}

Result<Shading> parseShading(const std::string& name) {
    if (name == "flat") return Shading::Flat;
    if (name == "vertex") return Shading::Vertex;
    if (name == "pixel") return Shading::Pixel;
    return usageError(fmt::format("unknown shading '{}' (expected flat, vertex or pixel)", name));
}

const char* shadingName(Shading shading) {
    switch (shading) {
        case Shading::Flat: return "flat";
        case Shading::Vertex: return "vertex";
        case Shading::Pixel: return "pixel";
    }
    return "?";
}

}  // namespace mvr

namespace mvr {

/// Hands out one slice, once, to an allocation of exactly its size; the rest from the heap.
class OutputBlock::Slice final : public std::pmr::memory_resource {
public:
    Slice(void* p, std::size_t bytes) : p_(p), bytes_(bytes) {}

private:
    void* do_allocate(std::size_t bytes, std::size_t align) override {
        if (bytes == bytes_ && !taken_.exchange(true)) return p_;
        return std::pmr::new_delete_resource()->allocate(bytes, align);
    }
    void do_deallocate(void* p, std::size_t bytes, std::size_t align) override {
        if (p == p_) {
            taken_ = false;
            return;
        }
        std::pmr::new_delete_resource()->deallocate(p, bytes, align);
    }
    bool do_is_equal(const std::pmr::memory_resource& o) const noexcept override {
        return this == &o;
    }
    void* p_;
    std::size_t bytes_;
    std::atomic<bool> taken_{false};
};

namespace {
constexpr std::align_val_t kBlockAlign{64};
}

OutputBlock::OutputBlock(int views, int width, int height)
    : views_(views), width_(width), height_(height) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    const std::size_t views_n = std::size_t(std::max(views, 0));
    color_ = static_cast<std::uint8_t*>(
        ::operator new(std::max<std::size_t>(n * 4 * views_n, 1), kBlockAlign));
    depth_ = static_cast<float*>(
        ::operator new(std::max<std::size_t>(n * sizeof(float) * views_n, 1), kBlockAlign));
    slices_.reserve(2 * views_n);
    for (std::size_t v = 0; v < views_n; ++v) {
        slices_.push_back(std::make_unique<Slice>(color_ + v * n * 4, n * 4));
        slices_.push_back(std::make_unique<Slice>(depth_ + v * n, n * sizeof(float)));
    }
}

OutputBlock::~OutputBlock() {
    ::operator delete(color_, kBlockAlign);
    ::operator delete(depth_, kBlockAlign);
}

std::pmr::memory_resource* OutputBlock::colorMemory(int view) {
    return view >= 0 && view < views_ ? slices_[std::size_t(view) * 2].get() : nullptr;
}

std::pmr::memory_resource* OutputBlock::depthMemory(int view) {
    return view >= 0 && view < views_ ? slices_[std::size_t(view) * 2 + 1].get() : nullptr;
}

bool OutputBlock::inPlace(const Image& image, int view) const {
    const std::size_t n = std::size_t(width_) * std::size_t(height_);
    return view >= 0 && view < views_ && image.width == width_ && image.height == height_ &&
           image.rgba.size() == n * 4 && image.rgba.data() == color_ + std::size_t(view) * n * 4;
}

bool OutputBlock::inPlace(const DepthImage& image, int view) const {
    const std::size_t n = std::size_t(width_) * std::size_t(height_);
    return view >= 0 && view < views_ && image.width == width_ && image.height == height_ &&
           image.depth.size() == n && image.depth.data() == depth_ + std::size_t(view) * n;
}

}  // namespace mvr
