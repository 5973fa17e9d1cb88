#include <cmath>

#include <gtest/gtest.h>

#include "mvr/adelson/adelson.h"

namespace mvr::adelson {
namespace {

// ---- every Table 1 workload: simultaneous == separate --------------------------------------------

class CaseTest : public ::testing::TestWithParam<std::size_t> {};

TEST_P(CaseTest, SimultaneousEqualsTwoSingleEyeRuns) {
    std::vector<ExperimentCase> cases = adelsonCases(true);
    ASSERT_LT(GetParam(), cases.size());
    ExperimentCase& c = cases[GetParam()];
    std::string detail;
    EXPECT_EQ(c.check(detail), "") << c.algorithm << ": " << c.caseName;
    EXPECT_FALSE(detail.empty());
    OpCounts sep, sim;
    c.separate(&sep);
    c.simultaneous(&sim);
    EXPECT_GT(sep.total(), 0u) << c.algorithm;
    // The simultaneous version never needs more operations than two single-eye runs — except
    // BSP + one z-buffer, which trades a traversal and the shared projection for a z
    // interpolation and test per left-eye pixel (adelson1991 measured its time, not its ops).
    if (c.algorithm.find("BSP") == std::string::npos) {
        EXPECT_LE(sim.total(), sep.total()) << c.algorithm << ": " << c.caseName;
    }
}

INSTANTIATE_TEST_SUITE_P(Table1, CaseTest,
                         ::testing::Range<std::size_t>(0, adelsonCases(true).size()),
                         [](const ::testing::TestParamInfo<std::size_t>& param) {
                             std::string name = adelsonCases(true)[param.param].algorithm;
                             std::string out;
                             for (const char ch : name)
                                 out += std::isalnum((unsigned char)ch) ? ch : '_';
                             return out + "_" + std::to_string(param.param);
                         });

TEST(Adelson, FullWorkloadsAgreeToo) {
    // The bench's own workloads (not tiny) for the cheap rows.
    std::vector<ExperimentCase> cases = adelsonCases(false);
    for (ExperimentCase& c : cases) {
        if (c.algorithm.find("Perspective") == std::string::npos &&
            c.algorithm.find("Back-face") == std::string::npos &&
            c.algorithm.find("line clipping") == std::string::npos) {
            continue;
        }
        std::string detail;
        EXPECT_EQ(c.check(detail), "") << c.algorithm;
    }
}

// ---- the paper's operation counts ---------------------------------------------------------------

TEST(Adelson, ProjectionCountsAreThePapers) {
    const StereoCamera cam;
    const Vec3 p[1] = {{0.3, -0.2, 4.0}};
    Projected l[1], r[1];
    ProjectedStereo s[1];
    OpCounts mono, stereo;
    projectMono(p, -1, cam, l, &mono);
    projectMono(p, +1, cam, r, &mono);
    projectStereo(p, cam, s, &stereo);
    EXPECT_EQ(mono.adds, 4u);
    EXPECT_EQ(mono.muls, 8u);
    EXPECT_EQ(stereo.adds, 3u);
    EXPECT_EQ(stereo.muls, 5u);
    // x_left = (x − z·e/2d) / (1 + z/d)
    const double den = 1.0 + 4.0 / cam.d;
    EXPECT_NEAR(l[0].x, (0.3 - 4.0 * cam.e / (2 * cam.d)) / den, 1e-15);
    EXPECT_NEAR(r[0].x, (0.3 + 4.0 * cam.e / (2 * cam.d)) / den, 1e-15);
    EXPECT_EQ(l[0].y, r[0].y);
    // the paper's equivalent form: x_left = (x + e/2) / (1 + z/d) − e/2
    EXPECT_NEAR(l[0].x, (0.3 + cam.e / 2) / den - cam.e / 2, 1e-12);
}

TEST(Adelson, BackFaceWorstCaseCountIsThePapers) {
    // Right eye back, left eye front (A·e > 0 branch, second test): 4 mul, 4 add, 3 cmp.
    const PlaneEq planes[1] = {{1.0, 0.0, 0.0, -0.1}};  // x = 0.1, normal +x
    const Vec3 viewer{0.0, 0.0, -2.0};
    std::uint8_t out[1];
    OpCounts ops;
    backFacesStereo(planes, viewer, 0.25, out, &ops);
    EXPECT_EQ(ops.muls, 4u);
    EXPECT_EQ(ops.adds, 4u);
    EXPECT_EQ(ops.cmps, 3u);
    EXPECT_EQ(out[0], 2);  // back for the right eye only
    OpCounts mono;
    std::uint8_t l[1], r[1];
    const PlaneEq left[1] = {{1.0, 0.0, 0.0, 1.0 * 0.25 - 0.1}};
    backFacesMono(left, viewer, l, &mono);
    backFacesMono(planes, viewer, r, &mono);
    EXPECT_EQ(mono.muls, 6u);
    EXPECT_EQ(mono.adds, 6u);
    EXPECT_EQ(mono.cmps, 2u);
    EXPECT_EQ(l[0], 0);
    EXPECT_EQ(r[0], 1);
}

TEST(Adelson, GouraudEdgeInterpolationsFiveInsteadOfEight) {
    // A 1-pixel-wide vertical sliver: per scan-line 2 edges, nothing inside but 1 pixel.
    StereoPolygon p;
    p.xl = {10.2, 11.2, 11.2, 10.2};
    p.xr = {12.2, 13.2, 13.2, 12.2};
    p.y = {5.0, 5.0, 25.0, 25.0};
    p.color.assign(4, Rgb{0.5f, 0.2f, 0.1f});
    Frame l1(32, 32), r1(32, 32), l2(32, 32), r2(32, 32);
    OpCounts mono, stereo;
    fillGouraud(p.xl, p.y, p.color, l1, &mono);
    fillGouraud(p.xr, p.y, p.color, r1, &mono);
    fillGouraudStereo(p, l2, r2, &stereo);
    EXPECT_EQ(l1.pixels, l2.pixels);
    EXPECT_EQ(r1.pixels, r2.pixels);
    // 20 scan-lines × 2 edges: 8 vs 5 interpolations per edge scan-line; 3 per interior pixel.
    EXPECT_EQ(mono.interps, 20u * 2 * 8 + 2 * 20 * 3);
    EXPECT_EQ(stereo.interps, 20u * 2 * 5 + 2 * 20 * 3);
}

// ---- clipping on hand-made cases ------------------------------------------------------------------

TEST(Adelson, LineClipping) {
    const ClipWindow w{0, 10, 0, 10};
    Segment s = clipLine(-5, 5, 15, 5, w);
    ASSERT_TRUE(s.visible);
    EXPECT_DOUBLE_EQ(s.x0, 0.0);
    EXPECT_DOUBLE_EQ(s.x1, 10.0);
    EXPECT_FALSE(clipLine(-5, 11, 15, 12, w).visible);
    s = clipLine(2, 3, 4, 5, w);
    EXPECT_EQ(s, (Segment{2, 3, 4, 5, true}));
    // stereo: the left eye's segment is inside, the right eye's misses the window
    Segment l, r;
    clipLineStereo({2, 12, 3, 4, 14, 5}, w, l, r);
    EXPECT_EQ(l, (Segment{2, 3, 4, 5, true}));
    EXPECT_FALSE(r.visible);
}

double area(const std::vector<double>& x, const std::vector<double>& y) {
    double a = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const std::size_t j = (i + 1) % x.size();
        a += x[i] * y[j] - x[j] * y[i];
    }
    return std::abs(a) * 0.5;
}

TEST(Adelson, PolygonClipping) {
    const ClipWindow w{0, 10, 0, 10};
    std::vector<double> ox, oy;
    const std::vector<double> ix = {2, 8, 8, 2}, iy = {2, 2, 8, 8};
    clipPolygon(ix, iy, w, ox, oy);
    // Inside: each edge emits its end vertex, so the output is the input rotated by one.
    EXPECT_EQ(ox, (std::vector<double>{8, 8, 2, 2}));
    EXPECT_EQ(oy, (std::vector<double>{2, 8, 8, 2}));
    const std::vector<double> bx = {-5, 15, 15, -5}, by = {-5, -5, 15, 15};
    clipPolygon(bx, by, w, ox, oy);
    EXPECT_NEAR(area(ox, oy), 100.0, 1e-9);
    const std::vector<double> hx = {5, 15, 15, 5}, hy = {-5, -5, 5, 5};  // a quarter overlaps
    clipPolygon(hx, hy, w, ox, oy);
    EXPECT_NEAR(area(ox, oy), 25.0, 1e-9);
    const std::vector<double> tx = {-1, 5, 11}, ty = {-1, 12, -1};  // triangle over the window
    clipPolygon(tx, ty, w, ox, oy);
    EXPECT_GT(area(ox, oy), 50.0);
    EXPECT_LT(area(ox, oy), 100.0);
}

TEST(Adelson, BspSplitsCrossingPolygonsAndPaintsThemRight) {
    // Two quads crossing each other (an X seen from above): one must be split, and painting
    // the tree back to front must give what the z-buffer gives.
    auto quad = [](Vec3 a, Vec3 b, Vec3 c, Vec3 d, std::uint32_t id) {
        Polygon3 p;
        p.v = {a, b, c, d};
        p.color.assign(4, Rgb{0.5f, 0.5f, 0.5f});
        p.id = id;
        return p;
    };
    std::vector<Polygon3> polys = {quad({-1, -1, 2}, {1, -1, 4}, {1, 1, 4}, {-1, 1, 2}, 0),
                                   quad({-1, -1, 4}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 4}, 1)};
    const BspTree tree = buildBsp(polys);
    EXPECT_EQ(tree.polygons.size(), 3u);
    StereoCamera cam;
    cam.width = 200, cam.height = 150, cam.scale = 60;
    Frame l1(200, 150), r1(200, 150), l2(200, 150), r2(200, 150);
    renderBspMono(tree, -1, cam, l1);
    renderBspMono(tree, +1, cam, r1);
    renderBspZBuffer(tree, cam, l2, r2);
    EXPECT_EQ(r1.pixels, r2.pixels);
    std::size_t diff = 0, drawn = 0;
    for (std::size_t i = 0; i < l1.pixels.size(); ++i)
        diff += l1.pixels[i] != l2.pixels[i], drawn += l1.pixels[i] != 0;
    EXPECT_GT(drawn, 1000u);
    EXPECT_LE(diff, drawn / 100);  // only along the line where the quads meet at equal depth
}

