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
/// A grid's rows of one triangle (LaneQueue::addRows: up to kMaxGridRows rows of up to
/// kMaxGridRows views, 4 lanes written per row) land after at most kLaneCount − 1 queued lanes.
inline constexpr int kMaxGridRows = 4;
inline constexpr int kLaneRoom = kLaneCount + kMaxGridRows * kMaxGridRows + 4;
static_assert(kLaneRoom >= kLaneCount + kLaneBlock);

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

/// A grid's rows' values of one vertex side by side (row r in element r): snapped y.
using GridY = std::int32_t __attribute__((vector_size(16)));

/// setupY's rowMin / rowMax of 4 rows at once from their snapped y of the three vertices (y[j]
/// element r: row r's), clamped to [rowLo, rowHi] (broadcast). 32-bit: exact where |y| stays
/// below 2^31 − kSubpixel, as inside the guard band (setupY computes in 64 bits for any y).
/// A row with y 0 at every vertex gets an empty range.
inline void gridRowRange(const GridY y[3], GridY rowLo, GridY rowHi, GridY& rowMin, GridY& rowMax) {
    auto min = [](GridY a, GridY c) { return a < c ? a : c; };
    auto max = [](GridY a, GridY c) { return a < c ? c : a; };
    const GridY lo = min(y[0], min(y[1], y[2])), hi = max(y[0], max(y[1], y[2]));
    rowMin = max(rowLo, (lo - kHalfSubpixel + (kSubpixel - 1)) >> kSubpixelBits);
    rowMax = min(rowHi, (hi - kHalfSubpixel) >> kSubpixelBits);
}

