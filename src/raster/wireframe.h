// src/raster/wireframe.h — RenderSettings::wireframe: triangle edges as lines, with
// adelson1991's stereo Liang–Barsky clipping.
//
// An edge is clipped in homogeneous space against the near and far planes (shared by the views
// of a family: they involve only z and w), projected, and clipped to the viewport [0, W]×[0, H]
// by Liang–Barsky. The y borders (bottom, top) involve only y, which the views of a family share,
// so they are clipped once for all of them; the x borders (left, right) per view. Liang–Barsky's
// result (t0 = max over entering borders, t1 = min over leaving ones, reject when t0 > t1) does
// not depend on the order of the borders, so the shared form gives exactly what clipping each
// view on its own gives (tests/raster check this against multipass).
//
// The walk: one pixel per column (x-major) or row (y-major) whose center lies within the clipped
// segment, t measured on the unclipped projected segment; the fragment goes through the triangle
// FragmentSink with barycentrics (1 − t, t, 0), so depth is screen-linear and attributes
// perspective-correct exactly as for filled triangles. Edges shared by two triangles are drawn
// twice; the LESS depth test makes the second draw a no-op.
#pragma once

#include <cmath>

#include "pipeline.h"

namespace mvr::raster::detail {

/// One Liang–Barsky border: p·t ≤ q. Narrows [t0, t1]; false when the segment is outside.
inline bool liangBarskyBorder(float p, float q, float& t0, float& t1) {
    if (p == 0.0f) return q >= 0.0f;
    const float r = q / p;
    if (p < 0.0f) {
        if (r > t1) return false;
        if (r > t0) t0 = r;
    } else {
        if (r < t0) return false;
        if (r < t1) t1 = r;
    }
    return true;
}
/// Both borders lo ≤ a + t·d ≤ hi of one axis.
inline bool liangBarskyAxis(float a, float d, float lo, float hi, float& t0, float& t1) {
    return liangBarskyBorder(-d, a - lo, t0, t1) && liangBarskyBorder(d, hi - a, t0, t1);
}

/// A clip-space edge of a triangle for the views of one family: (y, z, w) and attributes of its
/// two ends shared, x per view.
struct LineEnds {
    float y[2], z[2], w[2];
    const float* a[2];
    float x[2][kMaxViews];
};

/// Near/far clipping of the edge in homogeneous space: a new end is interpolated from the
/// inside end with a t that depends only on (z, w), so it is the same for every view (x of each
/// view is interpolated with it). Interpolated attributes go to attr[end] (kMaxAttrs floats).
/// Returns false when nothing is left or an end cannot be projected.
inline bool clipLineNearFar(LineEnds& e, int views, int attrCount, float (*attr)[kMaxAttrs]) {
    for (int plane = 0; plane < 2; ++plane) {
        const float d0 = planeDistance(plane, 0.0f, e.y[0], e.z[0], e.w[0]);
        const float d1 = planeDistance(plane, 0.0f, e.y[1], e.z[1], e.w[1]);
        const bool in0 = d0 >= 0.0f, in1 = d1 >= 0.0f;
        if (!in0 && !in1) return false;
        if (in0 && in1) continue;
        const int o = in0 ? 1 : 0, i = 1 - o;
        const float t = in0 ? clipT(d0, d1) : clipT(d1, d0);
        for (int k = 0; k < attrCount; ++k) attr[o][k] = lerpF(e.a[i][k], e.a[o][k], t);
        e.a[o] = attr[o];
        e.y[o] = lerpF(e.y[i], e.y[o], t);
        e.z[o] = lerpF(e.z[i], e.z[o], t);
        e.w[o] = lerpF(e.w[i], e.w[o], t);
        for (int v = 0; v < views; ++v) e.x[o][v] = lerpF(e.x[i][v], e.x[o][v], t);
    }
    return e.w[0] > 0.0f && e.w[1] > 0.0f;
}

/// Window coordinate (pixels, not snapped) of a clip coordinate with q = 1/w.
inline float windowCoord(float c, float q, float size) { return ((c * q) * 0.5f + 0.5f) * size; }

/// Walks the pixels of one view's projected segment (x0, y0) → (x1, y1) for t in [t0, t1] (the
/// Liang–Barsky interval), rows clamped to [rowLo, rowHi]; the FragmentSink's triangle must hold
/// the two ends as vertices 0 and 1.
template <class Sink>
inline void rasterLine(float x0, float y0, float x1, float y1, float t0, float t1, int width,
                       int height, int rowLo, int rowHi, Sink& sink) {
    if (!(t0 <= t1)) return;
    const float dx = x1 - x0, dy = y1 - y0;
    const bool xMajor = std::abs(dx) >= std::abs(dy);
    const float d = xMajor ? dx : dy;
    if (d == 0.0f) return;  // a point: nothing to walk
    const float a0 = xMajor ? x0 : y0;
    const float size = float(xMajor ? width : height);
    // Clamped in float before any conversion: ends far outside are legal (guard-band free).
    const float ea = a0 + t0 * d, eb = a0 + t1 * d;
    const float lo = std::clamp(std::min(ea, eb), -1.0f, size + 1.0f);
    const float hi = std::clamp(std::max(ea, eb), -1.0f, size + 1.0f);
    int first = int(std::ceil(lo - 0.5f)), last = int(std::floor(hi - 0.5f));
    first = std::max(first, xMajor ? 0 : rowLo);
    last = std::min(last, xMajor ? width - 1 : rowHi);
    for (int i = first; i <= last; ++i) {
        const float t = (float(i) + 0.5f - a0) / d;
        const float other = std::floor(xMajor ? y0 + t * dy : x0 + t * dx);
        if (xMajor) {
            if (other >= float(rowLo) && other <= float(rowHi))
                sink(i, int(other), 1.0f - t, t, 0.0f);
        } else {
            if (other >= 0.0f && other <= float(width - 1)) sink(int(other), i, 1.0f - t, t, 0.0f);
        }
    }
}

/// Rows a wireframe triangle may touch, from its snapped window y (pixel rows are floor(y) for
/// lines, so one row of margin covers the snapping).
inline void wireframeRows(std::int32_t y0, std::int32_t y1, std::int32_t y2, int height,
                          int& rowMin, int& rowMax) {
    const std::int32_t lo = std::min(y0, std::min(y1, y2)), hi = std::max(y0, std::max(y1, y2));
    rowMin = std::max(0, floorDivSub(lo) - 1);
    rowMax = std::min(height - 1, floorDivSub(hi) + 1);
}

}  // namespace mvr::raster::detail
