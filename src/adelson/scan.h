// src/adelson/scan.h — the scan-line polygon fill shared by every fill in this module (private).
//
// One template fills a polygon for K = 1 or 2 eyes. What depends only on y (the edge table
// sorted by y, the active edge list, the per-edge 1/Δy and start offset, and attributes that do
// not depend on the eye: Gouraud colors, projected z) is done once; x, its increment, the x
// order of the active edges and the spans are done per eye. With K = 1 the very same
// expressions run, so one stereo fill == two single fills bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "count.h"

namespace mvr::adelson::detail {

/// Flat: one color. Gouraud: colors interpolated. FlatZ: one color, z-buffered.
/// ZLeftFlatRight (K = 2): adelson1991's BSP compromise — eye 0 (left) z-buffered, eye 1 (right)
/// painted in order; z along the edges is shared, the right eye ignores it.
enum class Mode { Flat, Gouraud, FlatZ, ZLeftFlatRight };

template <Mode M>
constexpr int kAttrs = M == Mode::Gouraud ? 3 : (M == Mode::Flat ? 0 : 1);

struct EdgeY {
    int ys = 0, ye = 0;            ///< first scan-line, one past the last
    double inv = 0, off = 0;       ///< 1/Δy, (ys + 0.5) − y_low
    std::uint32_t lo = 0, hi = 0;  ///< vertex indices, lo has the smaller y
};

inline std::uint32_t packD(double r, double g, double b) {
    auto q = [](double v) {
        return static_cast<std::uint32_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5);
    };
    return q(r) | (q(g) << 8) | (q(b) << 16) | 0xff000000u;
}

/// Scratch buffers reused across calls (one per thread).
struct ScanScratch {
    std::vector<EdgeY> edges;
    std::vector<double> x[2], dx[2];
    std::vector<double> a[3], da[3];
    std::vector<int> order[2];
    std::vector<unsigned char> dead;
};
inline ScanScratch& scratch() {
    thread_local ScanScratch s;
    return s;
}