/// A band's queue of (triangle, view) lanes waiting for setupLanes, in submission order. Slots
/// hold what a queued triangle shares between its views (and a grid's rows): the fragment
/// inputs; each lane holds its own y setup (YSetup: laneYs).
/// A caller that draws anything without the queue flushes it first, so every view keeps
/// receiving its triangles in submission order (depth ties resolve as without the queue).
template <Shading S>
struct LaneQueue {
    TriangleLanes lanes{};
    int laneCount = 0, slotCount = 0;
    alignas(16) std::uint8_t laneSlot[kLaneRoom], laneView[kLaneRoom];
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
    int addTriangle(const FragmentTri& frag) {
        slotFrag[slotCount] = frag;
        storeColors(slotCount, frag);
        return slotCount++;
    }
    /// Lane k's YSetup (its y, Δy and row range, as setupY gave them).
    YSetup laneYs(int k) const {
        YSetup ys;
        for (int i = 0; i < 3; ++i) ys.y[i] = lanes.y[i][k];
        ys.dy[0] = ys.y[2] - ys.y[1], ys.dy[1] = ys.y[0] - ys.y[2], ys.dy[2] = ys.y[1] - ys.y[0];
        ys.rowMin = lanes.rowMin[k], ys.rowMax = lanes.rowMax[k];
        return ys;
    }
    void storeColors(int slot, const FragmentTri& frag) {
        if constexpr (S == Shading::Vertex) {
            if (!slotColors.colors) return;
            for (int j = 0; j < 3; ++j)
                for (int c = 0; c < 3; ++c) slotColors.a[j][c][slot] = frag.attr[j][c];
        }
    }
    void addLane(int slot, const YSetup& ys, int view, std::int32_t x0, std::int32_t x1,
                 std::int32_t x2) {
        const int k = laneCount++;
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
    /// A grid's rows of one triangle (slot: its fragment inputs), NV views per row: row r's
    /// lanes (views rowViews[r][0, NV), snapped x of vertex j in view k: x[j][k], y of vertex j:
    /// y[j][r], rows [rowMin[r], rowMax[r]]) queued where keep[r] is not 0, in row order. Every
    /// row is written (whole registers, branch-free) and only the kept ones advance the queue:
    /// which rows of a grid a small triangle reaches in a band is as good as random. The caller
    /// queues it with laneCount <= kLaneCount and a free slot, and flushes when full
    /// (flushFull).
    template <int NV>
    void addRows(int slot, int rows, const GridY x[3], const GridY y[3], GridY rowMin, GridY rowMax,
                 GridY keep, const std::uint8_t (*rowViews)[kLaneBlock]) {
        static_assert(NV >= 2 && NV <= kMaxGridRows);
        int k = laneCount;
        const std::uint32_t slots = 0x01010101u * std::uint32_t(slot);
        auto row = [&]<int R>() __attribute__((always_inline)) {
            auto put = [&](std::int32_t* p, GridY v) { std::memcpy(p + k, &v, sizeof v); };
            constexpr GridY pick = {R, R, R, R};
            for (int j = 0; j < 3; ++j) {
                put(lanes.x[j], x[j]);
                put(lanes.y[j], __builtin_shuffle(y[j], pick));
            }
            put(lanes.rowMin, __builtin_shuffle(rowMin, pick));
            put(lanes.rowMax, __builtin_shuffle(rowMax, pick));
            std::memcpy(laneSlot + k, &slots, 4);
            std::memcpy(laneView + k, rowViews[R], 4);
            k += keep[R] & NV;
        };
        row.template operator()<0>();
        row.template operator()<1>();
        if (rows > 2) row.template operator()<2>();
        if (rows > 3) row.template operator()<3>();
        laneCount = k;
    }
    /// Sets up and draws the first kLaneCount lanes when the queue holds that many; the lanes
    /// past them (all of the last slot's triangle: addRows is called with fewer than kLaneCount
    /// queued) move to the front with their slot, so every flush but a band's last is full.
    template <class SinkFor>
    void flushFull(SetupLanesFn setup, int width, SinkFor&& sinkFor) {
        if (laneCount < kLaneCount) return;
        const int rest = laneCount - kLaneCount;
        const int lastSlot = slotCount - 1;
        laneCount = kLaneCount;
        drawQueued(setup, width, sinkFor);
        if (rest == 0) {
            laneCount = slotCount = 0;
            return;
        }
        // Whole blocks of kMaxGridRows² lanes (fixed-size copies; the arrays have the room).
        constexpr int kMove = kMaxGridRows * kMaxGridRows;
        static_assert(kLaneCount + kMove <= kLaneRoom);
        auto move = [&](auto* a) { std::memcpy(a, a + kLaneCount, sizeof(*a) * kMove); };
        for (int j = 0; j < 3; ++j) move(lanes.x[j]), move(lanes.y[j]);
        move(lanes.rowMin), move(lanes.rowMax), move(laneView);
        std::memset(laneSlot, 0, kMove);
        slotFrag[0] = slotFrag[lastSlot];
        storeColors(0, slotFrag[0]);
        laneCount = rest, slotCount = 1;
    }
    /// Sets the queued lanes up in one pass and draws them; sinkFor(view) gives the view's sink
    /// by reference: each lane sets its triangle there and puts the caller's back (it copied the
    /// ~100-byte sink per lane before: 1024x768, instructions per frame one view 272.9 -> 269.7 M,
    /// the pair 363.1 -> 359.7 M).
    template <class SinkFor>
    void flush(SetupLanesFn setup, int width, SinkFor&& sinkFor) {
        drawQueued(setup, width, sinkFor);
        laneCount = slotCount = 0;
    }

private:
    template <class SinkFor>
    void drawQueued(SetupLanesFn setup, int width, SinkFor&& sinkFor) {
        if (laneCount == 0) return;
        std::uint32_t bits;
        if (draw) {
            bits = draw(lanes, laneCount, width, laneSlot, laneView, slotColors, slotFrag,
                        S == Shading::Flat, images);
            if (bits == kLanesDrawn) return;
        } else {
            bits = setup(lanes, laneCount, width);
        }
        for (; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(bits);
            FragmentSink<S>& sink = sinkFor(laneView[k]);
            const FragmentTri* const callers = sink.tri;  // put back below
            sink.tri = &slotFrag[laneSlot[k]];
            if (lanes.out.mask[k] > 0) {
                if (sink.shade.samples()) {
                    const std::int32_t xk[3] = {lanes.x[0][k], lanes.x[1][k], lanes.x[2][k]};
                    const std::int32_t yk[3] = {lanes.y[0][k], lanes.y[1][k], lanes.y[2][k]};
                    sink.setTriangle(xk, yk);
                }
                emitSmall(lanes.out, k, lanes.rowMin[k], sink);
            } else {
                const std::int32_t xk[3] = {lanes.x[0][k], lanes.x[1][k], lanes.x[2][k]};
                rasterTriangle(laneYs(k), xk, width, sink);
            }
            sink.tri = callers;
        }
    }
};

}  // namespace mvr::raster::detail
