// src/raster/lanes.h — coverage setup of many (triangle, view) pairs side by side.
//
// setupViews (cpu.h) runs one triangle's views in SIMD lanes; for a stereo pair that fills 2 of
// 8 lanes and pays the kernel's whole latency for every triangle. Here a band's raster loop
// queues the (triangle, view) pairs of consecutive small triangles — for a stereo pair 8
// triangles × 2 views — and sets them all up in one pass: per lane the triangle's snapped x in
// that view and its y setup (computed ONCE per triangle and family, then copied into each of its
// views' lanes: adelson1991's shared y). The integers are those of setupViews lane for lane, so
// images do not change; each view still receives its triangles in submission order.
//
// Where the kernels have one (Kernels::drawLanes, AVX-512) and the views' images are one block,
// a flush sets the lanes up and draws their covered centres side by side — a pass per centre of
// a lane, gathers and scatters — whenever that cannot differ from the ordered walk: no lane
// needs the general walk and no two fragments fall on one pixel (then their order cannot
// matter); otherwise the ordered walk draws the flush, as before.
#pragma once

#include <cstdint>
#include <cstring>

#include "pipeline.h"

namespace mvr::raster::detail {

inline constexpr int kLaneCount = 16;
/// Lanes of one triangle are appended 8 at a time (fixed-size copies; views past the family's
/// count are overwritten by the next triangle or never read): the arrays have room for that.
inline constexpr int kLaneBlock = 8;
inline constexpr int kLaneRoom = kLaneCount + kLaneBlock;

struct TriangleLanes {
    alignas(64) std::int32_t x[3][kLaneRoom];    ///< snapped window x of the lane's view
    alignas(64) std::int32_t y[3][kLaneRoom];    ///< snapped window y (the triangle's, shared)
    alignas(64) std::int32_t rowMin[kLaneRoom];  ///< YSetup rows, clamped to the band, not empty
    alignas(64) std::int32_t rowMax[kLaneRoom];
    ViewsSetup out;  ///< lane k's results in column k, as setupViews writes view k's
};

/// Lanes [0, n) of `l` (n <= kLaneCount): fills l.out like setupViews fills a view (mask, colMin,
/// area, e, sx, sy, bias) and returns the lanes whose mask is not 0 (bit k: lane k). A kernel of
/// cpu.h's table (Kernels::setupLanes): scalar, AVX2 and AVX-512 bit for bit the same, the SIMD
/// ones sharing their setupViews' code.
using SetupLanesFn = std::uint32_t (*)(TriangleLanes& l, int n, int width);

/// The queued slots' vertex colors by component (slot s in column s) for drawLanes, stored when
/// `colors`: the queue's owner sets it where a slot feeds several lanes (a family's views), and
/// a lane's colors are then its slot's column, picked in registers; else drawLanes reads them
/// from the slots' FragmentTri for the lanes that pass a depth test. (Depth, 1/w and the flat
/// color it gathers from the slots' FragmentTri.)
struct SlotColors {
    alignas(64) float a[3][3][kLaneCount];  ///< Vertex: channel c of vertex j
    bool colors = false;
};

/// Where drawLanes writes: view v's pixel (x, row) at depth[p] / color[p] with
/// p = v · viewStride + origin − row · width + x (every view's image in one block; a single
/// view: viewStride 0). origin = (height − 1) · width − Target::offset.
struct LaneImages {
    float* depth = nullptr;
    std::uint32_t* color = nullptr;
    std::int32_t viewStride = 0, origin = 0;
};

/// The LaneImages of `targets` (view v: targets[v]) when their depth and color images lie in one
/// block each at one stride, with one offset, and every pixel's offset fits 31 bits (a single
/// target always); else false.
inline bool laneImages(const Target* targets, std::size_t n, LaneImages& out) {
    if (n == 0) return false;
    const Target& t0 = targets[0];
    const std::int64_t origin = std::int64_t(t0.height - 1) * t0.width - std::int64_t(t0.offset);
    std::int64_t stride = 0;
    if (n > 1) stride = targets[1].depth - t0.depth;
    if (stride < 0) return false;
    for (std::size_t v = 0; v < n; ++v) {
        const Target& t = targets[v];
        const std::int64_t k = std::int64_t(v) * stride;
        if (t.depth - t0.depth != k || t.color - t0.color != k || t.offset != t0.offset ||
            t.width != t0.width || t.height != t0.height) {
            return false;
        }
    }
    if (std::int64_t(n - 1) * stride + origin + t0.width >= (std::int64_t(1) << 31)) return false;
    out = LaneImages{t0.depth, t0.color, std::int32_t(stride), std::int32_t(origin)};
    return true;
}

/// setupLanes and the fragments of lanes [0, n) at once, for untextured Vertex or Flat shading
/// (flat): every covered centre's depth test and color with FragmentSink's operations, written
/// into `img` (lane k's view laneView[k], fragment inputs slotFrag[laneSlot[k]], vertex colors
/// also in column laneSlot[k] of `s` when s.colors). Returns kLanesDrawn; or, having written
/// no pixel, when the lanes need the ordered walk of LaneQueue::flush — a lane needs the
/// general walk, two fragments fall on one pixel (their order decides depth ties), or there are
/// more than 16 fragments — what setupLanes returns, with l.out filled as setupLanes fills it.
/// laneSlot and laneView readable for 16 bytes.
inline constexpr std::uint32_t kLanesDrawn = 1u << 31;
using DrawLanesFn = std::uint32_t (*)(TriangleLanes& l, int n, int width,
                                      const std::uint8_t* laneSlot, const std::uint8_t* laneView,
                                      const SlotColors& s, const FragmentTri* slotFrag, bool flat,
                                      const LaneImages& img);

/// A band's queue of (triangle, view) lanes waiting for setupLanes, in submission order. Slots
/// hold what a queued triangle shares between its views: the y setup and the fragment inputs.
/// A caller that draws anything without the queue flushes it first, so every view keeps
/// receiving its triangles in submission order (depth ties resolve as without the queue).
template <Shading S>
struct LaneQueue {
    TriangleLanes lanes{};
    int laneCount = 0, slotCount = 0;
    std::uint8_t laneSlot[kLaneRoom], laneView[kLaneRoom];
    YSetup slotYs[kLaneCount];
    FragmentTri slotFrag[kLaneCount];
    SlotColors slotColors;
    /// Set by useDrawLanes when the queue's fragments may go through drawLanes.
    DrawLanesFn draw = nullptr;
    LaneImages images;