/// xs[k]: eye k's x per vertex (pixels); y: shared (pixels); attr[c]: per-vertex attribute c
/// (r, g, b for Gouraud; z for FlatZ). frames[k]: eye k's frame (FlatZ: with depth).
template <bool On, int K, Mode M>
void scanFill(const double* const* xs, const double* y, std::size_t count,
              const double* const* attr, std::uint32_t color, Frame* const* frames, Count<On>& n) {
    constexpr int A = kAttrs<M>;
    ScanScratch& s = scratch();
    std::vector<EdgeY>& edges = s.edges;
    edges.clear();
    // ---- edge table (shared) ----
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t j = i + 1 == count ? 0 : i + 1;
        n.cmp();
        if (y[i] == y[j]) continue;  // horizontal edges add nothing
        EdgeY e;
        n.cmp();
        if (y[i] < y[j])
            e.lo = std::uint32_t(i), e.hi = std::uint32_t(j);
        else
            e.lo = std::uint32_t(j), e.hi = std::uint32_t(i);
        const double y0 = y[e.lo], y1 = y[e.hi];
        e.ys = int(std::ceil(y0 - 0.5));
        e.ye = int(std::ceil(y1 - 0.5));
        n.add(2), n.cmp();
        if (e.ys >= e.ye) continue;  // covers no pixel center
        e.inv = 1.0 / (y1 - y0);
        e.off = (double(e.ys) + 0.5) - y0;
        n.add(3), n.mul();
        edges.push_back(e);
    }
    std::stable_sort(edges.begin(), edges.end(), [&](const EdgeY& p, const EdgeY& q) {
        n.cmp();
        return p.ys < q.ys;
    });
    const std::size_t ne = edges.size();
    for (int c = 0; c < A; ++c) s.a[c].resize(ne), s.da[c].resize(ne);
    for (std::size_t k = 0; k < ne; ++k) {  // shared attributes along the edges
        const EdgeY& e = edges[k];
        for (int c = 0; c < A; ++c) {
            s.da[c][k] = (attr[c][e.hi] - attr[c][e.lo]) * e.inv;
            s.a[c][k] = attr[c][e.lo] + e.off * s.da[c][k];
            n.add(2), n.mul(2);
        }
    }
    for (int v = 0; v < K; ++v) {  // per-eye x along the edges
        s.x[v].resize(ne), s.dx[v].resize(ne);
        const double* xv = xs[v];
        for (std::size_t k = 0; k < ne; ++k) {
            const EdgeY& e = edges[k];
            s.dx[v][k] = (xv[e.hi] - xv[e.lo]) * e.inv;
            s.x[v][k] = xv[e.lo] + e.off * s.dx[v][k];
            n.add(2), n.mul(2);
        }
        s.order[v].clear();
    }
    s.dead.assign(ne, 0);
    if (ne == 0) return;
    const int width = frames[0]->width, height = frames[0]->height;
    std::size_t next = 0;
    int yy = edges[0].ys;
    std::size_t activeCount = 0;
    std::vector<int> active;  // shared active edge list
    active.reserve(16);
    while (next < ne || activeCount > 0) {
        if (activeCount == 0) yy = std::max(yy, edges[next].ys);
        if (yy >= height) break;
        // ---- active edge list update (shared) ----
        bool anyDead = false;
        for (std::size_t i = 0; i < active.size(); ++i) {
            n.cmp();
            if (edges[active[i]].ye <= yy) s.dead[active[i]] = 1, anyDead = true;
        }
        if (anyDead) {
            std::erase_if(active, [&](int k) { return s.dead[k] != 0; });
            for (int v = 0; v < K; ++v)
                std::erase_if(s.order[v], [&](int k) { return s.dead[k] != 0; });
        }
        while (next < ne && edges[next].ys == yy) {
            n.cmp();
            active.push_back(int(next));
            for (int v = 0; v < K; ++v) s.order[v].push_back(int(next));
            ++next;
        }
        activeCount = active.size();
        // ---- per eye: x order (insertion sort: nearly sorted from the last line) and spans ----
        for (int v = 0; v < K; ++v) {
            std::vector<int>& ord = s.order[v];
            const double* xv = s.x[v].data();
            for (std::size_t i = 1; i < ord.size(); ++i) {
                const int key = ord[i];
                std::size_t j = i;
                while (j > 0) {
                    n.cmp();
                    if (!(xv[ord[j - 1]] > xv[key])) break;
                    ord[j] = ord[j - 1];
                    --j;
                }
                ord[j] = key;
            }
            if (yy < 0) continue;
            Frame& f = *frames[v];
            std::uint32_t* row = f.pixels.data() + std::size_t(yy) * width;
            for (std::size_t i = 0; i + 1 < ord.size(); i += 2) {
                const int ea = ord[i], eb = ord[i + 1];
                const double xa = xv[ea], xb = xv[eb];
                int pa = int(std::ceil(xa - 0.5)), pb = int(std::ceil(xb - 0.5));
                n.add(2);
                pa = std::max(pa, 0), pb = std::min(pb, width);
                if (pa >= pb) continue;
                if constexpr (M == Mode::Flat) {
                    std::fill(row + pa, row + pb, color);
                } else {
                    if constexpr (M == Mode::ZLeftFlatRight) {
                        if (v == 1) {  // the right eye: painter's order
                            std::fill(row + pa, row + pb, color);
                            continue;
                        }
                    }
                    const double w = xb - xa;
                    const double start = (double(pa) + 0.5) - xa;
                    n.add(2);
                    double c[A], d[A];
                    for (int ch = 0; ch < A; ++ch) {
                        d[ch] = (s.a[ch][eb] - s.a[ch][ea]) / w;
                        c[ch] = s.a[ch][ea] + start * d[ch];
                        n.add(2), n.mul(2);
                    }
                    if constexpr (M == Mode::Gouraud) {
                        for (int px = pa; px < pb; ++px) {
                            row[px] = packD(c[0], c[1], c[2]);
                            c[0] += d[0], c[1] += d[1], c[2] += d[2];
                        }
                        n.interp(3 * std::uint64_t(pb - pa));
                    } else {
                        float* depth = f.depth.data() + std::size_t(yy) * width;
                        for (int px = pa; px < pb; ++px) {
                            const float z = float(c[0]);
                            if (z < depth[px]) depth[px] = z, row[px] = color;
                            c[0] += d[0];
                        }
                        n.interp(std::uint64_t(pb - pa)), n.cmp(std::uint64_t(pb - pa));
                    }
                }
            }
        }
        // ---- step to the next scan-line: x per eye, attributes once ----
        for (const int k : active) {
            for (int v = 0; v < K; ++v) s.x[v][k] += s.dx[v][k];
            for (int c = 0; c < A; ++c) s.a[c][k] += s.da[c][k];
        }
        n.interp(active.size() * std::uint64_t(K + A));
        ++yy;
    }
}

}  // namespace mvr::adelson::detail