// ---- scenes and measures --------------------------------------------------------------------------

TEST(Adelson, VillageHasAbout1100Polygons) {
    EXPECT_EQ(makeVillage(8).size(), 1136u);
    EXPECT_EQ(makeVillage(1).size(), 156u);
    for (const Polygon3& p : makeVillage(8)) {
        for (const Vec3& v : p.v) EXPECT_GT(v.z, 0.0);
    }
}

TEST(Adelson, SavingsMeasures) {
    const Savings s = savingsFrom(2.0, 1.5);
    EXPECT_DOUBLE_EQ(s.measureI, 0.25);
    EXPECT_DOUBLE_EQ(s.measureII, 0.5);
    EXPECT_DOUBLE_EQ(s.measureIII, 2.0 / 1.5);
    const Savings best = savingsFrom(2.0, 1.0);
    EXPECT_DOUBLE_EQ(best.measureI, 0.5);
    EXPECT_DOUBLE_EQ(best.measureII, 1.0);
    EXPECT_DOUBLE_EQ(best.measureIII, 2.0);
}

}  // namespace
}  // namespace mvr::adelson

// ---- the village as an mvr::Scene (`mvr render --scene village`) ----------------------------
#include "mvr/adelson/village_scene.h"

namespace mvr::adelson {
namespace {

TEST(VillageScene, IsAValidRightHandedSceneInFrontOfTheViewer) {
    const Scene s = makeVillageScene();
    ASSERT_TRUE(validateScene(s)) << validateScene(s).message();
    // Every polygon fanned: 1136 polygons of 4+ vertices give more triangles than polygons.
    std::size_t polys = 0, tris = 0;
    for (const Polygon3& p : makeVillage()) {
        ++polys;
        tris += p.v.size() - 2;
    }
    EXPECT_EQ(polys, 1136u);
    EXPECT_EQ(s.triangleCount(), tris);
    const Bounds b = s.bounds();
    EXPECT_LT(b.max.z, 0.0f);  // all of it down -z, in front of the viewer at the origin
    ASSERT_TRUE(s.viewpoint);
    EXPECT_EQ(s.viewpoint->position, glm::vec3(0.0f));
    // Front faces wind counter-clockwise seen from the viewer: the ground faces up.
    int upward = 0;
    for (const Mesh& m : s.meshes)
        for (const glm::vec3& n : m.normals) upward += n.y > 0.99f;
    EXPECT_GT(upward, 0);
}

}  // namespace
}  // namespace mvr::adelson
