// src/core/synthesize.cpp — view synthesis from depth (mvr/core/synthesize.h).
#include "mvr/core/synthesize.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <thread>

#include <fmt/core.h>

#include "mvr/core/stereo_surfaces.h"

namespace mvr {

namespace {

/// A target pixel nothing has landed on yet (window depths are ≤ 1).
constexpr float kHole = 2.0f;

/// Per pixel of an exact view, a = 1 − C / w (w: the eye-space distance of its depth), so that
/// its shift into a view whose shear differs by ds is ds · a · W / 2. 1 / w is affine in the
/// window depth d: 1 / w = (2d − 1 + A) / B (eyeDistance()).
void parallaxFactors(const View& view, float convergence, const DepthImage& depth,
                     std::vector<float>& a) {
    const float pa = view.clipFromView[2][2], pb = view.clipFromView[3][2];
    a.resize(depth.depth.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        const float invW = ((2.0f * depth.depth[i] - 1.0f) + pa) / pb;
        a[i] = 1.0f - convergence * invW;
    }
}

struct Source {
    const Image* color = nullptr;
    const DepthImage* depth = nullptr;
    const float* factor = nullptr;  ///< per pixel, 1 − C / w
    float shear = 0.0f;  ///< clipShear.x
};

/// The largest stretch (pixels) between the landing points of two adjacent source pixels that
/// still counts as one surface: beyond it the surfaces parted (a disocclusion), below zero they
/// crossed (an occlusion); either way the two are not joined.
constexpr float kMaxStretch = 2.0f;

/// ⌈x⌉ for the pixel positions here (|x| well inside int's range): std::ceil is a libm call on
/// the baseline x86-64 this file is built for.
inline int ceilInt(float x) {
    x = std::clamp(x, -1e8f, 1e8f);  // finite here (a join's span is); within int's range
    const int i = int(x);
    return i + (float(i) < x ? 1 : 0);
}

/// Forward-warps `sources` (nearer first) into one target view, then fills its holes. Adjacent
/// source pixels of one surface (landing at most kMaxStretch apart, in order) are joined: the
/// target pixels whose centres lie between their landing points take the colour and depth
/// interpolated linearly between them (a one-dimensional mesh warp, so a fractional shift
/// resamples rather than rounds, and a stretched surface leaves no cracks). A pixel at either
/// end of a run of joined pixels also lands on the pixel its point falls in.
void warpView(const Source* sources, int count, float shear, Image& color, DepthImage& depth,
              float maxStretch = kMaxStretch) {
    const int w = color.width, h = color.height;
    std::fill(depth.depth.begin(), depth.depth.end(), kHole);
    for (int s = 0; s < count; ++s) {
        const Source& src = sources[s];
        const float k = (shear - src.shear) * 0.5f * float(w);
        for (int y = 0; y < h; ++y) {
            const std::size_t row = std::size_t(y) * w;
            // A later source only where the earlier ones left holes in the row: what it adds
            // elsewhere would lose the depth test or tie (a surface one source sees in front of
            // another's is a hole in the other's warp, not a pixel of it).
            if (s > 0 && std::find(depth.depth.begin() + std::ptrdiff_t(row),
                                   depth.depth.begin() + std::ptrdiff_t(row + w),
                                   kHole) == depth.depth.begin() + std::ptrdiff_t(row + w))
                continue;
            const float* fa = src.factor + row;
            const float* sd = src.depth->depth.data() + row;
            const std::uint8_t* sc = src.color->row(y);
            float* td = depth.depth.data() + row;
            std::uint8_t* tc = color.row(y);
            float p = 0.5f + k * fa[0];
            bool joinedLeft = false;
            for (int x = 0; x < w; ++x) {
                const float q = x + 1 < w ? float(x + 1) + 0.5f + k * fa[x + 1] : 0.0f;
                const float span = q - p;
                // Background (nothing drawn) is no surface: never joined to one.
                const bool joinedRight = x + 1 < w && span > 0.0f && span <= maxStretch &&
                                         (sd[x] >= 1.0f) == (sd[x + 1] >= 1.0f);
                if (joinedRight) {
                    // Target centres c = t + ½ in [p, q).
                    const int first = std::max(0, ceilInt(p - 0.5f));
                    const int last = std::min(w, ceilInt(q - 0.5f));
                    const float inv = 1.0f / span;
                    for (int tx = first; tx < last; ++tx) {
                        const float t = (float(tx) + 0.5f - p) * inv;
                        const float d = sd[x] + t * (sd[x + 1] - sd[x]);
                        if (d < td[tx]) {
                            td[tx] = d;
                            // Colour in 8-bit fixed point: (c0 · (256 − f) + c1 · f + 128) / 256.
                            const int f = int(t * 256.0f + 0.5f);
                            const std::uint8_t* c0 = sc + 4 * x;
                            std::uint8_t* out = tc + 4 * tx;
                            for (int c = 0; c < 4; ++c)
                                out[c] = std::uint8_t((c0[c] * (256 - f) + c0[4 + c] * f + 128) >> 8);
                        }
                    }
                }
                // The end of a run (not joined on one side) also lands on the pixel its point
                // falls in: a silhouette keeps its edge pixel whichever side of a pixel centre
                // the point falls.
                if ((!joinedLeft || !joinedRight) && p >= 0.0f && p < float(w)) {
                    const int tx = int(p);
                    if (sd[x] < td[tx]) {
                        td[tx] = sd[x];
                        std::memcpy(tc + 4 * tx, sc + 4 * x, 4);
                    }
                }
                joinedLeft = joinedRight;
                p = q;
            }
        }
    }
    // Holes. Background (depth 1) is no surface at a depth: where a source sees nothing at the
    // same pixel, the target is taken to see nothing too (the space between two objects that
    // neither source sees past, since both occlude it from their side, is empty, not the
    // farther object's). The rest take the colour and depth of the farther of the nearest
    // filled pixels on either side of their run: what a disocclusion uncovers lies behind.
    for (int y = 0; y < h; ++y) {
        const std::size_t row = std::size_t(y) * w;
        float* td = depth.depth.data() + row;
        std::uint8_t* tc = color.row(y);
        for (int x = 0; x < w; ++x) {
            if (td[x] != kHole) continue;
            for (int s = 0; s < count; ++s) {
                if (sources[s].depth->depth[row + x] >= 1.0f) {
                    td[x] = sources[s].depth->depth[row + x];
                    std::memcpy(tc + 4 * x, sources[s].color->row(y) + 4 * x, 4);
                    break;
                }
            }
        }
        for (int x = 0; x < w;) {
            if (td[x] != kHole) {
                ++x;
                continue;
            }
            int end = x;
            while (end < w && td[end] == kHole) ++end;
            const int left = x - 1, right = end < w ? end : -1;
            int from = -1;
            if (left >= 0 && right >= 0)
                from = td[left] >= td[right] ? left : right;
            else
                from = left >= 0 ? left : right;
            for (int i = x; i < end; ++i) {
                if (from >= 0) {
                    td[i] = td[from];
                    std::memcpy(tc + 4 * i, tc + 4 * from, 4);
                } else {  // nothing landed on the whole row: the nearer source's row
                    td[i] = sources[0].depth->depth[row + i];
                    std::memcpy(tc + 4 * i, sources[0].color->row(y) + 4 * i, 4);
                }
            }
            x = end;
        }
    }
}

/// body(i) for i in 0..count − 1, spread over `threads` workers (0: one per core).
template <class Body>
void forEachParallel(int count, int threads, Body&& body) {
    std::atomic<int> next{0};
    auto work = [&] {
        for (int i = next++; i < count; i = next++) body(i);
    };
    const int hw = threads > 0 ? threads : int(std::thread::hardware_concurrency());
    const int workers = std::clamp(hw, 1, std::max(1, count));
    std::vector<std::thread> pool;
    for (int t = 1; t < workers; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
}

}  // namespace

std::vector<int> exactColumns(int columns, int k) {
    std::vector<int> cols;
    if (columns <= 0) return cols;
    k = std::max(k, 1);
    for (int c = 0; c < columns; c += k) cols.push_back(c);
    if (cols.back() != columns - 1) cols.push_back(columns - 1);
    return cols;
}

std::vector<int> exactViews(const Rig& rig, int k) {
    std::vector<int> views;
    for (int r = 0; r < rig.rows; ++r)
        for (int c : exactColumns(rig.columns, k)) views.push_back(r * rig.columns + c);
    return views;
}

std::vector<char> exactMask(int viewCount, const std::vector<int>& exact) {
    std::vector<char> mask(std::size_t(std::max(viewCount, 0)), 0);
    for (int v : exact) mask[std::size_t(v)] = 1;
    return mask;
}

Status checkSynthesisRig(const Rig& rig, const std::string& option) {
    if (rig.columns * rig.rows != rig.viewCount() || rig.columns < 3) {
        return usageError(fmt::format(
            "{}: needs rows of at least 3 views (the rig has {} view{} in {} row{})", option,
            rig.viewCount(), rig.viewCount() == 1 ? "" : "s", rig.rows, rig.rows == 1 ? "" : "s"));
    }
    for (const View& v : rig.views) {
        if (!v.clipShear) {
            return usageError(fmt::format(
                "{}: needs an off-axis rig (the warp is the horizontal shear between its views; "
                "--rig {} has none)",
                option, rig.screen ? "screen" : rigKindName(rig.kind)));
        }
    }
    return {};
}

Rig subRig(const Rig& rig, const std::vector<int>& views) {
    Rig sub = rig;
    sub.views.clear();
    for (int v : views) sub.views.push_back(rig.views[std::size_t(v)]);
    sub.columns = rig.rows > 0 ? int(views.size()) / rig.rows : int(views.size());
    return sub;
}

Status synthesizeViews(const Rig& rig, const std::vector<int>& exact, RenderOutput& out,
                       int threads) {
    if (Status s = checkSynthesisRig(rig, "view synthesis"); !s) return s;
    const int n = rig.viewCount();
    if (int(out.color.size()) != n || int(out.depth.size()) != n)
        return internalError(fmt::format("view synthesis: {} colour and {} depth images for {} views",
                                         out.color.size(), out.depth.size(), n));
    const int w = out.color.front().width, h = out.color.front().height;
    for (int v = 0; v < n; ++v) {
        if (out.color[v].width != w || out.color[v].height != h || out.depth[v].width != w ||
            out.depth[v].height != h)
            return internalError(fmt::format("view synthesis: view {} is not {}x{}", v, w, h));
    }
    for (int v : exact)
        if (v < 0 || v >= n) return internalError(fmt::format("view synthesis: no view {}", v));
    const std::vector<char> isExact = exactMask(n, exact);
    for (int r = 0; r < rig.rows; ++r) {
        if (!isExact[std::size_t(r * rig.columns)] || !isExact[std::size_t(r * rig.columns + rig.columns - 1)])
            return internalError(fmt::format("view synthesis: row {}'s ends are not exact", r));
    }
    // The parallax factors of every exact view, then the targets, one worker per core.
    std::vector<std::vector<float>> factors(static_cast<std::size_t>(n));
    for (int v : exact) parallaxFactors(rig.views[v], rig.convergence, out.depth[v], factors[v]);
    std::vector<int> targets;
    for (int v = 0; v < n; ++v)
        if (!isExact[std::size_t(v)]) targets.push_back(v);
    forEachParallel(int(targets.size()), threads, [&](int i) {
            const int t = targets[std::size_t(i)];
            const int row = t / rig.columns, col = t % rig.columns;
            int left = col, right = col;
            while (!isExact[std::size_t(row * rig.columns + left)]) --left;
            while (!isExact[std::size_t(row * rig.columns + right)]) ++right;
            const int a = row * rig.columns + left, b = row * rig.columns + right;
            Source src[2];
            auto source = [&](int v) {
                return Source{&out.color[v], &out.depth[v], factors[v].data(),
                              rig.views[v].clipShear->x};
            };
            // The nearer exact view first: it keeps the ties.
            const bool leftNearer = col - left <= right - col;
            src[0] = source(leftNearer ? a : b);
            src[1] = source(leftNearer ? b : a);
            warpView(src, 2, rig.views[t].clipShear->x, out.color[t], out.depth[t]);
    });
    return {};
}

Result<std::vector<Image>> warpFromView(const Image& color, const DepthImage& depth,
                                        std::span<const float> factor,
                                        std::span<const float> shears, float maxStretch,
                                        int threads) {
    const std::size_t pixels = std::size_t(color.width) * std::size_t(color.height);
    if (color.width < 1 || color.height < 1 || depth.width != color.width ||
        depth.height != color.height || depth.depth.size() != pixels || factor.size() != pixels)
        return internalError(fmt::format(
            "view synthesis: a {}x{} colour image with a {}x{} depth image and {} factors",
            color.width, color.height, depth.width, depth.height, factor.size()));
    std::vector<Image> views(shears.size());
    forEachParallel(int(shears.size()), threads, [&](int i) {
        views[std::size_t(i)] = Image(color.width, color.height);
        DepthImage scratch(color.width, color.height);
        const Source src{&color, &depth, factor.data(), 0.0f};
        warpView(&src, 1, shears[std::size_t(i)], views[std::size_t(i)], scratch, maxStretch);
    });
    return views;
}

Status renderSynthesizedInto(Backend& backend, const Scene& scene, const Rig& rig,
                             const RenderSettings& settings, const std::string& method, int k,
                             RenderOutput& out) {
    if (k <= 1) return backend.renderInto(scene, rig, settings, method, out);
    if (Status s = checkSynthesisRig(rig, fmt::format("--synthesize {}", k)); !s) return s;
    const std::vector<int> exact = exactViews(rig, k);
    RenderSettings sub = settings;
    sub.depth = true;
    sub.output = nullptr;  // the views land in rig order below, not in the sub-rig's
    // The exact views' render, kept from frame to frame as a backend's renderInto keeps its
    // images; its images are swapped into `out` (and out's old ones back for the next frame).
    thread_local RenderOutput pass;
    if (Status s = backend.renderInto(scene, subRig(rig, exact), sub, method, pass); !s) {
        // The backend speaks of the sub-rig ("the rig has 3"): say which rig that is.
        return Status(s.code(), fmt::format("--synthesize {}: the {} exact views: {}", k,
                                            exact.size(), s.message()));
    }
    if (pass.depth.size() != exact.size()) {
        return unsupportedError(fmt::format(
            "--synthesize {}: --method {} gives no depth images to warp from", k, pass.method));
    }
    const int n = rig.viewCount();
    const int w = settings.width, h = settings.height;
    out.color.resize(std::size_t(n));
    out.depth.resize(std::size_t(n));
    out.depthRange.clear();
    out.method = pass.method;
    // What `mvr render` prints after the method: "--synthesize 4: 12 exact, 33 warped".
    out.note = fmt::format("--synthesize {}: {} exact, {} warped{}{}", k, exact.size(),
                           n - int(exact.size()), pass.note.empty() ? "" : "; ", pass.note);
    out.stages = pass.stages;
    for (std::size_t i = 0; i < exact.size(); ++i) {
        Image& c = out.color[std::size_t(exact[i])];
        DepthImage& d = out.depth[std::size_t(exact[i])];
        if (c.rgba.get_allocator() == pass.color[i].rgba.get_allocator() &&
            d.depth.get_allocator() == pass.depth[i].depth.get_allocator()) {
            std::swap(c, pass.color[i]);
            std::swap(d, pass.depth[i]);
        } else {
            c = pass.color[i];
            d = pass.depth[i];
        }
    }
    const std::vector<char> isExact = exactMask(n, exact);
    for (int v = 0; v < n; ++v) {
        if (isExact[std::size_t(v)]) continue;
        out.color[std::size_t(v)].reuseOrReset(w, h, nullptr);
        out.depth[std::size_t(v)].reuseOrReset(w, h, nullptr);
    }
    return synthesizeViews(rig, exact, out);
}

Result<RenderOutput> renderSynthesized(Backend& backend, const Scene& scene, const Rig& rig,
                                       const RenderSettings& settings, const std::string& method,
                                       int k) {
    if (k <= 1) return backend.render(scene, rig, settings, method);
    RenderOutput out;
    if (Status s = renderSynthesizedInto(backend, scene, rig, settings, method, k, out); !s)
        return s;
    return out;
}

}  // namespace mvr
