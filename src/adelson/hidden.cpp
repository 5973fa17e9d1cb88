// Hidden-surface removal (adelson1991 "Hidden surface elimination"): BSP tree painted per eye
// vs one BSP pass + one z-buffer; scan-line hidden-surface removal single-eye and
// simultaneous; the simple renderer of the village test.
#include <algorithm>
#include <cmath>
#include <limits>

#include "count.h"
#include "mvr/adelson/adelson.h"
#include "scan.h"

namespace mvr::adelson {

using detail::Count;
using detail::dispatch;
using detail::Mode;
using detail::scanFill;

namespace {

/// A distinct, stable color per polygon id (the test compares ids through colors).
std::uint32_t idColor(std::uint32_t id) {
    std::uint32_t h = (id + 1u) * 2654435761u;
    return (h & 0x00ffffffu) | 0xff000000u;
}

double side(const PlaneEq& p, const Vec3& v) { return p.a * v.x + p.b * v.y + p.c * v.z + p.d; }

constexpr double kPlaneEps = 1e-9;

/// Splits `poly` by `plane` into its front and back parts (either may come back empty).
void splitPolygon(const Polygon3& poly, const PlaneEq& plane, Polygon3& front, Polygon3& back) {
    front = {}, back = {};
    front.albedo = back.albedo = poly.albedo;
    front.id = back.id = poly.id;
    const std::size_t n = poly.v.size();
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = i + 1 == n ? 0 : i + 1;
        const Vec3 &a = poly.v[i], &b = poly.v[j];
        const double sa = side(plane, a), sb = side(plane, b);
        if (sa >= -kPlaneEps) front.v.push_back(a), front.color.push_back(poly.color[i]);
        if (sa <= kPlaneEps) back.v.push_back(a), back.color.push_back(poly.color[i]);
        if ((sa > kPlaneEps && sb < -kPlaneEps) || (sa < -kPlaneEps && sb > kPlaneEps)) {
            const double t = sa / (sa - sb);
            const Vec3 p{a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
            const Rgb &ca = poly.color[i], &cb = poly.color[j];
            const Rgb c{float(ca.r + (cb.r - ca.r) * t), float(ca.g + (cb.g - ca.g) * t),
                        float(ca.b + (cb.b - ca.b) * t)};
            front.v.push_back(p), front.color.push_back(c);
            back.v.push_back(p), back.color.push_back(c);
        }
    }
    if (front.v.size() < 3) front.v.clear(), front.color.clear();
    if (back.v.size() < 3) back.v.clear(), back.color.clear();
}

int buildNode(BspTree& tree, std::vector<Polygon3> polys) {
    if (polys.empty()) return -1;
    // Root: the candidate among the first few that splits the fewest others.
    std::size_t best = 0, bestSplits = std::numeric_limits<std::size_t>::max();
    for (std::size_t c = 0; c < std::min<std::size_t>(polys.size(), 5); ++c) {
        const PlaneEq pl = planeOf(polys[c]);
        std::size_t splits = 0;
        for (const Polygon3& p : polys) {
            bool f = false, bk = false;
            for (const Vec3& v : p.v) {
                const double s = side(pl, v);
                f |= s > kPlaneEps, bk |= s < -kPlaneEps;
            }
            splits += f && bk;
        }
        if (splits < bestSplits) best = c, bestSplits = splits;
    }
    std::swap(polys[0], polys[best]);
    const PlaneEq plane = planeOf(polys[0]);
    std::vector<Polygon3> front, back;
    for (std::size_t i = 1; i < polys.size(); ++i) {
        bool coplanar = true;
        for (const Vec3& v : polys[i].v)
            coplanar = coplanar && std::abs(side(plane, v)) <= kPlaneEps;
        if (coplanar) {  // on the plane: draw with the front side
            front.push_back(std::move(polys[i]));
            continue;
        }
        Polygon3 f, b;
        splitPolygon(polys[i], plane, f, b);
        if (!f.v.empty()) front.push_back(std::move(f));
        if (!b.v.empty()) back.push_back(std::move(b));
    }
    const int index = int(tree.nodes.size());
    tree.nodes.push_back({});
    tree.nodes[index].polygon = std::uint32_t(tree.polygons.size());
    tree.nodes[index].plane = plane;
    tree.polygons.push_back(std::move(polys[0]));
    const int f = buildNode(tree, std::move(front));
    const int b = buildNode(tree, std::move(back));
    tree.nodes[index].front = f;
    tree.nodes[index].back = b;
    return index;
}

/// Projects one polygon for one eye (the expressions of projectMono) into pixel coordinates.
template <bool On>
void projectPixelsMono(const Polygon3& p, int eye, const StereoCamera& cam, std::vector<double>& x,
                       std::vector<double>& y, Count<On>& n) {
    const double e2d = cam.e / (2.0 * cam.d), invD = 1.0 / cam.d;
    const double hw = cam.width * 0.5, hh = cam.height * 0.5;
    x.resize(p.v.size()), y.resize(p.v.size());
    for (std::size_t i = 0; i < p.v.size(); ++i) {
        const Vec3& v = p.v[i];
        const double t = v.z * e2d;
        const double num = eye < 0 ? v.x - t : v.x + t;
        const double den = 1.0 + v.z * invD;
        x[i] = hw + (num / den) * cam.scale;
        y[i] = hh - (v.y / den) * cam.scale;
        n.mul(6), n.add(4);
    }
}

/// Both eyes (the expressions of projectStereo) plus the projected z.
template <bool On>
void projectPixelsStereo(const Polygon3& p, const StereoCamera& cam, std::vector<double>& xl,
                         std::vector<double>& xr, std::vector<double>& y, std::vector<double>& z,
                         Count<On>& n) {
    const double e2d = cam.e / (2.0 * cam.d), invD = 1.0 / cam.d;
    const double hw = cam.width * 0.5, hh = cam.height * 0.5;
    const std::size_t count = p.v.size();
    xl.resize(count), xr.resize(count), y.resize(count), z.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3& v = p.v[i];
        const double t = v.z * e2d;
        const double den = 1.0 + v.z * invD;
        xl[i] = hw + ((v.x - t) / den) * cam.scale;
        xr[i] = hw + ((v.x + t) / den) * cam.scale;
        y[i] = hh - (v.y / den) * cam.scale;
        z[i] = v.z / den;
        n.mul(9), n.add(6);
    }
}

template <bool On>
void bspMono(const BspTree& tree, int node, const Vec3& eyePos, int eye, const StereoCamera& cam,
             Frame& frame, Count<On>& n, std::vector<double>& x, std::vector<double>& y) {
    if (node < 0) return;
    const BspTree::Node& nd = tree.nodes[node];
    const bool eyeInFront = side(nd.plane, eyePos) >= 0.0;
    n.mul(3), n.add(3), n.cmp();
    bspMono(tree, eyeInFront ? nd.back : nd.front, eyePos, eye, cam, frame, n, x, y);
    const Polygon3& p = tree.polygons[nd.polygon];
    projectPixelsMono(p, eye, cam, x, y, n);
    const double* xs[1] = {x.data()};
    Frame* frames[1] = {&frame};
    scanFill<On, 1, Mode::Flat>(xs, y.data(), y.size(), nullptr, idColor(p.id), frames, n);
    bspMono(tree, eyeInFront ? nd.front : nd.back, eyePos, eye, cam, frame, n, x, y);
}

struct StereoScratch {
    std::vector<double> xl, xr, y, z;
};

template <bool On>
void bspZ(const BspTree& tree, int node, const Vec3& eyePos, const StereoCamera& cam, Frame& left,
          Frame& right, Count<On>& n, StereoScratch& s) {
    if (node < 0) return;
    const BspTree::Node& nd = tree.nodes[node];
    const bool eyeInFront = side(nd.plane, eyePos) >= 0.0;
    n.mul(3), n.add(3), n.cmp();
    bspZ(tree, eyeInFront ? nd.back : nd.front, eyePos, cam, left, right, n, s);
    const Polygon3& p = tree.polygons[nd.polygon];
    projectPixelsStereo(p, cam, s.xl, s.xr, s.y, s.z, n);
    // One edge table for both eyes: the left eye z-buffered, the right eye painted in order.
    const double* xs[2] = {s.xl.data(), s.xr.data()};
    const double* zs[1] = {s.z.data()};
    Frame* frames[2] = {&left, &right};
    scanFill<On, 2, Mode::ZLeftFlatRight>(xs, s.y.data(), s.y.size(), zs, idColor(p.id), frames, n);
    bspZ(tree, eyeInFront ? nd.front : nd.back, eyePos, cam, left, right, n, s);
}

}  // namespace

