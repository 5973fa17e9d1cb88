// The workloads of adelson1991 Table 1 as mvr reproduces it (see adelsonCases()).
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "mvr/adelson/adelson.h"

namespace mvr::adelson {

namespace {

std::string num(std::size_t n) { return std::to_string(n); }

/// Compares two frames; "" when equal.
std::string compareFrames(const Frame& a, const Frame& b, const char* what) {
    std::size_t diff = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) diff += a.pixels[i] != b.pixels[i];
    if (diff == 0) return {};
    return std::string(what) + ": " + num(diff) + " of " + num(a.pixels.size()) + " pixels differ";
}

std::size_t covered(const Frame& f) {
    std::size_t c = 0;
    for (const std::uint32_t p : f.pixels) c += p != 0;
    return c;
}

/// 3D polygons (convex, planar, tilted) projected for both eyes into pixel coordinates.
struct PolygonSet {
    StereoCamera cam;
    std::vector<StereoPolygon> polys;
    Frame l1, r1, l2, r2;  // separate / simultaneous results
};

/// `count` polygons shaped by `shape(i, k, edges) → (u, v)` in pixels around a random center at
/// a random depth, on a plane tilted in z, with random vertex colors.
template <class Shape>
std::shared_ptr<PolygonSet> makePolygons(std::size_t count, int edges, int w, int h, Shape shape,
                                         std::uint32_t seed) {
    auto set = std::make_shared<PolygonSet>();
    set->cam = StereoCamera{2.0, 0.2, w, h, 160.0 * w / 640.0};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (std::size_t i = 0; i < count; ++i) {
        const double z = 2.0 + 6.0 * u01(rng);
        const double den = 1.0 + z / set->cam.d;
        // center in pixels → object space at depth z
        const double cx = (u01(rng) * w - w * 0.5) / set->cam.scale * den;
        const double cy = (h * 0.5 - u01(rng) * h) / set->cam.scale * den;
        const double tilt = (u01(rng) - 0.5) * 0.5;
        std::vector<Vec3> pts;
        StereoPolygon poly;
        for (int k = 0; k < edges; ++k) {
            const auto [du, dv] = shape(k, edges);
            const double ox = du / set->cam.scale * den, oy = dv / set->cam.scale * den;
            pts.push_back({cx + ox, cy + oy, z + tilt * ox});
            poly.color.push_back({float(u01(rng)), float(u01(rng)), float(u01(rng))});
        }
        std::vector<ProjectedStereo> pr(pts.size());
        projectStereo(pts, set->cam, pr);
        for (const ProjectedStereo& p : pr) {
            poly.xl.push_back(toPixelX(p.xl, set->cam));
            poly.xr.push_back(toPixelX(p.xr, set->cam));
            poly.y.push_back(toPixelY(p.y, set->cam));
        }
        set->polys.push_back(std::move(poly));
    }
    set->l1 = set->r1 = set->l2 = set->r2 = Frame(w, h);
    return set;
}

ExperimentCase fillCase(const std::string& algorithm, const std::string& name,
                        const std::string& label, bool gouraud, std::shared_ptr<PolygonSet> set) {
    ExperimentCase c;
    c.algorithm = algorithm;
    c.caseName = name;
    c.label = label;
    if (gouraud) {
        c.paperI = "4.5% - 37.5%", c.paperII = "9% - 75%", c.paperIII = "1.1 - 1.75";
    } else {
        c.paperI = "<1% - 25%", c.paperII = "<1% - 50%", c.paperIII = "1 - 1.5";
    }
    c.opsNote = gouraud ? "edge table, active edges, x/color interpolations, span setup"
                        : "edge table, active edges, x interpolations, span ends";
    c.separate = [set, gouraud](OpCounts* ops) {
        for (const StereoPolygon& p : set->polys) {
            if (gouraud) {
                fillGouraud(p.xl, p.y, p.color, set->l1, ops);
                fillGouraud(p.xr, p.y, p.color, set->r1, ops);
            } else {
                fillFlat(p.xl, p.y, 0xffffffffu, set->l1, ops);
                fillFlat(p.xr, p.y, 0xffffffffu, set->r1, ops);
            }
        }
    };
    c.simultaneous = [set, gouraud](OpCounts* ops) {
        for (const StereoPolygon& p : set->polys) {
            if (gouraud)
                fillGouraudStereo(p, set->l2, set->r2, ops);
            else
                fillFlatStereo(p, 0xffffffffu, set->l2, set->r2, ops);
        }
    };
    c.check = [set, sep = c.separate, sim = c.simultaneous](std::string& detail) {
        set->l1.clear(), set->r1.clear(), set->l2.clear(), set->r2.clear();
        sep(nullptr), sim(nullptr);
        detail = "identical images (" + num(covered(set->l1) + covered(set->r1)) + " pixels drawn)";
        std::string e = compareFrames(set->l1, set->l2, "left");
        if (e.empty()) e = compareFrames(set->r1, set->r2, "right");
        return e;
    };
    return c;
}

}  // namespace

