// Perspective projection, Liang–Barsky line and polygon clipping and back-face removal, each
// single-eye and simultaneous (adelson1991 §"Differences and similarities", "Line and polygon
// clipping", "Stereoscopic back-face removal").
#include <algorithm>
#include <cmath>
#include <limits>

#include "count.h"
#include "mvr/adelson/adelson.h"

namespace mvr::adelson {

using detail::Count;
using detail::dispatch;

void Frame::clear() {
    std::fill(pixels.begin(), pixels.end(), 0u);
    if (!depth.empty())
        std::fill(depth.begin(), depth.end(), std::numeric_limits<float>::infinity());
}

std::uint32_t packRgb(const Rgb& c) {
    auto q = [](float v) {
        const float s = std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f;
        return static_cast<std::uint32_t>(s);
    };
    return q(c.r) | (q(c.g) << 8) | (q(c.b) << 16) | 0xff000000u;
}

double toPixelX(double x, const StereoCamera& cam) { return cam.width * 0.5 + x * cam.scale; }
double toPixelY(double y, const StereoCamera& cam) { return cam.height * 0.5 - y * cam.scale; }

// ---- projection ---------------------------------------------------------------------------------

void projectMono(std::span<const Vec3> points, int eye, const StereoCamera& cam,
                 std::span<Projected> out, OpCounts* ops, bool withZ) {
    const double e2d = cam.e / (2.0 * cam.d);
    const double invD = 1.0 / cam.d;
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Vec3& p = points[i];
            const double t = p.z * e2d;
            const double num = eye < 0 ? p.x - t : p.x + t;
            const double den = 1.0 + p.z * invD;
            out[i].x = num / den;
            out[i].y = p.y / den;
            out[i].z = withZ ? p.z / den : 0.0;
            n.mul(withZ ? 5 : 4), n.add(2);
        }
        n.flush(ops);
    });
}

void projectStereo(std::span<const Vec3> points, const StereoCamera& cam,
                   std::span<ProjectedStereo> out, OpCounts* ops, bool withZ) {
    const double e2d = cam.e / (2.0 * cam.d);
    const double invD = 1.0 / cam.d;
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Vec3& p = points[i];
            const double t = p.z * e2d;
            const double den = 1.0 + p.z * invD;
            out[i].xl = (p.x - t) / den;
            out[i].xr = (p.x + t) / den;
            out[i].y = p.y / den;
            out[i].z = withZ ? p.z / den : 0.0;
            n.mul(withZ ? 6 : 5), n.add(3);
        }
        n.flush(ops);
    });
}

// ---- Liang–Barsky line clipping ------------------------------------------------------------------

namespace {

/// One border test of Liang–Barsky: p·t ≤ q. false = rejected.
template <bool On>
inline bool clipT(double p, double q, double& t0, double& t1, Count<On>& n) {
    n.cmp();
    if (p == 0.0) {
        n.cmp();
        return q >= 0.0;
    }
    const double r = q / p;
    n.mul(), n.cmp(2);
    if (p < 0.0) {
        if (r > t1) return false;
        n.cmp();
        if (r > t0) t0 = r;
    } else {
        if (r < t0) return false;
        n.cmp();
        if (r < t1) t1 = r;
    }
    return true;
}

template <bool On>
inline bool clipX(double x0, double dx, const ClipWindow& w, double& t0, double& t1, Count<On>& n) {
    n.add(2);
    return clipT(-dx, x0 - w.xmin, t0, t1, n) && clipT(dx, w.xmax - x0, t0, t1, n);
}

template <bool On>
inline bool clipY(double y0, double dy, const ClipWindow& w, double& t0, double& t1, Count<On>& n) {
    n.add(2);
    return clipT(-dy, y0 - w.ymin, t0, t1, n) && clipT(dy, w.ymax - y0, t0, t1, n);
}

template <bool On>
inline Segment finish(double x0, double y0, double dx, double dy, double t0, double t1,
                      Count<On>& n) {
    n.mul(4), n.add(4);
    return {x0 + t0 * dx, y0 + t0 * dy, x0 + t1 * dx, y0 + t1 * dy, true};
}

}  // namespace

Segment clipLine(double x0, double y0, double x1, double y1, const ClipWindow& w, OpCounts* ops) {
    Segment s;
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        const double dx = x1 - x0, dy = y1 - y0;
        n.add(2);
        double t0 = 0.0, t1 = 1.0;
        if (clipY(y0, dy, w, t0, t1, n) && clipX(x0, dx, w, t0, t1, n)) {
            s = finish(x0, y0, dx, dy, t0, t1, n);
        }
        n.flush(ops);
    });
    return s;
}

