// src/raster/unified.cpp — kalaiah2007's unified N-view pipeline, with adelson1991's
// simultaneous algorithms, on the CPU.
//
//  1. Vertex stage, once per vertex: the view-independent outputs (world position, lighting
//     color or normal + position) once; the center clip position once; per view only
//     x = x_c + s_x(w − c) (and y per row of a grid). Views without a shear (toe-in, parallel,
//     lists) get their own matrix. Views that share (y, z, w) form a *family* (an off-axis row;
//     a row of a grid); every y/z/w quantity below is computed once per family.
//  2. Primitive stage: each triangle is replicated to the views of each family (the view tag is
//     the view index); trivial reject on near/far/top/bottom once per family, on left/right per
//     view; back faces by adelson1991's stereo test: det[x, y, w] is linear in the shear, so the
//     two outermost views of a family classify it for all of them (monotone in floating point as
//     well), and only a mixed triangle is tested view by view. Triangles are binned into bands
//     (unified_bin.cpp).
//  3. Raster stage, per band: the triangle's y setup (snapped y, row range, Δy of the edges,
//     depth and 1/w of its vertices, attributes, flat color) once per family, then for the views
//     of the family only the x terms (snapped x, area sign, column range, edge x terms) —
//     computed side by side, one view per SIMD lane (Kernels::setupViews) — and each view's
//     pixel walk, while the shared setup is still in registers / L1. Clipping against the y/z
//     planes is done once per family with the t values shared (adelson1991's Liang–Barsky
//     observation); only views whose x leaves the guard band clip left/right on their own.
//  4. Per-view depth and color buffers.
// The result equals multipass bit for bit (see pipeline.h for why).
#include "unified.h"

#include <algorithm>
#include <array>
#include <bit>

#include "methods.h"
#include "wireframe.h"

#ifndef MVR_MIN_SIMD_VIEWS
#define MVR_MIN_SIMD_VIEWS 2
#endif