    /// Flushes through `fn` (a Kernels::drawLanes, or nullptr) from now on where it applies:
    /// untextured Vertex or Flat shading into views whose images are one block (laneImages;
    /// view v: targets[v]). colors: store the slots' vertex colors by component at queue time
    /// (SlotColors) — worth it where a slot feeds several lanes.
    void useDrawLanes(DrawLanesFn fn, bool textured, const Target* targets, std::size_t n,
                      bool colors) {
        if ((S != Shading::Vertex && S != Shading::Flat) || textured || !fn ||
            !laneImages(targets, n, images)) {
            return;
        }
        draw = fn;
        slotColors.colors = colors;
    }

    /// Flush first unless `views` more lanes fit.
    bool needsFlush(int views) const { return laneCount + views > kLaneCount; }
    int addTriangle(const YSetup& ys, const FragmentTri& frag) {
        slotYs[slotCount] = ys;
        slotFrag[slotCount] = frag;
        storeColors(slotCount, frag);
        return slotCount++;
    }
    void storeColors(int slot, const FragmentTri& frag) {
        if constexpr (S == Shading::Vertex) {
            if (!slotColors.colors) return;
            for (int j = 0; j < 3; ++j)
                for (int c = 0; c < 3; ++c) slotColors.a[j][c][slot] = frag.attr[j][c];
        }
    }
    void addLane(int slot, int view, std::int32_t x0, std::int32_t x1, std::int32_t x2) {
        const int k = laneCount++;
        const YSetup& ys = slotYs[slot];
        lanes.x[0][k] = x0, lanes.x[1][k] = x1, lanes.x[2][k] = x2;
        lanes.y[0][k] = ys.y[0], lanes.y[1][k] = ys.y[1], lanes.y[2][k] = ys.y[2];
        lanes.rowMin[k] = ys.rowMin, lanes.rowMax[k] = ys.rowMax;
        laneSlot[k] = std::uint8_t(slot), laneView[k] = std::uint8_t(view);
    }
    /// The lanes of n <= kLaneBlock views at once (x of view k: x0[k], x1[k], x2[k]; view
    /// indices views[k]): block copies and broadcasts instead of n addLane() calls. All of x0,
    /// x1, x2 and views must be readable for kLaneBlock entries. ys: the slot's y setup, from the
    /// caller's copy (not reloaded from slotYs: a wide load of what was just stored field by
    /// field waits for the stores, store-to-load forwarding cannot serve it).
    /// NV > 0: exactly NV views (n == NV), copied at their width: a stereo pair's lanes are
    /// 8-byte copies, not 32-byte ones.
    template <int NV = 0>
    void addLanes(int slot, const YSetup& ys, int n, const std::uint8_t* views,
                  const std::int32_t* x0, const std::int32_t* x1, const std::int32_t* x2) {
        // Copy width: exactly NV lanes, or kLaneBlock of which the next triangle overwrites
        // those past n.
        constexpr int kWidth = NV > 0 ? NV : kLaneBlock;
        const int k = laneCount;
        std::memcpy(&lanes.x[0][k], x0, sizeof(std::int32_t) * kWidth);
        std::memcpy(&lanes.x[1][k], x1, sizeof(std::int32_t) * kWidth);
        std::memcpy(&lanes.x[2][k], x2, sizeof(std::int32_t) * kWidth);
        for (int j = 0; j < kWidth; ++j) {
            lanes.y[0][k + j] = ys.y[0], lanes.y[1][k + j] = ys.y[1], lanes.y[2][k + j] = ys.y[2];
            lanes.rowMin[k + j] = ys.rowMin, lanes.rowMax[k + j] = ys.rowMax;
            laneSlot[k + j] = std::uint8_t(slot);
        }
        std::memcpy(&laneView[k], views, kWidth);
        laneCount += n;
    }
    /// Sets the queued lanes up in one pass and draws them; sinkFor(view) gives the view's sink
    /// by reference: each lane sets its triangle there and puts the caller's back (it copied the
    /// ~100-byte sink per lane before: 1024x768, instructions per frame one view 272.9 -> 269.7 M,
    /// the pair 363.1 -> 359.7 M).
    template <class SinkFor>
    void flush(SetupLanesFn setup, int width, SinkFor&& sinkFor) {
        if (laneCount == 0) return;
        std::uint32_t bits;
        if (draw) {
            bits = draw(lanes, laneCount, width, laneSlot, laneView, slotColors, slotFrag,
                        S == Shading::Flat, images);
            if (bits == kLanesDrawn) {
                laneCount = slotCount = 0;
                return;
            }
        } else {
            bits = setup(lanes, laneCount, width);
        }
        for (; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(bits);
            FragmentSink<S>& sink = sinkFor(laneView[k]);
            const FragmentTri* const callers = sink.tri;  // put back below
            sink.tri = &slotFrag[laneSlot[k]];
            if (lanes.out.mask[k] > 0) {
                if (sink.shade.texture) {
                    const std::int32_t xk[3] = {lanes.x[0][k], lanes.x[1][k], lanes.x[2][k]};
                    sink.setTriangle(xk, slotYs[laneSlot[k]].y);
                }
                emitSmall(lanes.out, k, lanes.rowMin[k], sink);
            } else {
                const std::int32_t xk[3] = {lanes.x[0][k], lanes.x[1][k], lanes.x[2][k]};
                rasterTriangle(slotYs[laneSlot[k]], xk, width, sink);
            }
            sink.tri = callers;
        }
        laneCount = slotCount = 0;
    }
};

}  // namespace mvr::raster::detail