void clipLineStereo(const StereoSegment& s, const ClipWindow& w, Segment& left, Segment& right,
                    OpCounts* ops) {
    left = {}, right = {};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        const double dy = s.y1 - s.y0;
        n.add();
        double ty0 = 0.0, ty1 = 1.0;
        if (clipY(s.y0, dy, w, ty0, ty1, n)) {  // bottom and top once for both eyes
            const double dxl = s.xl1 - s.xl0, dxr = s.xr1 - s.xr0;
            n.add(2);
            double t0 = ty0, t1 = ty1;
            if (clipX(s.xl0, dxl, w, t0, t1, n)) left = finish(s.xl0, s.y0, dxl, dy, t0, t1, n);
            t0 = ty0, t1 = ty1;
            if (clipX(s.xr0, dxr, w, t0, t1, n)) right = finish(s.xr0, s.y0, dxr, dy, t0, t1, n);
        }
        n.flush(ops);
    });
}

// ---- Liang–Barsky polygon clipping ---------------------------------------------------------------

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The y terms of one edge: the same for both eyes.
struct EdgeY {
    double y1, y2, dy, yin, yout, touty;
    double tiny;
    bool haveTiny;
};

template <bool On>
inline EdgeY edgeY(double y1, double y2, const ClipWindow& w, Count<On>& n) {
    EdgeY e{y1, y2, y2 - y1, 0, 0, 0, 0, false};
    n.add(), n.cmp(2);
    if (e.dy > 0.0 || (e.dy == 0.0 && y1 > w.ymax)) {
        e.yin = w.ymin, e.yout = w.ymax;
    } else {
        e.yin = w.ymax, e.yout = w.ymin;
    }
    n.cmp();
    if (e.dy != 0.0) {
        e.touty = (e.yout - y1) / e.dy;
        n.add(), n.mul();
    } else {
        n.cmp(2);
        e.touty = (y1 <= w.ymax && w.ymin <= y1) ? kInf : -kInf;
    }
    return e;
}

template <bool On>
inline double tinY(EdgeY& e, Count<On>& n) {
    if (!e.haveTiny) {
        n.cmp();
        if (e.dy != 0.0) {
            e.tiny = (e.yin - e.y1) / e.dy;
            n.add(), n.mul();
        } else {
            e.tiny = -kInf;
        }
        e.haveTiny = true;
    }
    return e.tiny;
}

/// The rest of the turning-vertex algorithm for one edge and one eye (Foley et al. Fig. 3.48).
template <bool On>
inline void clipEdgeX(double x1, double x2, EdgeY& ey, const ClipWindow& w, std::vector<double>& ox,
                      std::vector<double>& oy, Count<On>& n) {
    const double dx = x2 - x1;
    double xin, xout;
    n.add(), n.cmp(2);
    if (dx > 0.0 || (dx == 0.0 && x1 > w.xmax)) {
        xin = w.xmin, xout = w.xmax;
    } else {
        xin = w.xmax, xout = w.xmin;
    }
    double toutx;
    n.cmp();
    if (dx != 0.0) {
        toutx = (xout - x1) / dx;
        n.add(), n.mul();
    } else {
        n.cmp(2);
        toutx = (x1 <= w.xmax && w.xmin <= x1) ? kInf : -kInf;
    }
    const double touty = ey.touty;
    double tout1, tout2;
    n.cmp();
    if (toutx < touty)
        tout1 = toutx, tout2 = touty;
    else
        tout1 = touty, tout2 = toutx;
    n.cmp();
    if (tout2 > 0.0) {
        double tinx;
        n.cmp();
        if (dx != 0.0) {
            tinx = (xin - x1) / dx;
            n.add(), n.mul();
        } else {
            tinx = -kInf;
        }
        const double tiny = tinY(ey, n);
        const double tin2 = tinx < tiny ? tiny : tinx;
        n.cmp(2);
        if (tout1 < tin2) {  // no visible segment: maybe a turning vertex
            n.cmp(2);
            if (0.0 < tout1 && tout1 <= 1.0) {
                n.cmp();
                if (tinx < tiny)
                    ox.push_back(xout), oy.push_back(ey.yin);
                else
                    ox.push_back(xin), oy.push_back(ey.yout);
            }
        } else {
            n.cmp(2);
            if (0.0 < tout1 && tin2 <= 1.0) {
                n.cmp();
                if (0.0 < tin2) {  // the edge enters the window
                    n.cmp(), n.mul(), n.add();
                    if (tinx > tiny)
                        ox.push_back(xin), oy.push_back(ey.y1 + tinx * ey.dy);
                    else
                        ox.push_back(x1 + tiny * dx), oy.push_back(ey.yin);
                }
                n.cmp();
                if (1.0 > tout1) {  // the edge leaves the window
                    n.cmp(), n.mul(), n.add();
                    if (toutx < touty)
                        ox.push_back(xout), oy.push_back(ey.y1 + toutx * ey.dy);
                    else
                        ox.push_back(x1 + touty * dx), oy.push_back(ey.yout);
                } else {
                    ox.push_back(x2), oy.push_back(ey.y2);
                }
            }
        }
        n.cmp(2);
        if (0.0 < tout2 && tout2 <= 1.0) ox.push_back(xout), oy.push_back(ey.yout);
    }
}

}  // namespace