namespace mvr::raster::detail {

namespace {

/// Families with fewer active views than this set up x one view at a time. Measured on the
/// 9-bunny scene (1024×768, AVX-512): the vector kernel costs ~22 ns per triangle whatever the
/// lane count, then ~7 ns per view, against ~20–25 ns per view for the scalar walk: it wins
/// from two views on.
constexpr int kMinSimdViews = MVR_MIN_SIMD_VIEWS;
/// setupViews returns one bit per view in a std::uint64_t: families of more views (kMaxViews is
/// 128) are set up 64 views at a time.
constexpr int kSetupChunk = 64;

/// A polygon being clipped against the planes shared by a family: (y, z, w, attributes) once,
/// x per active view of the family, all interpolated with the same t.
struct SharedPolygon {
    int n = 0;
    float y[kMaxPolyVerts], z[kMaxPolyVerts], w[kMaxPolyVerts];
    float a[kMaxPolyVerts][kMaxAttrs];
    float x[kMaxPolyVerts][kMaxViews];
};

/// Sutherland–Hodgman against the y/z planes in `planes` — the same decisions, t values and
/// interpolations as clipPolygon() makes for each view on its own.
void clipShared(SharedPolygon& p, std::uint8_t planes, int attrCount, int viewCount,
                SharedPolygon& tmp) {
    SharedPolygon* in = &p;
    SharedPolygon* out = &tmp;
    for (int plane = 0; plane < 4 && in->n > 0; ++plane) {
        if (!(planes & (1u << plane))) continue;
        float dist[kMaxPolyVerts];
        for (int i = 0; i < in->n; ++i)
            dist[i] = planeDistance(plane, 0.0f, in->y[i], in->z[i], in->w[i]);
        int m = 0;
        auto copy = [&](int i) {
            out->y[m] = in->y[i], out->z[m] = in->z[i], out->w[m] = in->w[i];
            std::copy_n(in->a[i], attrCount, out->a[m]);
            std::copy_n(in->x[i], viewCount, out->x[m]);
            ++m;
        };
        for (int i = 0; i < in->n; ++i) {
            const int j = i + 1 == in->n ? 0 : i + 1;
            const bool inI = dist[i] >= 0.0f, inJ = dist[j] >= 0.0f;
            if (inI) copy(i);
            if (inI != inJ) {
                const int a = inI ? i : j, b = inI ? j : i;
                const float t = inI ? clipT(dist[i], dist[j]) : clipT(dist[j], dist[i]);
                out->y[m] = lerpF(in->y[a], in->y[b], t);
                out->z[m] = lerpF(in->z[a], in->z[b], t);
                out->w[m] = lerpF(in->w[a], in->w[b], t);
                for (int k = 0; k < attrCount; ++k)
                    out->a[m][k] = lerpF(in->a[a][k], in->a[b][k], t);
                for (int k = 0; k < viewCount; ++k)
                    out->x[m][k] = lerpF(in->x[a][k], in->x[b][k], t);
                ++m;
            }
        }
        out->n = m;
        std::swap(in, out);
    }
    if (in != &p) {
        p.n = in->n;
        for (int i = 0; i < in->n; ++i) {
            p.y[i] = in->y[i], p.z[i] = in->z[i], p.w[i] = in->w[i];
            std::copy_n(in->a[i], attrCount, p.a[i]);
            std::copy_n(in->x[i], viewCount, p.x[i]);
        }
    }
}

/// The views' images by family position, for shadeLanes: family i's view k at first[i] + k.
/// Built once per frame, read by every band.
struct ViewSlots {
    std::vector<std::size_t> first;
    std::vector<float*> depth;
    std::vector<std::uint32_t*> color;
    /// Per family: drawSheared's blockStride — the pixels between its consecutive views'
    /// images when they lie in one block (a streamed band's scratch), else 0.
    std::vector<std::int32_t> blockStride;
};

template <Shading S>
struct BandContext {
    FrameContext& f;
    const UnifiedData& d;
    int rowLo, rowHi;
    FragmentTri frag{};
    std::vector<FragmentSink<S>> sinks;  ///< per view, all pointing at `frag`
    int attrCount = attributeCount(S, f.textured, f.colored, f.tangents);
    bool cull = false;     ///< back-face culling for the current draw item (not double-sided)
    ViewsSetup views{};    ///< the current triangle's per-view x setup (L1)
    ViewsX xs{};           ///< a long row's derived snapped x of the current triangle
    const ViewSlots* slots = nullptr;  ///< set when a long row's fragments go through shadeLanes
    /// The height the kernels address `slots` with: the image's, or for a streamed band rowHi + 1
    /// (its scratch holds rows rowHi down to rowLo, the top one first).
    int slotHeight = f.settings.height;
    LaneQueue<S> queue{};  ///< small families' (triangle, view) lanes waiting for setupLanes
};

template <Shading S>
void flushLanes(BandContext<S>& b) {
    b.queue.flush(b.f.kernels.setupLanes, b.f.settings.width,
                  [&](int view) -> FragmentSink<S>& { return b.sinks[std::size_t(view)]; });
}

/// Draws the queue's first kLaneCount lanes once it holds that many (LaneQueue::flushFull).
template <Shading S>
void flushFullLanes(BandContext<S>& b) {
    b.queue.flushFull(b.f.kernels.setupLanes, b.f.settings.width,
                      [&](int view) -> FragmentSink<S>& { return b.sinks[std::size_t(view)]; });
}

/// One family's replicas of a triangle that needs clipping against shared planes (or whose
/// views need left/right clipping).
template <Shading S>
void drawFamilyClipped(BandContext<S>& b, const Family& fam, const std::uint32_t v[3],
                       std::uint8_t famPlanes, const int* active, int activeCount) {
    const UnifiedData& d = b.d;
    SharedPolygon poly, tmp;
    poly.n = 3;
    const float* z = d.famZ(fam);
    const float* w = d.famW(fam);
    for (int j = 0; j < 3; ++j) {
        poly.y[j] = fam.y[v[j]], poly.z[j] = z[v[j]], poly.w[j] = w[v[j]];
        std::copy_n(d.attrOf(v[j]), b.attrCount, poly.a[j]);
        for (int k = 0; k < activeCount; ++k)
            poly.x[j][k] = d.viewX(d.views[std::size_t(active[k])], v[j]);
    }
    clipShared(poly, famPlanes, b.attrCount, activeCount, tmp);
    if (poly.n < 3) return;
    bool projectable = true;
    for (int i = 0; i < poly.n; ++i) projectable = projectable && poly.w[i] > 0.0f;
    const float width = float(b.f.settings.width), height = float(b.f.settings.height);
    // Shared projection of the clipped polygon: 1/w, y, depth.
    float pq[kMaxPolyVerts], pz[kMaxPolyVerts];
    std::int32_t py[kMaxPolyVerts];
    if (projectable) {
        for (int i = 0; i < poly.n; ++i) {
            pq[i] = 1.0f / poly.w[i];
            py[i] = snapY(poly.y[i], pq[i], height);
            pz[i] = windowDepth(poly.z[i], pq[i]);
        }
    }
    for (int k = 0; k < activeCount; ++k) {
        const int view = active[k];
        const ViewData& vd = d.views[std::size_t(view)];
        const std::uint8_t orX = d.viewCode(vd, v[0]) | d.viewCode(vd, v[1]) | d.viewCode(vd, v[2]);
        if (orX & kClipX) {
            // This view leaves the guard band: continue with left/right on its own copy.
            ClipVertex cv[kMaxPolyVerts];
            for (int i = 0; i < poly.n; ++i) {
                cv[i].x = poly.x[i][k], cv[i].y = poly.y[i], cv[i].z = poly.z[i],
                cv[i].w = poly.w[i];
                std::copy_n(poly.a[i], b.attrCount, cv[i].a);
            }
            drawClippedPolygon(cv, poly.n, std::uint8_t(orX & kClipX), b.attrCount,
                               b.sinks[std::size_t(view)].target, b.rowLo, b.rowHi,
                               b.sinks[std::size_t(view)], b.frag);
            continue;
        }
        if (!projectable) continue;
        std::int32_t px[kMaxPolyVerts];
        for (int i = 0; i < poly.n; ++i) px[i] = snapX(poly.x[i][k], pq[i], width);
        for (int t = 1; t + 1 < poly.n; ++t) {
            const int idx[3] = {0, t, t + 1};
            YSetup ys;
            setupY(ys, py[0], py[t], py[t + 1], b.rowLo, b.rowHi);
            const std::int32_t x[3] = {px[0], px[t], px[t + 1]};
            for (int j = 0; j < 3; ++j) {
                b.frag.z[j] = pz[idx[j]];
                b.frag.q[j] = pq[idx[j]];
                b.frag.attr[j] = poly.a[idx[j]];
            }
            rasterTriangle(ys, x, b.f.settings.width, b.sinks[std::size_t(view)]);
        }
    }
}

/// A family's replicas of a triangle's edges: near/far clipping, projection of y/z/w and the
/// bottom/top Liang–Barsky borders once for the family (adelson1991), x and left/right per view.
template <Shading S>
void drawFamilyWireframe(BandContext<S>& b, const Family& fam, const std::uint32_t v[3],
                         const int* active, int activeCount) {
    const UnifiedData& d = b.d;
    const float* z = d.famZ(fam);
    const float* w = d.famW(fam);
    const float width = float(b.f.settings.width), height = float(b.f.settings.height);
    for (int edge = 0; edge < 3; ++edge) {
        const std::uint32_t i0 = v[edge], i1 = v[edge == 2 ? 0 : edge + 1];
        LineEnds e;
        e.y[0] = fam.y[i0], e.z[0] = z[i0], e.w[0] = w[i0];
        e.y[1] = fam.y[i1], e.z[1] = z[i1], e.w[1] = w[i1];
        e.a[0] = d.attrOf(i0), e.a[1] = d.attrOf(i1);
        for (int k = 0; k < activeCount; ++k) {
            const ViewData& vd = d.views[std::size_t(active[k])];
            e.x[0][k] = d.viewX(vd, i0), e.x[1][k] = d.viewX(vd, i1);
        }
        float attr[2][kMaxAttrs];
        if (!clipLineNearFar(e, activeCount, b.attrCount, attr)) continue;
        float q[2], yw[2];
        for (int j = 0; j < 2; ++j) {
            q[j] = 1.0f / e.w[j];
            yw[j] = windowCoord(e.y[j], q[j], height);
            b.frag.z[j] = windowDepth(e.z[j], q[j]);
            b.frag.q[j] = q[j];
            b.frag.attr[j] = e.a[j];
        }
        b.frag.z[2] = b.frag.z[1], b.frag.q[2] = b.frag.q[1], b.frag.attr[2] = b.frag.attr[1];
        // Bottom/top borders once for every view of the family.
        float y0 = 0.0f, y1 = 1.0f;
        if (!liangBarskyAxis(yw[0], yw[1] - yw[0], 0.0f, height, y0, y1)) continue;
        for (int k = 0; k < activeCount; ++k) {
            const float x0 = windowCoord(e.x[0][k], q[0], width),
                        x1 = windowCoord(e.x[1][k], q[1], width);
            float t0 = y0, t1 = y1;
            if (!liangBarskyAxis(x0, x1 - x0, 0.0f, width, t0, t1)) continue;
            rasterLine(x0, yw[0], x1, yw[1], t0, t1, b.f.settings.width, b.f.settings.height,
                       b.rowLo, b.rowHi, b.sinks[std::size_t(active[k])]);
        }
    }
}

/// A family's triangle's fragment inputs from the vertex arrays: window depth zw and 1/w q (the
/// family's), the vertices' attributes (attr, stride floats each). Raw pointers: the hot callers
/// load them once per band or triangle.
inline void setFragmentInputs(FragmentTri& frag, const std::uint32_t v[3], const float* zw,
                              const float* q, const float* attr, std::size_t stride) {
    for (int j = 0; j < 3; ++j) {
        frag.z[j] = zw[v[j]];
        frag.q[j] = q[v[j]];
        frag.attr[j] = attr + v[j] * stride;
    }
}

/// Slot `slot`'s fragment inputs: the triangle's (setFragmentInputs), the flat color of b.frag.
template <Shading S>
inline void setSlot(BandContext<S>& b, int slot, const std::uint32_t v[3], const float* zw,
                    const float* q, const float* attr, std::size_t stride) {
    FragmentTri& frag = b.queue.slotFrag[slot];
    setFragmentInputs(frag, v, zw, q, attr, stride);
    if constexpr (S == Shading::Flat) {
        frag.flat = b.frag.flat;
        frag.flatD = b.frag.flatD;
    }
    b.queue.storeColors(slot, frag);
}

/// Queues a triangle's slot (its fragment inputs, shared by its views' lanes — and a grid's
/// rows'), flushing first unless `views` more lanes fit; the caller adds the lanes. zw, q: the
/// family's window depth and 1/w per vertex; attr, stride: the vertex attributes.
template <Shading S>
inline int queueSlot(BandContext<S>& b, const std::uint32_t v[3], int views, const float* zw,
                     const float* q, const float* attr, std::size_t stride) {
    if (b.queue.needsFlush(views)) flushLanes(b);
    const int slot = b.queue.slotCount++;
    setSlot(b, slot, v, zw, q, attr, stride);
    return slot;
}

/// Whether view k of a sheared family sees the triangle from behind (its det at the view's
/// shear; for a Mixed triangle, whose views differ).
inline bool viewBack(const UnifiedData& d, const Family& fam, const ShearDet& det, int k) {
    return shearedDet(det, d.views[std::size_t(fam.views[std::size_t(k)])].shearX, fam.shearY) <
           0.0f;
}

/// A long row's triangle as the row kernels take it: per vertex the center clip x, w − c and
/// 1/w, from which each view's x is derived (ShearedTri); its fragment inputs into b.frag.
template <Shading S>
[[gnu::always_inline]] inline ShearedTri longRowTriangle(BandContext<S>& b, const Family& fam,
                                                         const std::uint32_t v[3]) {
    const UnifiedData& d = b.d;
    const float* q = d.famQ(fam);
    ShearedTri t;
    for (int j = 0; j < 3; ++j) {
        t.cx[j] = d.cx[v[j]];
        t.wc[j] = d.cw[v[j]] - d.convergence;
        t.q[j] = q[v[j]];
    }
    setFragmentInputs(b.frag, v, d.famZW(fam), q, d.attr.data(), d.attrStride);
    return t;
}

/// A long row's replicas of a triangle that needs no clipping in any view, where the row kernel
/// takes setup and fragments (Kernels::drawSheared, untextured Vertex / Flat): the shared y
/// setup, the triangle's centre x, w − c and 1/w, the call; the views that need the general walk
/// come back and are drawn one by one. drawFamilyInside's path for these, without its other
/// paths' per-triangle work.
template <Shading S>
void drawLongRow(BandContext<S>& b, const Family& fam, const std::uint32_t v[3], FaceClass faces,
                 const ShearDet& det) {
    const UnifiedData& d = b.d;
    const std::int32_t* sy = fam.sy.data();
    YSetup ys;
    setupY(ys, sy[v[0]], sy[v[1]], sy[v[2]], b.rowLo, b.rowHi);
    if (ys.rowMin > ys.rowMax) return;
    flushLanes(b);
    const ShearedTri t = longRowTriangle(b, fam, v);
    const int nv = int(fam.views.size());
    const int* views = fam.views.data();
    const int width = b.f.settings.width;
    // Culled views only for a mixed triangle (nullptr: none, the kernel's cheaper case).
    std::uint64_t culledViews[(kMaxViews + 63) / 64] = {};
    const bool mixed = faces == FaceClass::Mixed;
    if (mixed) {
        for (int k = 0; k < nv; ++k)
            culledViews[k / 64] |= std::uint64_t(viewBack(d, fam, det, k)) << (k % 64);
    }
    const std::size_t family = std::size_t(&fam - d.families.data());
    const std::size_t first = b.slots->first[family];
    const int general = b.f.kernels.drawSheared(
        ys, t, fam.shears.data(), nv, mixed ? culledViews : nullptr, width, b.slotHeight, b.frag,
        S == Shading::Flat, b.slots->depth.data() + first, b.slots->color.data() + first,
        b.slots->blockStride[family], b.xs);
    for (int i = 0; i < general; ++i) {
        FragmentSink<S> sink = b.sinks[std::size_t(views[b.xs.view[i]])];
        const std::int32_t xk[3] = {b.xs.x[0][i], b.xs.x[1][i], b.xs.x[2][i]};
        rasterTriangle(ys, xk, width, sink);
    }
}

/// A family's replicas of a triangle that needs no clipping in any view: the shared y setup
/// once, then every view's x setup side by side straight from the family's interleaved snapped x
/// (a view whose x lies outside the viewport gets an empty column range there, so no per-view
/// reject is needed), and each covered view's pixels. Back faces of a mixed family are skipped
/// view by view. The same values rasterTriangle() computes, view by view.
template <Shading S>
void drawFamilyInside(BandContext<S>& b, const Family& fam, const std::uint32_t v[3],
                      FaceClass faces, const ShearDet& det) {
    const UnifiedData& d = b.d;
    const int width = b.f.settings.width;
    // Raw pointers, loaded once: the stores below (queue, fragment inputs) could alias the
    // vectors' internals as far as the compiler knows, which made it reload them every time.
    const std::int32_t* sy = fam.sy.data();
    const float* zw = d.famZW(fam);
    const float* q = d.famQ(fam);
    const float* attr = d.attr.data();
    const std::size_t stride = d.attrStride;
    YSetup ys;
    setupY(ys, sy[v[0]], sy[v[1]], sy[v[2]], b.rowLo, b.rowHi);
    if (ys.rowMin > ys.rowMax) return;
    const int nv = int(fam.views.size());
    const std::int32_t* x0 = fam.sxvData + std::size_t(v[0]) * std::size_t(nv);
    const std::int32_t* x1 = fam.sxvData + std::size_t(v[1]) * std::size_t(nv);
    const std::int32_t* x2 = fam.sxvData + std::size_t(v[2]) * std::size_t(nv);
    const int* views = fam.views.data();
    auto culled = [&](int k) { return faces == FaceClass::Mixed && viewBack(d, fam, det, k); };
    if (nv <= kLaneCount / 2) {
        // Queue the views' lanes: y setup and fragment inputs once (the slot), x per view.
        const int slot = queueSlot(b, v, nv, zw, q, attr, stride);
        if (faces != FaceClass::Mixed) {
            b.queue.addLanes(slot, ys, nv, fam.views8, x0, x1, x2);
        } else {
            for (int k = 0; k < nv; ++k) {
                if (!culled(k)) b.queue.addLane(slot, ys, views[k], x0[k], x1[k], x2[k]);
            }
        }
        return;
    }
    if (fam.many) {
        // A long row the row kernel does not take (drawLongRow: textured or Pixel fragments, or
        // a path without drawSheared): the views' x derived from the center here
        // (setupSheared), nothing stored.
        const ShearedTri t = longRowTriangle(b, fam, v);
        flushLanes(b);
        for (int base = 0; base < nv; base += kSetupChunk) {
            const int n = std::min(kSetupChunk, nv - base);
            const std::uint64_t lanes =
                b.f.kernels.setupSheared(ys, t, fam.shears.data() + base, n, width, b.views, b.xs);
            auto viewOf = [&](int k) { return base + b.xs.view[k]; };  // position in the family
            if (b.slots) {
                // All views' fragments side by side (shadeLanes); lanes that need the general
                // walk come back and are drawn one by one. Culled views of a mixed family are
                // taken out first.
                std::uint64_t drawn = lanes;
                if (faces == FaceClass::Mixed) {
                    for (std::uint64_t bits = lanes; bits; bits &= bits - 1) {
                        const int k = std::countr_zero(bits);
                        if (culled(viewOf(k))) drawn &= ~(std::uint64_t(1) << k);
                    }
                }
                const std::size_t first =
                    b.slots->first[std::size_t(&fam - d.families.data())] + std::size_t(base);
                for (std::uint64_t general = b.f.kernels.shadeLanes(
                         b.views, drawn, ys.rowMin, width, b.slotHeight, b.frag, S == Shading::Flat,
                         b.xs.view, b.slots->depth.data() + first, b.slots->color.data() + first);
                     general; general &= general - 1) {
                    const int k = std::countr_zero(general);
                    FragmentSink<S> sink = b.sinks[std::size_t(views[viewOf(k)])];
                    const std::int32_t xk[3] = {b.xs.x[0][k], b.xs.x[1][k], b.xs.x[2][k]};
                    rasterTriangle(ys, xk, width, sink);
                }
                continue;
            }
            for (std::uint64_t bits = lanes; bits; bits &= bits - 1) {
                const int k = std::countr_zero(bits);  // packed position
                const int kv = viewOf(k);
                if (culled(kv)) continue;
                FragmentSink<S> sink = b.sinks[std::size_t(views[kv])];  // in registers
                if (b.views.mask[k] > 0) {
                    if (sink.shade.samples()) {  // the view's λ from its own snapped x
                        const std::int32_t xk[3] = {b.xs.x[0][k], b.xs.x[1][k], b.xs.x[2][k]};
                        sink.setTriangle(xk, ys.y);
                    }
                    emitSmall(b.views, k, ys.rowMin, sink);
                } else {
                    const std::int32_t xk[3] = {b.xs.x[0][k], b.xs.x[1][k], b.xs.x[2][k]};
                    rasterTriangle(ys, xk, width, sink);
                }
            }
        }
        return;
    }
    setFragmentInputs(b.frag, v, zw, q, attr, stride);
    flushLanes(b);
    // More views than a queue block: setupViews passes over the family's views, at most
    // kSetupChunk at a time (its lane mask has 64 bits).
    for (int base = 0; base < nv; base += kSetupChunk) {
        const int n = std::min(kSetupChunk, nv - base);
        for (std::uint64_t lanes =
                 b.f.kernels.setupViews(ys, x0 + base, x1 + base, x2 + base, n, width, b.views);
             lanes; lanes &= lanes - 1) {
            const int k = std::countr_zero(lanes);
            const int kv = base + k;  // the view's position in the family
            const std::int32_t m = b.views.mask[k];
            if (culled(kv)) continue;
            FragmentSink<S> sink = b.sinks[std::size_t(views[kv])];  // in registers
            if (m > 0) {
                if (sink.shade.samples()) {
                    const std::int32_t xk[3] = {x0[kv], x1[kv], x2[kv]};
                    sink.setTriangle(xk, ys.y);
                }
                emitSmall(b.views, k, ys.rowMin, sink);
            } else {
                const std::int32_t xk[3] = {x0[kv], x1[kv], x2[kv]};
                rasterTriangle(ys, xk, width, sink);
            }
        }
    }
}

/// One family's replicas of one triangle (global vertex indices v): reject, cull, then the
/// inside fast path (the lane queue), wireframe, or clipping. b.frag.flat is already set for
/// Flat shading; det is the triangle's ShearDet when culling sheared views.
template <Shading S>
void drawTriangleFamily(BandContext<S>& b, const Family& fam, const std::uint32_t v[3],
                        const ShearDet& det) {
    FrameContext& f = b.f;
    const UnifiedData& d = b.d;
    const bool cull = b.cull;
    const int width = f.settings.width;
    const std::uint8_t c0 = fam.code[v[0]], c1 = fam.code[v[1]], c2 = fam.code[v[2]];
    if (c0 & c1 & c2 & kRejectYZW) return;
    FaceClass faces = FaceClass::AllFront;
    if (cull) {
        faces = fam.sheared ? classify(fam, det)
                            : (ownViewCulled(d, fam, v) ? FaceClass::AllBack : FaceClass::AllFront);
        if (faces == FaceClass::AllBack) return;
    }
    const std::uint8_t famPlanes = (c0 | c1 | c2) & kClipYZW;
    if (!famPlanes && !f.settings.wireframe && !((c0 | c1 | c2) & kClipX)) {
        if (fam.many && b.slots && f.kernels.drawSheared) {
            drawLongRow(b, fam, v, faces, det);
        } else {
            drawFamilyInside(b, fam, v, faces, det);
        }
        return;
    }
    flushLanes(b);  // the paths below draw at once: keep submission order per view
    // Replicate to the views of the family that survive their own x reject / cull
    // and, for a triangle that needs no clipping in that view, have a pixel-center
    // column in its x extent (otherwise rasterTriangle would draw nothing).
    const bool testColumns = !famPlanes && !f.settings.wireframe;
    int active[kMaxViews];
    int activeCount = 0;
    bool anyClipX = false;
    for (int view : fam.views) {
        const ViewData& vd = d.views[std::size_t(view)];
        const std::uint8_t a0 = d.viewCode(vd, v[0]), a1 = d.viewCode(vd, v[1]),
                           a2 = d.viewCode(vd, v[2]);
        if (a0 & a1 & a2 & kRejectX) continue;
        const bool viewClipX = ((a0 | a1 | a2) & kClipX) != 0;
        if (testColumns && !viewClipX &&
            noColumns(d.viewSx(vd, v[0]), d.viewSx(vd, v[1]), d.viewSx(vd, v[2]), width)) {
            continue;
        }
        if (faces == FaceClass::Mixed && shearedDet(det, vd.shearX, fam.shearY) < 0.0f) continue;
        anyClipX = anyClipX || viewClipX;
        active[activeCount++] = view;
    }
    if (activeCount == 0) return;
    if (f.settings.wireframe) {
        drawFamilyWireframe(b, fam, v, active, activeCount);
        return;
    }
    if (famPlanes || anyClipX) {
        drawFamilyClipped(b, fam, v, famPlanes, active, activeCount);
        return;
    }
    // Shared setup: y snapping, row range, Δy, depth, 1/w, attributes.
    YSetup ys;
    setupY(ys, fam.sy[v[0]], fam.sy[v[1]], fam.sy[v[2]], b.rowLo, b.rowHi);
    if (ys.rowMin > ys.rowMax) return;
    setFragmentInputs(b.frag, v, d.famZW(fam), d.famQ(fam), d.attr.data(), d.attrStride);
    // Per view: x only — the views' x setup side by side (SIMD across views), then
    // each view's pixels while that setup is in L1.
    if (activeCount < kMinSimdViews) {
        // Too few lanes to pay for the vector setup: one view at a time (same result).
        for (int k = 0; k < activeCount; ++k) {
            const ViewData& vd = d.views[std::size_t(active[k])];
            const std::int32_t xk[3] = {d.viewSx(vd, v[0]), d.viewSx(vd, v[1]), d.viewSx(vd, v[2])};
            FragmentSink<S> sink = b.sinks[std::size_t(active[k])];  // in registers
            rasterTriangle(ys, xk, width, sink);
        }
        return;
    }
    std::int32_t x[3][kMaxViews];
    for (int k = 0; k < activeCount; ++k) {
        const ViewData& vd = d.views[std::size_t(active[k])];
        x[0][k] = d.viewSx(vd, v[0]), x[1][k] = d.viewSx(vd, v[1]), x[2][k] = d.viewSx(vd, v[2]);
    }
    for (int base = 0; base < activeCount; base += kSetupChunk) {
        const int n = std::min(kSetupChunk, activeCount - base);
        f.kernels.setupViews(ys, x[0] + base, x[1] + base, x[2] + base, n, width, b.views);
        for (int k = 0; k < n; ++k) {
            const std::int32_t m = b.views.mask[k];
            if (m == 0) continue;
            const int view = active[base + k];
            auto& sink = b.sinks[std::size_t(view)];
            if (m > 0) {
                if (sink.shade.samples()) {
                    const std::int32_t xk[3] = {x[0][base + k], x[1][base + k], x[2][base + k]};
                    sink.setTriangle(xk, ys.y);
                }
                emitSmall(b.views, k, ys.rowMin, sink);
            } else {
                const ViewData& vd = d.views[std::size_t(view)];
                const std::int32_t xk[3] = {d.viewSx(vd, v[0]), d.viewSx(vd, v[1]),
                                            d.viewSx(vd, v[2])};
                rasterTriangle(ys, xk, width, sink);
            }
        }
    }
}

/// One triangle, every family.
template <Shading S>
void drawTriangle(BandContext<S>& b, const std::uint32_t v[3]) {
    ShearDet det;
    if (b.f.settings.cullBackFaces && b.d.anySheared)
        det = triangleShearDet(b.d, v, b.f.rig.convergence);
    for (const Family& fam : b.d.families) drawTriangleFamily(b, fam, v, det);
}

template <Shading S>
void rasterBand(BandContext<S>& b, const Bins& bins, int band) {
    FrameContext& f = b.f;
    const UnifiedData& d = b.d;
    // Sheared families (a stereo pair or off-axis row: one; a grid: one per row) of at most
    // kLaneBlock views each, no culling, filled: the inside path of drawTriangleFamily inlined
    // here, from pointers loaded once per band; replicas that need clipping take
    // drawTriangleFamily. 1/w, depth and attributes are the same for every sheared family.
    struct Row {
        const Family* fam;
        const std::uint8_t* code;
        const std::int32_t* sy;
        const std::int32_t* sxv;
        int nv;
    };
    constexpr int kMaxFastRows = 8;
    Row rows[kMaxFastRows] = {};
    int rowCount = 0;
    bool fast = !f.settings.cullBackFaces && !f.settings.wireframe &&
                d.families.size() <= std::size_t(kMaxFastRows);
    for (const Family& fam : d.families) {
        fast = fast && fam.sheared && fam.views.size() <= std::size_t(kLaneBlock);
        if (fast)
            rows[rowCount++] =
                Row{&fam, fam.code.data(), fam.sy.data(), fam.sxvData, int(fam.views.size())};
    }
    const float* zw = d.czw.data();
    const float* q = d.cq.data();
    const float* attr = d.attr.data();
    const std::size_t stride = d.attrStride;
    const Row row0 = rows[0];
    auto queueRow = [&]<int NV>(const Row& row, const std::uint32_t v[3])
        __attribute__((always_inline)) {
        const std::uint8_t c0 = row.code[v[0]], c1 = row.code[v[1]], c2 = row.code[v[2]];
        if (c0 & c1 & c2 & kRejectYZW) return;
        if ((c0 | c1 | c2) & (kClipYZW | kClipX)) {
            drawTriangleFamily(b, *row.fam, v, ShearDet{});
            return;
        }
        YSetup ys;
        setupY(ys, row.sy[v[0]], row.sy[v[1]], row.sy[v[2]], b.rowLo, b.rowHi);
        if (ys.rowMin > ys.rowMax) return;
        const int nvi = NV > 0 ? NV : row.nv;
        const int slot = queueSlot(b, v, nvi, zw, q, attr, stride);
        const std::size_t nv = std::size_t(nvi);
        b.queue.template addLanes<NV>(slot, ys, nvi, row.fam->views8, row.sxv + v[0] * nv,
                                      row.sxv + v[1] * nv, row.sxv + v[2] * nv);
    };
    const Material* material = nullptr;
    auto onItem = [&](const DrawItem& it) {
        flushLanes(b);  // the queued triangles shade with the previous material
        material = &it.instance->material;
        b.cull = f.settings.cullBackFaces && !material->doubleSided;
        for (auto& sink : b.sinks) f.setMaterial(sink.shade, *material);
    };
    // Rows of one view count known at compile time (a stereo pair, a 3-view grid's rows): the
    // lanes are copied at their width.
    // fn(v) for the band's triangles, the flat color set first (view-independent: once for
    // every view).
    auto eachTriangle = [&](auto&& fn) {
        forBandTriangles(f.draw, bins, band, f.bands.count, onItem, [&](const std::uint32_t v[3]) {
            if constexpr (S == Shading::Flat) {
                setFlat(b.frag, f.textured, f.shading, *material, d.world[v[0]], d.world[v[1]],
                        d.world[v[2]]);
            }
            fn(v);
        });
    };
    auto loop = [&]<int NV>() {
        eachTriangle([&](const std::uint32_t v[3]) {
            if (!fast) {
                drawTriangle(b, v);
                return;
            }
            if (rowCount == 1) {
                // a stereo pair / an off-axis row: row0 stays in registers
                queueRow.template operator()<NV>(row0, v);
            } else {
                for (int r = 0; r < rowCount; ++r) queueRow.template operator()<NV>(rows[r], v);
            }
        });
    };
    // A grid of 2–4 rows of 2–4 views sharing their columns' x (a rig's grid: twin rows): a
    // triangle's rows at once, their y ranges side by side and one slot for all of them.
    bool grid = fast && rowCount >= 2 && rowCount <= kMaxGridRows && row0.nv >= 2 &&
                row0.nv <= kMaxGridRows;
    for (int r = 1; grid && r < rowCount; ++r)
        grid = rows[r].nv == row0.nv && rows[r].sxv == row0.sxv;
    std::uint8_t gridViews[kMaxGridRows][kLaneBlock] = {};
    for (int r = 0; grid && r < rowCount && r < kMaxGridRows; ++r)
        std::memcpy(gridViews[r], rows[r].fam->views8, kLaneBlock);
    auto gridRows = [&]<int NV>() {
        const GridY rowLo = GridY{} + b.rowLo, rowHi = GridY{} + b.rowHi;
        const std::int32_t* sxv = row0.sxv;
        eachTriangle([&](const std::uint32_t v[3]) {
            std::uint8_t codes = 0;
            for (int r = 0; r < rowCount; ++r)
                codes |= rows[r].code[v[0]] | rows[r].code[v[1]] | rows[r].code[v[2]];
            if (codes & (kClipYZW | kClipX)) {
                // A row needs clipping: row by row (drawTriangleFamily for that one).
                for (int r = 0; r < rowCount; ++r) queueRow.template operator()<NV>(rows[r], v);
                return;
            }
            GridY y[3], x[3];
            for (int j = 0; j < 3; ++j) {
                // (rows past rowCount: y 0, an empty row range)
                y[j] =
                    GridY{rows[0].sy[v[j]], rows[1].sy[v[j]], rowCount > 2 ? rows[2].sy[v[j]] : 0,
                          rowCount > 3 ? rows[3].sy[v[j]] : 0};
                std::memcpy(&x[j], sxv + std::size_t(v[j]) * NV, sizeof(GridY));
            }
            // No clip bits: inside the guard band (gridRowRange is exact there). A row that
            // queueRow would reject without clip bits (all three vertices above or below the
            // screen) has no pixel row in the band either.
            GridY rowMin, rowMax;
            gridRowRange(y, rowLo, rowHi, rowMin, rowMax);
            const GridY keep = rowMin <= rowMax;
            if (!(keep[0] | keep[1] | keep[2] | keep[3])) return;
            // (a free slot: every queued slot holds at least 2 of the < 16 queued lanes)
            const int slot = b.queue.slotCount++;
            setSlot(b, slot, v, zw, q, attr, stride);
            b.queue.template addRows<NV>(slot, rowCount, x, y, rowMin, rowMax, keep, gridViews);
            flushFullLanes(b);
        });
    };
    if (grid) {
        switch (row0.nv) {
            case 2: gridRows.template operator()<2>(); break;
            case 3: gridRows.template operator()<3>(); break;
            default: gridRows.template operator()<4>(); break;
        }
        return;
    }
    bool sameCount = fast;
    for (int r = 1; r < rowCount; ++r) sameCount = sameCount && rows[r].nv == row0.nv;
    if (sameCount && row0.nv == 2) {
        loop.template operator()<2>();
    } else if (sameCount && row0.nv == 3) {
        loop.template operator()<3>();
    } else {
        loop.template operator()<0>();
    }
}

/// The pixels between consecutive images of slots [first, end) when depth and color both lie in
/// one block at that stride (and 32-bit offsets reach every slot's image), else 0.
std::int32_t blockStride(const ViewSlots& slots, std::size_t first) {
    const std::size_t n = slots.depth.size() - first;
    if (n < 2) return 0;
    auto at = [](const void* p) { return std::intptr_t(reinterpret_cast<std::uintptr_t>(p)); };
    const std::intptr_t step = at(slots.depth[first + 1]) - at(slots.depth[first]);
    if (step <= 0 || step % std::intptr_t(sizeof(float)) != 0 ||
        step / std::intptr_t(sizeof(float)) * std::intptr_t(n) >= (std::intptr_t(1) << 30)) {
        return 0;
    }
    for (std::size_t i = 1; i < n; ++i) {
        const std::intptr_t k = std::intptr_t(i) * step;
        if (at(slots.depth[first + i]) - at(slots.depth[first]) != k ||
            at(slots.color[first + i]) - at(slots.color[first]) != k) {
            return 0;
        }
    }
    return std::int32_t(step / std::intptr_t(sizeof(float)));
}

/// The views' images by family position (ViewSlots) for `targets`.
ViewSlots makeSlots(const UnifiedData& d, std::span<const Target> targets) {
    ViewSlots slots;
    for (const Family& fam : d.families) {
        slots.first.push_back(slots.depth.size());
        for (const int v : fam.views) {
            slots.depth.push_back(targets[std::size_t(v)].depth);
            slots.color.push_back(targets[std::size_t(v)].color);
        }
        slots.blockStride.push_back(blockStride(slots, slots.first.back()));
    }
    // shadeLanes and drawSheared read the table for all 8 lanes of a group (positions below
    // kMaxViews past a family's first slot), the unused ones only to be masked off.
    slots.depth.resize(slots.depth.size() + kMaxViews, nullptr);
    slots.color.resize(slots.color.size() + kMaxViews, nullptr);
    return slots;
}

/// A worker's scratch for streamed bands: one band's rows of every view (view v at v · stride),
/// targets and slots addressing them.
struct BandScratch {
    std::vector<Target> targets;
    ViewSlots slots;
};

template <Shading S>
void rasterStage(FrameContext& f, UnifiedData& d, std::span<const Target> targets) {
    // Untextured Vertex or Flat shading: a long row's fragments of one triangle go through
    // shadeLanes (all its views side by side), which finds the views' images here.
    const bool laneFragments = (S == Shading::Vertex || S == Shading::Flat) && !f.textured;
    const ViewSlots slots = laneFragments ? makeSlots(d, targets) : ViewSlots{};
    // Streamed bands: when the frame's images are larger than the cache (f.streamBands), each
    // worker draws a band into a scratch that stays in its cache (cleared there, no image line
    // read from memory) and then streams the band's rows into the images (written once, not
    // read). Otherwise each band's rows of the images are cleared just before they are drawn.
    const bool stream = f.streamBands;
    std::vector<BandScratch> scratch(stream ? std::size_t(f.pool.size()) : 0);
    const std::size_t stride = std::size_t(f.bands.rows) * std::size_t(f.settings.width);
    if (stream) {
        d.bandBuffers.resize(f.pool.size(), stride * targets.size());
        for (std::size_t w = 0; w < scratch.size(); ++w) {
            for (std::size_t v = 0; v < targets.size(); ++v)
                scratch[w].targets.push_back(d.bandBuffers.target(int(w), v * stride, targets[v]));
            if (laneFragments) scratch[w].slots = makeSlots(d, scratch[w].targets);
        }
    }
    const std::uint32_t clear = packColor(f.settings.clearColor);
    f.pool.run(f.bands.count, [&](int band, int worker) {
        BandContext<S> b{f, d, f.bands.rowBegin(band), f.bands.rowEnd(band) - 1, {}, {}};
        std::span<Target> local;
        if (stream) {
            BandScratch& s = scratch[std::size_t(worker)];
            for (Target& t : s.targets) t.offset = targets[0].index(0, b.rowHi);
            local = s.targets;
            b.slotHeight = b.rowHi + 1;
        }
        std::span<const Target> draw = stream ? std::span<const Target>(local) : targets;
        // The band's rows of every view, into the cache just before they are drawn (bands are
        // sized so that they fit L2 with all views: makeBands).
        for (const Target& t : draw) clearRows(t, b.rowLo, b.rowHi, clear);
        b.sinks.reserve(draw.size());
        for (std::size_t v = 0; v < draw.size(); ++v) {
            b.sinks.push_back(FragmentSink<S>{
                draw[v], &b.frag, {&f.shadingOf(v), nullptr, f.textured, nullptr, f.colored}});
        }
        if (laneFragments) b.slots = stream ? &scratch[std::size_t(worker)].slots : &slots;
        // The queue's fragments side by side (drawLanes) where the views' images are one
        // block (a streamed band's scratch); a slot serves all its views' lanes, so its vertex
        // colors are stored by component at queue time (lazily per lane: 3x3 grid at 1024x768
        // 50.4 against 48.3 ms).
        b.queue.useDrawLanes(f.kernels.drawLanes, f.textured, draw.data(), draw.size(), true);
        rasterBand(b, d.bins, band);
        flushLanes(b);
        if (stream && f.rowSink) {
            // The band's rows handed over in place of the images (renderRows).
            std::array<const std::uint8_t*, kMaxViews> first{};
            const int top = f.settings.height - 1 - b.rowHi;
            for (std::size_t v = 0; v < local.size(); ++v)
                first[v] = reinterpret_cast<const std::uint8_t*>(local[v].color +
                                                                 local[v].index(0, b.rowHi));
            f.rowSink->rows(ViewRows{top, f.settings.height - 1 - b.rowLo, f.settings.width,
                                     std::span<const std::uint8_t* const>(first.data(),
                                                                          local.size())});
        } else if (stream) {
            streamRows(local, targets, b.rowLo, b.rowHi);
        }
    });
}

}  // namespace

void renderUnified(FrameContext& f, std::span<const Target> targets, StageTimes& times,
                   std::unique_ptr<MethodScratch>& scratch) {
    if (f.rig.viewCount() == 1) {
        // One view: nothing to share, and the family / replication bookkeeping cost ~25 % —
        // the single-view pipeline is this case's unified pipeline (same pixels by construction).
        renderMultipass(f, targets, times, scratch);
        return;
    }
    if (!dynamic_cast<UnifiedData*>(scratch.get())) scratch = std::make_unique<UnifiedData>();
    UnifiedData& d = static_cast<UnifiedData&>(*scratch);
    StageClock clock;
    // Bands sized for all views' rows (a band spans every view): see makeBands. Only for rigs
    // whose views are shears of one centre view (rows, grids): their triangles cover the same
    // rows in every view. Views that differ by more (lists: the lights of a shadow pass) bin a
    // triangle to the rows of each view, so short bands only multiply the triangles each band
    // sets up (8 shadow maps of 1024²: 3× slower than 8 single passes with 12-row bands).
    const bool sheared = std::all_of(f.rig.views.begin(), f.rig.views.end(),
                                     [](const View& v) { return v.clipShear.has_value(); });
    if (sheared) {
        f.bands = makeBands(f.settings.height, f.pool.size(),
                            std::size_t(f.settings.width) * 8 * std::size_t(f.rig.viewCount()));
    }
    buildFamilies(f.rig, f.settings.shading, f.textured, f.colored, f.tangents, f.draw.vertexCount,
                  d);
    d.convergence = f.rig.convergence, d.width = float(f.settings.width);
    vertexStage(f, d);
    times.vertexMs += clock.lap();
    binStage(f, d);
    times.setupMs += clock.lap();
    switch (f.settings.shading) {
        case Shading::Flat: rasterStage<Shading::Flat>(f, d, targets); break;
        case Shading::Vertex: rasterStage<Shading::Vertex>(f, d, targets); break;
        case Shading::Pixel: rasterStage<Shading::Pixel>(f, d, targets); break;
    }
    times.rasterMs += clock.lap();
}

}  // namespace mvr::raster::detail