BspTree buildBsp(std::vector<Polygon3> polygons) {
    BspTree tree;
    tree.root = buildNode(tree, std::move(polygons));
    return tree;
}

void renderBspMono(const BspTree& tree, int eye, const StereoCamera& cam, Frame& frame,
                   OpCounts* ops) {
    frame.clear();
    const Vec3 eyePos{eye < 0 ? -cam.e / 2 : cam.e / 2, 0.0, -cam.d};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        std::vector<double> x, y;
        bspMono(tree, tree.root, eyePos, eye, cam, frame, n, x, y);
        n.flush(ops);
    });
}

void renderBspZBuffer(const BspTree& tree, const StereoCamera& cam, Frame& left, Frame& right,
                      OpCounts* ops) {
    if (left.depth.size() != left.pixels.size()) left.depth.resize(left.pixels.size());
    left.clear(), right.clear();
    const Vec3 eyePos{cam.e / 2, 0.0, -cam.d};  // traversal order of the right eye
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        StereoScratch s;
        bspZ(tree, tree.root, eyePos, cam, left, right, n, s);
        n.flush(ops);
    });
}

// ---- scan-line hidden-surface removal ----------------------------------------------------------

namespace {

struct HsrEdge {
    int ys = 0, ye = 0;
    std::uint32_t poly = 0;
    std::uint32_t lo = 0, hi = 0;  ///< global vertex indices
    double inv = 0, off = 0;
};

/// Per polygon, per eye and scan-line: its span [xa, xb) with z and colors at both ends.
struct Span {
    double xa = 0, xb = 0;
    double za = 0, zb = 0;
    double ca[3] = {0, 0, 0}, cb[3] = {0, 0, 0};
    int line = -1;  ///< scan-line · K + eye of xa (a stamp: no clearing per line)
    bool haveB = false;
    bool inside = false;
};

struct HsrScratch {
    std::vector<double> x[2], y, z, col[3];
    std::vector<std::uint32_t> vertexPoly;
    std::vector<HsrEdge> edges;
    std::vector<double> ex[2], edx[2], ez, edz, ec[3], edc[3];
    std::vector<int> order[2];
    std::vector<unsigned char> dead;
    std::vector<Span> spans;
    std::vector<int> inside;
    std::vector<std::uint32_t> flat;
};

template <bool On, int K>
void scanlineHsr(std::span<const Polygon3> polys, int eye, const StereoCamera& cam, bool gouraud,
                 Frame* const* frames, Count<On>& n) {
    thread_local HsrScratch s;
    // ---- projection: y and z shared, x per eye (the expressions of projectMono/Stereo) ----
    std::size_t nv = 0;
    for (const Polygon3& p : polys) nv += p.v.size();
    for (int v = 0; v < K; ++v) s.x[v].resize(nv);
    s.y.resize(nv), s.z.resize(nv);
    for (int c = 0; c < 3; ++c) s.col[c].resize(nv);
    s.flat.resize(polys.size());
    const double e2d = cam.e / (2.0 * cam.d), invD = 1.0 / cam.d;
    const double hw = cam.width * 0.5, hh = cam.height * 0.5;
    std::size_t base = 0;
    for (std::size_t pi = 0; pi < polys.size(); ++pi) {
        const Polygon3& p = polys[pi];
        s.flat[pi] = packRgb(p.color[0]);
        for (std::size_t i = 0; i < p.v.size(); ++i) {
            const Vec3& v = p.v[i];
            const double t = v.z * e2d;
            const double den = 1.0 + v.z * invD;
            if constexpr (K == 1) {
                const double num = eye < 0 ? v.x - t : v.x + t;
                s.x[0][base + i] = hw + (num / den) * cam.scale;
                n.mul(6), n.add(4);
            } else {
                s.x[0][base + i] = hw + ((v.x - t) / den) * cam.scale;
                s.x[1][base + i] = hw + ((v.x + t) / den) * cam.scale;
                n.mul(9), n.add(6);
            }
            s.y[base + i] = hh - (v.y / den) * cam.scale;
            s.z[base + i] = v.z / den;
            s.col[0][base + i] = p.color[i].r, s.col[1][base + i] = p.color[i].g,
                            s.col[2][base + i] = p.color[i].b;
        }
        base += p.v.size();
    }
    // ---- the y-sorted edge list (shared) ----
    s.edges.clear();
    base = 0;
    for (std::size_t pi = 0; pi < polys.size(); ++pi) {
        const std::size_t count = polys[pi].v.size();
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t a = std::uint32_t(base + i),
                                b = std::uint32_t(base + (i + 1 == count ? 0 : i + 1));
            n.cmp();
            if (s.y[a] == s.y[b]) continue;
            HsrEdge e;
            e.poly = std::uint32_t(pi);
            n.cmp();
            if (s.y[a] < s.y[b])
                e.lo = a, e.hi = b;
            else
                e.lo = b, e.hi = a;
            const double y0 = s.y[e.lo], y1 = s.y[e.hi];
            e.ys = int(std::ceil(y0 - 0.5)), e.ye = int(std::ceil(y1 - 0.5));
            n.add(2), n.cmp();
            if (e.ys >= e.ye) continue;
            e.inv = 1.0 / (y1 - y0);
            e.off = (double(e.ys) + 0.5) - y0;
            n.add(3), n.mul();
            s.edges.push_back(e);
        }
        base += count;
    }
    std::stable_sort(s.edges.begin(), s.edges.end(), [&](const HsrEdge& p, const HsrEdge& q) {
        n.cmp();
        return p.ys < q.ys;
    });
    const std::size_t ne = s.edges.size();
    const int nc = gouraud ? 3 : 0;
    s.ez.resize(ne), s.edz.resize(ne);
    for (int c = 0; c < 3; ++c) s.ec[c].resize(ne), s.edc[c].resize(ne);
    for (std::size_t k = 0; k < ne; ++k) {  // z and colors along the edges: shared
        const HsrEdge& e = s.edges[k];
        s.edz[k] = (s.z[e.hi] - s.z[e.lo]) * e.inv;
        s.ez[k] = s.z[e.lo] + e.off * s.edz[k];
        n.add(2), n.mul(2);
        for (int c = 0; c < nc; ++c) {
            s.edc[c][k] = (s.col[c][e.hi] - s.col[c][e.lo]) * e.inv;
            s.ec[c][k] = s.col[c][e.lo] + e.off * s.edc[c][k];
            n.add(2), n.mul(2);
        }
    }
    for (int v = 0; v < K; ++v) {  // x along the edges: per eye
        s.ex[v].resize(ne), s.edx[v].resize(ne);
        for (std::size_t k = 0; k < ne; ++k) {
            const HsrEdge& e = s.edges[k];
            s.edx[v][k] = (s.x[v][e.hi] - s.x[v][e.lo]) * e.inv;
            s.ex[v][k] = s.x[v][e.lo] + e.off * s.edx[v][k];
            n.add(2), n.mul(2);
        }
        s.order[v].clear();
    }
    s.dead.assign(ne, 0);
    s.spans.assign(polys.size(), Span{});
    if (ne == 0) return;
    const int width = frames[0]->width, height = frames[0]->height;
    std::vector<int> active;
    std::size_t next = 0;
    int yy = s.edges[0].ys;
    while (next < ne || !active.empty()) {
        if (active.empty()) yy = std::max(yy, s.edges[next].ys);
        if (yy >= height) break;
        bool anyDead = false;
        for (const int k : active) {
            n.cmp();
            if (s.edges[k].ye <= yy) s.dead[k] = 1, anyDead = true;
        }
        if (anyDead) {
            std::erase_if(active, [&](int k) { return s.dead[k] != 0; });
            for (int v = 0; v < K; ++v)
                std::erase_if(s.order[v], [&](int k) { return s.dead[k] != 0; });
        }
        while (next < ne && s.edges[next].ys == yy) {
            n.cmp();
            active.push_back(int(next));
            for (int v = 0; v < K; ++v) s.order[v].push_back(int(next));
            ++next;
        }
        for (int v = 0; v < K && yy >= 0; ++v) {
            std::vector<int>& ord = s.order[v];
            const double* xv = s.ex[v].data();
            for (std::size_t i = 1; i < ord.size(); ++i) {  // x order of the crossings
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
            // Each polygon's span on this line (its first and second crossing in x order).
            const int stamp = yy * K + v;
            for (const int k : ord) {
                Span& sp = s.spans[s.edges[k].poly];
                if (sp.line != stamp) {
                    sp.line = stamp, sp.haveB = false, sp.inside = false;
                    sp.xa = xv[k], sp.za = s.ez[k];
                    for (int c = 0; c < nc; ++c) sp.ca[c] = s.ec[c][k];
                } else {
                    sp.haveB = true;
                    sp.xb = xv[k], sp.zb = s.ez[k];
                    for (int c = 0; c < nc; ++c) sp.cb[c] = s.ec[c][k];
                }
            }
            // Sweep: between successive crossings the nearest polygon at the interval's center.
            std::uint32_t* row = frames[v]->pixels.data() + std::size_t(yy) * width;
            s.inside.clear();
            for (std::size_t i = 0; i < ord.size(); ++i) {
                const std::uint32_t pi = s.edges[ord[i]].poly;
                Span& sp = s.spans[pi];
                if (!sp.inside) {
                    sp.inside = true;
                    s.inside.push_back(int(pi));
                } else {
                    sp.inside = false;
                    std::erase(s.inside, int(pi));
                }
                if (s.inside.empty() || i + 1 == ord.size()) continue;
                int pa = int(std::ceil(xv[ord[i]] - 0.5)),
                    pb = int(std::ceil(xv[ord[i + 1]] - 0.5));
                n.add(2);
                pa = std::max(pa, 0), pb = std::min(pb, width);
                if (pa >= pb) continue;
                const double xm = (double(pa) + double(pb)) * 0.5;
                n.add(), n.mul();
                int best = -1;
                double bestZ = std::numeric_limits<double>::infinity();
                for (const int q : s.inside) {
                    const Span& c = s.spans[q];
                    if (!c.haveB) continue;
                    const double w = c.xb - c.xa;
                    const double zq = w > 0.0 ? c.za + (xm - c.xa) * ((c.zb - c.za) / w) : c.za;
                    n.add(4), n.mul(2), n.cmp(3);
                    if (zq < bestZ || (zq == bestZ && q < best)) bestZ = zq, best = q;
                }
                if (best < 0) continue;
                const Span& c = s.spans[best];
                if (!gouraud) {
                    std::fill(row + pa, row + pb, s.flat[best]);
                } else {
                    const double w = c.xb - c.xa;
                    const double start = (double(pa) + 0.5) - c.xa;
                    double col[3], d[3];
                    for (int ch = 0; ch < 3; ++ch) {
                        d[ch] = w > 0.0 ? (c.cb[ch] - c.ca[ch]) / w : 0.0;
                        col[ch] = c.ca[ch] + start * d[ch];
                    }
                    n.add(2 + 6), n.mul(6);
                    for (int px = pa; px < pb; ++px) {
                        row[px] = detail::packD(col[0], col[1], col[2]);
                        col[0] += d[0], col[1] += d[1], col[2] += d[2];
                    }
                    n.interp(3 * std::uint64_t(pb - pa));
                }
            }
        }
        for (const int k : active) {  // next line: x per eye, z and colors once
            for (int v = 0; v < K; ++v) s.ex[v][k] += s.edx[v][k];
            s.ez[k] += s.edz[k];
            for (int c = 0; c < nc; ++c) s.ec[c][k] += s.edc[c][k];
        }
        n.interp(active.size() * std::uint64_t(K + 1 + nc));
        ++yy;
    }
}

}  // namespace