void clipPolygon(std::span<const double> x, std::span<const double> y, const ClipWindow& w,
                 std::vector<double>& outX, std::vector<double>& outY, OpCounts* ops) {
    outX.clear(), outY.clear();
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        const std::size_t count = x.size();
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t j = i + 1 == count ? 0 : i + 1;
            EdgeY ey = edgeY(y[i], y[j], w, n);
            clipEdgeX(x[i], x[j], ey, w, outX, outY, n);
        }
        n.flush(ops);
    });
}

void clipPolygonStereo(std::span<const double> xl, std::span<const double> xr,
                       std::span<const double> y, const ClipWindow& w, std::vector<double>& outXl,
                       std::vector<double>& outYl, std::vector<double>& outXr,
                       std::vector<double>& outYr, OpCounts* ops) {
    outXl.clear(), outYl.clear(), outXr.clear(), outYr.clear();
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        const std::size_t count = y.size();
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t j = i + 1 == count ? 0 : i + 1;
            EdgeY ey = edgeY(y[i], y[j], w, n);  // once for both eyes
            clipEdgeX(xl[i], xl[j], ey, w, outXl, outYl, n);
            clipEdgeX(xr[i], xr[j], ey, w, outXr, outYr, n);
        }
        n.flush(ops);
    });
}

// ---- back-face removal ---------------------------------------------------------------------------

void backFacesMono(std::span<const PlaneEq> planes, const Vec3& v, std::span<std::uint8_t> out,
                   OpCounts* ops) {
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        for (std::size_t i = 0; i < planes.size(); ++i) {
            const PlaneEq& p = planes[i];
            out[i] = (p.a * v.x + p.b * v.y + p.c * v.z + p.d) < 0.0 ? 1 : 0;
            n.mul(3), n.add(3), n.cmp();
        }
        n.flush(ops);
    });
}

void backFacesStereo(std::span<const PlaneEq> planes, const Vec3& v, double e,
                     std::span<std::uint8_t> out, OpCounts* ops) {
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        for (std::size_t i = 0; i < planes.size(); ++i) {
            const PlaneEq& p = planes[i];
            const double s = p.a * v.x + p.b * v.y + p.c * v.z + p.d;  // right eye
            const double ae = p.a * e;
            const double sl = s + ae;  // left eye: the plane (A, B, C, A·e + D)
            n.mul(4), n.add(4), n.cmp(2);
            // bit 0: left back, bit 1: right back (the paper's 4 cases, with its strict "< 0").
            if (ae > 0.0) {  // sl > s
                if (sl < 0.0) {
                    out[i] = 3;
                } else {
                    n.cmp();
                    out[i] = s < 0.0 ? 2 : 0;
                }
            } else {  // sl <= s
                if (sl >= 0.0) {
                    out[i] = 0;
                } else {
                    n.cmp();
                    out[i] = s < 0.0 ? 3 : 1;
                }
            }
        }
        n.flush(ops);
    });
}

void backFacesStereoBranchFree(std::span<const PlaneEq> planes, const Vec3& v, double e,
                               std::span<std::uint8_t> out, OpCounts* ops) {
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        for (std::size_t i = 0; i < planes.size(); ++i) {
            const PlaneEq& p = planes[i];
            const double s = p.a * v.x + p.b * v.y + p.c * v.z + p.d;
            const double sl = s + p.a * e;
            out[i] = std::uint8_t((sl < 0.0 ? 1 : 0) | (s < 0.0 ? 2 : 0));
            n.mul(4), n.add(4), n.cmp(2);
        }
        n.flush(ops);
    });
}

}  // namespace mvr::adelson