std::vector<ExperimentCase> adelsonCases(bool tiny) {
    std::vector<ExperimentCase> cases;
    const int w = tiny ? 160 : 640, h = tiny ? 120 : 480;
    std::mt19937 rng(1991);
    std::uniform_real_distribution<double> u01(0.0, 1.0);

    // ---- perspective projection ----
    {
        struct State {
            StereoCamera cam;
            std::vector<Vec3> pts;
            std::vector<Projected> l, r;
            std::vector<ProjectedStereo> s;
        };
        auto st = std::make_shared<State>();
        const std::size_t n = tiny ? 1000 : 200000;
        for (std::size_t i = 0; i < n; ++i) {
            st->pts.push_back({u01(rng) * 8 - 4, u01(rng) * 6 - 3, 0.5 + u01(rng) * 20});
        }
        st->l.resize(n), st->r.resize(n), st->s.resize(n);
        ExperimentCase c;
        c.algorithm = "Perspective projection";
        c.caseName = num(n) + " points";
        c.label = "projection";
        c.paperI = "33%", c.paperII = "67%", c.paperIII = "1.67";
        c.opsNote = "additions + multiplications per point (2+4 per eye vs 3+5)";
        c.separate = [st](OpCounts* ops) {
            projectMono(st->pts, -1, st->cam, st->l, ops);
            projectMono(st->pts, +1, st->cam, st->r, ops);
        };
        c.simultaneous = [st](OpCounts* ops) { projectStereo(st->pts, st->cam, st->s, ops); };
        c.check = [st, sep = c.separate, sim = c.simultaneous](std::string& detail) -> std::string {
            sep(nullptr), sim(nullptr);
            for (std::size_t i = 0; i < st->pts.size(); ++i) {
                if (st->l[i].x != st->s[i].xl || st->r[i].x != st->s[i].xr ||
                    st->l[i].y != st->s[i].y || st->r[i].y != st->s[i].y) {
                    return "point " + num(i) + " projects differently";
                }
            }
            detail = "identical coordinates";
            return {};
        };
        cases.push_back(std::move(c));
    }

    // ---- scan-line polygon fill, flat and Gouraud ----
    const std::size_t np = tiny ? 20 : 2000;
    for (const int edges : {4, 8, 16, 32}) {
        auto set = makePolygons(
            np, edges, w, h,
            [](int k, int n) {
                const double a = 2.0 * 3.14159265358979 * (k + 0.25) / n;
                return std::pair{30.0 * std::cos(a), 30.0 * std::sin(a)};
            },
            10 + edges);
        cases.push_back(fillCase("Flat shaded polygon (scan-line fill)",
                                 num(np) + " " + num(edges) + "-edge polygons, 60 px across",
                                 "flat fill " + num(edges) + "-gon", false, set));
    }
    struct GShape {
        const char* name;
        const char* label;
        int edges;
        double wpx, hpx;
    };
    // The paper's examples: a flat wide triangle (22 edge / 211 interior pixels), a tower
    // (58 edge / 105 interior) and the two-pixel-wide best case; plus a 32-edge polygon.
    for (const GShape& g :
         {GShape{"wide flat triangles (~40x11 px)", "Gouraud wide", 3, 40.0, 11.0},
          GShape{"tower quads (~4x29 px)", "Gouraud tower", 4, 4.0, 29.0},
          GShape{"two-pixel-wide quads (2x40 px)", "Gouraud 2 px wide", 4, 2.0, 40.0},
          GShape{"32-edge polygons, 60 px across", "Gouraud 32-gon", 32, 60.0, 60.0}}) {
        auto set = makePolygons(
            np, g.edges, w, h,
            [g](int k, int n) {
                if (n == 3) {
                    const double xs[3] = {-0.5, 0.5, 0.1}, ys[3] = {0.5, 0.5, -0.5};
                    return std::pair{xs[k] * g.wpx, ys[k] * g.hpx};
                }
                if (n == 4) {
                    const double xs[4] = {-0.5, 0.5, 0.5, -0.5}, ys[4] = {-0.5, -0.5, 0.5, 0.5};
                    return std::pair{xs[k] * g.wpx, ys[k] * g.hpx};
                }
                const double a = 2.0 * 3.14159265358979 * (k + 0.25) / n;
                return std::pair{0.5 * g.wpx * std::cos(a), 0.5 * g.hpx * std::sin(a)};
            },
            100 + g.edges);
        cases.push_back(
            fillCase("Gouraud shaded polygon", num(np) + " " + g.name, g.label, true, set));
    }

    // ---- Liang–Barsky line clipping ----
    {
        struct State {
            ClipWindow win{-1.6, 1.6, -1.2, 1.2};
            std::vector<StereoSegment> segs;
            std::vector<Segment> l1, r1, l2, r2;
        };
        auto st = std::make_shared<State>();
        const StereoCamera cam;
        const std::size_t n = tiny ? 1000 : 200000;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 a{u01(rng) * 10 - 5, u01(rng) * 8 - 4, 0.5 + u01(rng) * 6};
            const Vec3 b{u01(rng) * 10 - 5, u01(rng) * 8 - 4, 0.5 + u01(rng) * 6};
            ProjectedStereo p[2];
            const Vec3 ab[2] = {a, b};
            projectStereo(ab, cam, p);
            st->segs.push_back({p[0].xl, p[0].xr, p[0].y, p[1].xl, p[1].xr, p[1].y});
        }
        st->l1.resize(n), st->r1.resize(n), st->l2.resize(n), st->r2.resize(n);
        ExperimentCase c;
        c.algorithm = "Liang-Barsky line clipping";
        c.caseName = num(n) + " random segments (both eyes), ~50% crossing the window";
        c.label = "LB line clip";
        c.paperI = "25%", c.paperII = "50%", c.paperIII = "1.5";
        c.opsNote = "border tests (t = q/p, compares), Δx/Δy, clipped end points";
        c.separate = [st](OpCounts* ops) {
            for (std::size_t i = 0; i < st->segs.size(); ++i) {
                const StereoSegment& s = st->segs[i];
                st->l1[i] = clipLine(s.xl0, s.y0, s.xl1, s.y1, st->win, ops);
                st->r1[i] = clipLine(s.xr0, s.y0, s.xr1, s.y1, st->win, ops);
            }
        };
        c.simultaneous = [st](OpCounts* ops) {
            for (std::size_t i = 0; i < st->segs.size(); ++i) {
                clipLineStereo(st->segs[i], st->win, st->l2[i], st->r2[i], ops);
            }
        };
        c.check = [st, sep = c.separate, sim = c.simultaneous](std::string& detail) -> std::string {
            sep(nullptr), sim(nullptr);
            std::size_t visible = 0;
            for (std::size_t i = 0; i < st->segs.size(); ++i) {
                const bool same = st->l1[i].visible == st->l2[i].visible &&
                                  st->r1[i].visible == st->r2[i].visible &&
                                  (!st->l1[i].visible || st->l1[i] == st->l2[i]) &&
                                  (!st->r1[i].visible || st->r1[i] == st->r2[i]);
                if (!same) return "segment " + num(i) + " clips differently";
                visible += st->l1[i].visible + st->r1[i].visible;
            }
            detail = "identical segments (" + num(visible) + " of " + num(2 * st->segs.size()) +
                     " visible)";
            return {};
        };
        cases.push_back(std::move(c));
    }

    // ---- Liang–Barsky polygon clipping ----
    {
        struct State {
            ClipWindow win{-1.6, 1.6, -1.2, 1.2};
            std::vector<StereoPolygon> polys;
            std::vector<std::vector<double>> l1x, l1y, r1x, r1y, l2x, l2y, r2x, r2y;
        };
        auto st = std::make_shared<State>();
        const StereoCamera cam;
        const std::size_t n = tiny ? 300 : 50000;
        for (std::size_t i = 0; i < n; ++i) {
            const int k = 3 + int(i % 4);
            const Vec3 c{u01(rng) * 8 - 4, u01(rng) * 6 - 3, 0.5 + u01(rng) * 6};
            const double r = 0.3 + u01(rng) * 2.0;
            StereoPolygon p;
            for (int j = 0; j < k; ++j) {
                const double a = 2.0 * 3.14159265358979 * j / k;
                const Vec3 v[1] = {
                    {c.x + r * std::cos(a), c.y + r * std::sin(a), c.z + 0.3 * std::cos(a)}};
                ProjectedStereo pr[1];
                projectStereo(v, cam, pr);
                p.xl.push_back(pr[0].xl), p.xr.push_back(pr[0].xr), p.y.push_back(pr[0].y);
            }
            st->polys.push_back(std::move(p));
        }
        for (auto* v :
             {&st->l1x, &st->l1y, &st->r1x, &st->r1y, &st->l2x, &st->l2y, &st->r2x, &st->r2y}) {
            v->resize(n);
        }
        ExperimentCase c;
        c.algorithm = "Liang-Barsky polygon clipping";
        c.caseName = num(n) + " random 3- to 6-gons (both eyes)";
        c.label = "LB polygon clip";
        c.paperI = "<1%", c.paperII = "<1%", c.paperIII = "1";
        c.opsNote = "per edge: entering/leaving borders, t values, their order, output vertices";
        c.separate = [st](OpCounts* ops) {
            for (std::size_t i = 0; i < st->polys.size(); ++i) {
                const StereoPolygon& p = st->polys[i];
                clipPolygon(p.xl, p.y, st->win, st->l1x[i], st->l1y[i], ops);
                clipPolygon(p.xr, p.y, st->win, st->r1x[i], st->r1y[i], ops);
            }
        };
        c.simultaneous = [st](OpCounts* ops) {
            for (std::size_t i = 0; i < st->polys.size(); ++i) {
                const StereoPolygon& p = st->polys[i];
                clipPolygonStereo(p.xl, p.xr, p.y, st->win, st->l2x[i], st->l2y[i], st->r2x[i],
                                  st->r2y[i], ops);
            }
        };
        c.check = [st, sep = c.separate, sim = c.simultaneous](std::string& detail) -> std::string {
            sep(nullptr), sim(nullptr);
            std::size_t verts = 0;
            for (std::size_t i = 0; i < st->polys.size(); ++i) {
                if (st->l1x[i] != st->l2x[i] || st->l1y[i] != st->l2y[i] ||
                    st->r1x[i] != st->r2x[i] || st->r1y[i] != st->r2y[i]) {
                    return "polygon " + num(i) + " clips differently";
                }
                verts += st->l1x[i].size() + st->r1x[i].size();
            }
            detail = "identical clipped polygons (" + num(verts) + " output vertices)";
            return {};
        };
        cases.push_back(std::move(c));
    }

    // ---- back-face removal ----
    {
        struct State {
            std::vector<PlaneEq> right, left;
            Vec3 viewer;
            double e = 0;
            std::vector<std::uint8_t> l, r, s;
        };
        auto st = std::make_shared<State>();
        // Inputs on a 1/1024 grid below 64 in magnitude: every product and sum below is exact
        // in double, so A·xv + … + (A·e + D) == (A·xv + … + D) + A·e and the separate and
        // simultaneous classifications must agree everywhere.
        auto q = [&](double lo, double hi) {
            return std::round((lo + u01(rng) * (hi - lo)) * 1024.0) / 1024.0;
        };
        st->viewer = {0.0, 0.0, -2.0};
        st->e = 0.25;
        const std::size_t n = tiny ? 1000 : 200000;
        for (std::size_t i = 0; i < n; ++i) {
            // planes through points near the viewer's sight line, so that both signs and the
            // split cases (front for one eye, back for the other) all occur
            const PlaneEq p{q(-1, 1), q(-1, 1), q(-1, 1), q(-2.5, 2.5)};
            st->right.push_back(p);
            st->left.push_back({p.a, p.b, p.c, p.a * st->e + p.d});
        }
        st->l.resize(n), st->r.resize(n), st->s.resize(n);
        ExperimentCase c;
        c.algorithm = "Back-face removal";
        c.caseName = num(n) + " random polygon planes";
        c.label = "back-face";
        c.paperI = "33%", c.paperII = "67%", c.paperIII = "1.67";
        c.opsNote = "2 x (3 mul + 3 add + 1 cmp) vs at most 4 mul + 4 add + 3 cmp";
        c.separate = [st](OpCounts* ops) {
            backFacesMono(st->left, st->viewer, st->l, ops);
            backFacesMono(st->right, st->viewer, st->r, ops);
        };
        c.simultaneous = [st](OpCounts* ops) {
            backFacesStereo(st->right, st->viewer, st->e, st->s, ops);
        };
        c.check = [st, sep = c.separate, sim = c.simultaneous](std::string& detail) -> std::string {
            sep(nullptr), sim(nullptr);
            std::size_t split = 0;
            for (std::size_t i = 0; i < st->s.size(); ++i) {
                const std::uint8_t want = std::uint8_t(st->l[i] | (st->r[i] << 1));
                if (want != st->s[i]) return "plane " + num(i) + " classified differently";
                split += st->l[i] != st->r[i];
            }
            detail =
                "identical classification (" + num(split) + " planes back-facing for one eye only)";
            return {};
        };
        ExperimentCase b = c;  // the same classification without the paper's branches
        b.caseName += ", branch-free simultaneous test";
        b.label = "back-face branch-free";
        b.opsNote = "2 x (3 mul + 3 add + 1 cmp) vs 4 mul + 4 add + 2 cmp, no branches";
        b.simultaneous = [st](OpCounts* ops) {
            backFacesStereoBranchFree(st->right, st->viewer, st->e, st->s, ops);
        };
        b.check = [st, sep = b.separate, sim = b.simultaneous](std::string& detail) -> std::string {
            sep(nullptr), sim(nullptr);
            for (std::size_t i = 0; i < st->s.size(); ++i) {
                if (std::uint8_t(st->l[i] | (st->r[i] << 1)) != st->s[i])
                    return "plane " + num(i) + " classified differently";
            }
            detail = "identical classification";
            return {};
        };
        cases.push_back(std::move(c));
        cases.push_back(std::move(b));
    }

    // ---- BSP tree + one z-buffer vs two BSP passes ----
    for (const int buildings : tiny ? std::vector<int>{1} : std::vector<int>{1, 8}) {
        struct State {
            StereoCamera cam;
            BspTree tree;
            Frame l1, r1, l2, r2;
            std::size_t input = 0;
        };
        auto st = std::make_shared<State>();
        st->cam = villageCamera(w, h);
        auto polys = makeVillage(buildings);
        st->input = polys.size();
        st->tree = buildBsp(std::move(polys));
        st->l1 = st->r1 = st->l2 = st->r2 = Frame(w, h);
        ExperimentCase c;
        c.algorithm = "BSP/Z-buffer compared to BSP";
        c.caseName = "village, " + num(buildings) +
                     (buildings == 1 ? " building: " : " buildings: ") + num(st->input) +
                     " polygons (" + num(st->tree.polygons.size()) + " after BSP splits)";
        c.paperI = "17%", c.paperII = "33%", c.paperIII = "1.33";
        c.label = "BSP+z vs 2 BSP, " + num(st->input) + " polys";
        c.opsNote = "traversal, projection, fills (z-buffer: z interpolation and tests)";
        c.separate = [st](OpCounts* ops) {
            renderBspMono(st->tree, -1, st->cam, st->l1, ops);
            renderBspMono(st->tree, +1, st->cam, st->r1, ops);
        };
        c.simultaneous = [st](OpCounts* ops) {
            renderBspZBuffer(st->tree, st->cam, st->l2, st->r2, ops);
        };
        c.check = [st, sep = c.separate, sim = c.simultaneous](std::string& detail) -> std::string {
            sep(nullptr), sim(nullptr);
            if (std::string e = compareFrames(st->r1, st->r2, "right (same BSP order)"); !e.empty())
                return e;
            std::size_t diff = 0;
            for (std::size_t i = 0; i < st->l1.pixels.size(); ++i)
                diff += st->l1.pixels[i] != st->l2.pixels[i];
            const std::size_t drawn = covered(st->l1);
            detail = "right identical; left (z-buffer vs painter's) differs on " + num(diff) +
                     " of " + num(drawn) + " pixels (surfaces meeting at equal depth)";
            if (double(diff) > 0.01 * double(drawn)) return "left eye: " + detail;
            return {};
        };
        cases.push_back(std::move(c));
    }

    // ---- scan-line hidden-surface removal and the simple renderer (village) ----
    {
        struct State {
            StereoCamera cam;
            std::vector<Polygon3> polys;
            Frame l1, r1, l2, r2;
        };
        auto st = std::make_shared<State>();
        st->cam = villageCamera(w, h);
        st->polys = makeVillage(tiny ? 2 : 8);
        shadeVertices(st->polys);
        st->l1 = st->r1 = st->l2 = st->r2 = Frame(w, h);
        auto compare = [st](std::string& detail) -> std::string {
            if (std::string e = compareFrames(st->l1, st->l2, "left"); !e.empty()) return e;
            if (std::string e = compareFrames(st->r1, st->r2, "right"); !e.empty()) return e;
            detail =
                "identical images (" + num(covered(st->l1) + covered(st->r1)) + " pixels drawn)";
            return {};
        };
        for (const bool gouraud : {false, true}) {
            ExperimentCase c;
            c.algorithm = "Scan-line hidden surface";
            c.caseName = "village, " + num(st->polys.size()) + " polygons, " + num(w) + "x" +
                         num(h) + (gouraud ? ", Gouraud" : ", flat");
            c.paperI = gouraud ? "17% (with Gouraud)" : "12%";
            c.label = gouraud ? "scan-line HSR Gouraud" : "scan-line HSR flat";
            c.paperII = gouraud ? "-" : "24%";
            c.paperIII = gouraud ? "-" : "1.24";
            c.opsNote =
                "projection, y-sorted edge list, active edges, x order, nearest span, span fill";
            c.separate = [st, gouraud](OpCounts* ops) {
                renderScanlineMono(st->polys, -1, st->cam, gouraud, st->l1, ops);
                renderScanlineMono(st->polys, +1, st->cam, gouraud, st->r1, ops);
            };
            c.simultaneous = [st, gouraud](OpCounts* ops) {
                renderScanlineStereo(st->polys, st->cam, gouraud, st->l2, st->r2, ops);
            };
            c.check = [compare, sep = c.separate, sim = c.simultaneous](std::string& detail) {
                sep(nullptr), sim(nullptr);
                return compare(detail);
            };
            cases.push_back(std::move(c));
        }
        ExperimentCase c;
        c.algorithm = "Simple renderer (village scene)";
        c.caseName = "village, " + num(st->polys.size()) + " polygons, " + num(w) + "x" + num(h) +
                     ": lighting, projection, scan-line HSR, Gouraud";
        c.paperI = "18.8%", c.paperII = "37.6%", c.paperIII = "1.38";
        c.label = "village renderer";
        c.opsNote = "Lambert vertex lighting (per program run) + the scan-line renderer";
        c.separate = [st](OpCounts* ops) {
            renderVillageMono(st->polys, -1, st->cam, st->l1, ops);
            renderVillageMono(st->polys, +1, st->cam, st->r1, ops);
        };
        c.simultaneous = [st](OpCounts* ops) {
            renderVillageStereo(st->polys, st->cam, st->l2, st->r2, ops);
        };
        c.check = [compare, sep = c.separate, sim = c.simultaneous](std::string& detail) {
            sep(nullptr), sim(nullptr);
            return compare(detail);
        };
        cases.push_back(std::move(c));
    }
    return cases;
}

}  // namespace mvr::adelson