void renderScanlineMono(std::span<const Polygon3> polys, int eye, const StereoCamera& cam,
                        bool gouraud, Frame& frame, OpCounts* ops) {
    frame.clear();
    Frame* frames[1] = {&frame};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        scanlineHsr<On, 1>(polys, eye, cam, gouraud, frames, n);
        n.flush(ops);
    });
}

void renderScanlineStereo(std::span<const Polygon3> polys, const StereoCamera& cam, bool gouraud,
                          Frame& left, Frame& right, OpCounts* ops) {
    left.clear(), right.clear();
    Frame* frames[2] = {&left, &right};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        scanlineHsr<On, 2>(polys, 0, cam, gouraud, frames, n);
        n.flush(ops);
    });
}

void renderVillageMono(std::vector<Polygon3>& polys, int eye, const StereoCamera& cam, Frame& frame,
                       OpCounts* ops) {
    shadeVertices(polys, ops);
    renderScanlineMono(polys, eye, cam, true, frame, ops);
}

void renderVillageStereo(std::vector<Polygon3>& polys, const StereoCamera& cam, Frame& left,
                         Frame& right, OpCounts* ops) {
    shadeVertices(polys, ops);
    renderScanlineStereo(polys, cam, true, left, right, ops);
}

Savings savingsFrom(double separate, double simultaneous) {
    Savings s;
    if (!(separate > 0.0) || !(simultaneous > 0.0)) return s;
    s.measureI = 1.0 - simultaneous / separate;
    const double first = separate * 0.5;
    s.measureII = 1.0 - (simultaneous - first) / first;
    s.measureIII = separate / simultaneous;
    return s;
}

}  // namespace mvr::adelson
