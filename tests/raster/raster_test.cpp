// The soft backend's reference rasterizer ("multipass"): coverage (fill rule, watertightness,
// analytic counts), depth, near-plane clipping, culling, bad input, and the SIMD kernels.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <new>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "cpu.h"
#include "frame.h"
#include "mvr/raster/soft_backend.h"
#include "pipeline.h"
#include "thread_pool.h"
#include "test_scenes.h"
#include "wireframe.h"

namespace mvr::raster {
namespace {

// A task that throws (std::bad_alloc when a frame does not fit) must not terminate the process
// from a worker thread: run() rethrows it on the caller's thread, the other tasks stop being
// claimed, and the pool serves the next run() as before.
TEST(ThreadPool, ATaskThatThrowsIsRethrownByRun) {
    for (int workers : {1, 2}) {
        detail::ThreadPool pool(workers);
        std::atomic<int> ran{0};
        EXPECT_THROW(pool.run(1000,
                              [&](int task, int) {
                                  ++ran;
                                  if (task == 3) throw std::bad_alloc();
                              }),
                     std::bad_alloc);
        if (workers == 1) {
            EXPECT_EQ(ran.load(), 4);  // tasks 0..3, then no more claimed
        }
        std::atomic<int> sum{0};
        pool.run(100, [&](int task, int) { sum += task; });
        EXPECT_EQ(sum.load(), 4950) << workers;
    }
}

using detail::kSubpixel;

/// Counts how often each pixel is written (the test hook into the coverage walk).
struct CountSink {
    std::vector<int>* counts;
    int width;
    void operator()(int x, int y, float, float, float) const {
        ++(*counts)[std::size_t(y) * width + x];
    }
};

/// Rasterizes a triangle given in window pixels (GL: y up) through the same setup the renderer
/// uses (snap to 1/256 px, shared y setup, top-left rule) and adds 1 per covered pixel.
void coverTriangle(glm::vec2 a, glm::vec2 b, glm::vec2 c, int width, int height,
                   std::vector<int>& counts) {
    auto snap = [](float v) { return std::int32_t(std::lrintf(v * kSubpixel)); };
    detail::YSetup ys;
    detail::setupY(ys, snap(a.y), snap(b.y), snap(c.y), 0, height - 1);
    const std::int32_t x[3] = {snap(a.x), snap(b.x), snap(c.x)};
    CountSink sink{&counts, width};
    detail::rasterTriangle(ys, x, width, sink);
}

TEST(Coverage, TwoTrianglesSharingAnEdgeCoverEachPixelOnce) {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> u(-8.0f, 72.0f);
    const int w = 64, h = 64;
    int tested = 0;
    for (int iter = 0; iter < 300; ++iter) {
        // A quad split along one diagonal, in either winding, with vertices that are sometimes
        // snapped onto pixel centers / pixel edges to provoke ties.
        glm::vec2 p[4];
        for (auto& v : p) {
            v = {u(rng), u(rng)};
            if (iter % 3 == 0) v = glm::floor(v) + 0.5f;
            if (iter % 3 == 1) v = glm::floor(v);
        }
        // The triangles must not overlap: p1 and p3 strictly on opposite sides of p0–p2
        // (decided on the snapped positions, as the rasterizer sees them).
        auto sn = [](glm::vec2 v) {
            return glm::i64vec2(std::lrintf(v.x * 256), std::lrintf(v.y * 256));
        };
        auto side = [&](glm::vec2 q) {
            const auto a = sn(p[0]), b = sn(p[2]), c = sn(q);
            return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        };
        const std::int64_t s1 = side(p[1]), s3 = side(p[3]);
        if (!((s1 > 0 && s3 < 0) || (s1 < 0 && s3 > 0))) continue;
        ++tested;
        std::vector<int> both(w * h, 0), first(w * h, 0);
        coverTriangle(p[0], p[1], p[2], w, h, both);
        coverTriangle(p[0], p[2], p[3], w, h, both);
        for (int i = 0; i < w * h; ++i)
            ASSERT_LE(both[i], 1) << "iteration " << iter << " pixel " << i;
        // Reversing the winding must not change coverage.
        coverTriangle(p[0], p[2], p[1], w, h, first);
        coverTriangle(p[0], p[3], p[2], w, h, first);
        EXPECT_EQ(both, first) << "iteration " << iter;
    }
    EXPECT_GT(tested, 100);
}

TEST(Coverage, FanAroundAVertexCoversEachPixelOnce) {
    // Eight triangles around a pixel center: the shared vertex and every spoke lie on ties.
    const int w = 32, h = 32;
    std::vector<int> counts(w * h, 0);
    const glm::vec2 c(16.5f, 16.5f);
    for (int i = 0; i < 8; ++i) {
        const float a0 = float(i) * 0.785398163f, a1 = float(i + 1) * 0.785398163f;
        coverTriangle(c, c + 12.0f * glm::vec2(std::cos(a0), std::sin(a0)),
                      c + 12.0f * glm::vec2(std::cos(a1), std::sin(a1)), w, h, counts);
    }
    for (int v : counts) ASSERT_LE(v, 1);
    EXPECT_EQ(counts[16 * w + 16], 1) << "the center pixel is covered by exactly one triangle";
}

TEST(Coverage, FullScreenQuadCoversEveryPixelExactlyOnce) {
    for (auto [w, h] : {std::pair{1, 1}, {7, 5}, {64, 48}, {333, 17}}) {
        std::vector<int> counts(std::size_t(w) * h, 0);
        coverTriangle({0, 0}, {float(w), 0}, {float(w), float(h)}, w, h, counts);
        coverTriangle({0, 0}, {float(w), float(h)}, {0, float(h)}, w, h, counts);
        for (int v : counts) ASSERT_EQ(v, 1) << w << "x" << h;
    }
}

TEST(Coverage, MatchesAnalyticPixelCount) {
    // Right triangle with legs on pixel boundaries: (0,0), (W,0), (0,H). A pixel center
    // (x+.5, y+.5) is inside iff (x+.5)/W + (y+.5)/H < 1; on the hypotenuse (= 1) it is covered
    // only if that edge is top-left: the hypotenuse runs from (W,0) to (0,H), up-left, so it is a
    // right edge and excludes ties. Legs: left leg (x = 0) and bottom leg (y = 0) carry no centers.
    const int W = 40, H = 24;
    std::vector<int> counts(W * H, 0);
    coverTriangle({0, 0}, {float(W), 0}, {0, float(H)}, W, H, counts);
    long expected = 0;
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            // Exact in integers: (2x+1)·H + (2y+1)·W < 2·W·H.
            const long lhs = long(2 * x + 1) * H + long(2 * y + 1) * W;
            const bool inside = lhs < 2L * W * H;
            expected += inside;
            ASSERT_EQ(counts[y * W + x], inside ? 1 : 0) << "pixel " << x << "," << y;
        }
    }
    EXPECT_GT(expected, W * H / 2 - W - H);

    // A generic triangle (no ties): compare with a point-in-triangle test in double.
    const glm::dvec2 a(3.3, 2.7), b(57.1, 11.9), c(21.7, 45.3);  // multiples of 1/256? no: snapped
    auto snapd = [](double v) { return std::nearbyint(v * 256.0) / 256.0; };
    const glm::dvec2 sa(snapd(a.x), snapd(a.y)), sb(snapd(b.x), snapd(b.y)),
        sc(snapd(c.x), snapd(c.y));
    std::vector<int> counts2(64 * 64, 0);
    coverTriangle(glm::vec2(a), glm::vec2(b), glm::vec2(c), 64, 64, counts2);
    auto edge = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {
        return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    };
    long count = 0, want = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const glm::dvec2 pc(x + 0.5, y + 0.5);
            const bool in = edge(sa, sb, pc) > 0 && edge(sb, sc, pc) > 0 && edge(sc, sa, pc) > 0;
            want += in;
            count += counts2[y * 64 + x];
            EXPECT_EQ(counts2[y * 64 + x], in ? 1 : 0) << x << "," << y;
        }
    }
    EXPECT_EQ(count, want);
    // Area check: the count is close to the analytic area.
    const double area = std::abs(edge(sa, sb, sc)) / 2.0;
    EXPECT_NEAR(double(count), area, area * 0.05);
}

// A large triangle of which only a 2x2 corner lies in the image (or in the band): its clamped
// box is "small", but its edge values are not — the int32 path overflowed there (UBSan:
// 40048 * 69574). Coverage against a point-in-triangle test in double on the snapped vertices.
TEST(Coverage, ALargeTriangleSeenOnlyAtACornerIsCoveredExactly) {
    const int W = 64, H = 48;
    auto snapd = [](double v) { return std::nearbyint(v * 256.0) / 256.0; };
    auto edge = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {
        return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    };
    const std::vector<std::array<glm::vec2, 3>> triangles = {
        {glm::vec2(-20000.3f, -20000.7f), {2.2f, 1.1f}, {1.1f, 2.2f}},    // bottom-left corner
        {glm::vec2(20060.3f, 20040.7f), {62.1f, 46.95f}, {62.95f, 46.1f}},  // top-right corner
        {glm::vec2(-9000.4f, 47.3f), {1.7f, 46.2f}, {1.9f, 47.9f}},      // left edge, top rows
        {glm::vec2(30.2f, -30000.6f), {31.9f, 1.2f}, {30.7f, 1.8f}},      // bottom edge
    };
    for (const auto& t : triangles) {
        std::vector<int> counts(std::size_t(W) * H, 0);
        coverTriangle(t[0], t[1], t[2], W, H, counts);
        glm::dvec2 v[3];
        for (int i = 0; i < 3; ++i) v[i] = {snapd(t[i].x), snapd(t[i].y)};
        const double sign = edge(v[0], v[1], v[2]) > 0 ? 1.0 : -1.0;
        long want = 0;
        for (int y = 0; y < H; ++y) {
            for (int x = 0; x < W; ++x) {
                const glm::dvec2 pc(x + 0.5, y + 0.5);
                const bool in = sign * edge(v[0], v[1], pc) > 0 && sign * edge(v[1], v[2], pc) > 0 &&
                                sign * edge(v[2], v[0], pc) > 0;
                want += in;
                ASSERT_EQ(counts[std::size_t(y) * W + x], in ? 1 : 0)
                    << "pixel " << x << "," << y << " of the triangle at " << t[1].x << ","
                    << t[1].y;
            }
        }
        EXPECT_GE(want, 1) << "the triangle at " << t[1].x << "," << t[1].y << " covers no centre";
    }
}

// The same through the soft backend (its SIMD setup kernels and both methods): a triangle from
// far outside the screen (inside the guard band) whose tip covers the bottom-left 2x2 corner of
// a 1024x768 view; the three pixel centres it holds (x + y < 3.3 for the tip (2.2, 1.1) - (1.1,
// 2.2)... computed below in double) are drawn, nothing else.
TEST(Render, ALargeTriangleSeenOnlyAtACornerIsDrawnExactly) {
    const int W = 1024, H = 768;
    auto ndcX = [&](double px) { return float(px / W * 2.0 - 1.0); };
    auto ndcY = [&](double py) { return float(py / H * 2.0 - 1.0); };
    const glm::dvec2 win[3] = {{-20000.3, -15000.7}, {2.2, 1.1}, {1.1, 2.2}};
    Scene scene = test::triangleScene({glm::vec3(ndcX(win[0].x), ndcY(win[0].y), 0.0f),
                                       glm::vec3(ndcX(win[1].x), ndcY(win[1].y), 0.0f),
                                       glm::vec3(ndcX(win[2].x), ndcY(win[2].y), 0.0f)});
    RenderSettings s;
    s.width = W, s.height = H;
    s.clearColor = {1, 0, 0};
    auto edge = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {
        return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    };
    auto backend = makeSoftBackend();
    for (const char* method : {"multipass", "unified"}) {
        for (int views : {1, 2}) {
            auto out = backend->render(scene, test::identityRig(views), s, method);
            ASSERT_TRUE(out) << out.status().message();
            for (int v = 0; v < views; ++v) {
                int drawn = 0, want = 0;
                for (int y = 0; y < 4; ++y) {      // GL window rows from the bottom
                    for (int x = 0; x < 4; ++x) {
                        const glm::dvec2 pc(x + 0.5, y + 0.5);
                        const double o = edge(win[0], win[1], win[2]) > 0 ? 1.0 : -1.0;
                        const bool in = o * edge(win[0], win[1], pc) > 0 &&
                                        o * edge(win[1], win[2], pc) > 0 &&
                                        o * edge(win[2], win[0], pc) > 0;
                        const bool isDrawn =
                            out->color[std::size_t(v)].at(x, H - 1 - y) != Rgba8{255, 0, 0, 255};
                        EXPECT_EQ(isDrawn, in) << method << " " << views << " views, pixel " << x
                                               << "," << y;
                        drawn += isDrawn, want += in;
                    }
                }
                EXPECT_EQ(want, 3) << "the test's own triangle";
                EXPECT_EQ(drawn, 3) << method;
            }
        }
    }
}

// ---- whole renders -------------------------------------------------------------------------

TEST(Render, FullScreenQuadCoversEveryPixel) {
    Scene scene = test::quadScene({-1, -1, 0}, {1, 1, 0});
    const Rig rig = test::identityRig(1);
    RenderSettings s;
    s.width = 37, s.height = 23;
    s.clearColor = {1, 0, 0};
    auto backend = makeSoftBackend();
    auto out = backend->render(scene, rig, s, "multipass");
    ASSERT_TRUE(out) << out.status().message();
    ASSERT_EQ(out->color.size(), 1u);
    for (int y = 0; y < s.height; ++y) {
        for (int x = 0; x < s.width; ++x) {
            ASSERT_NE(out->color[0].at(x, y), (Rgba8{255, 0, 0, 255})) << x << "," << y;
            ASSERT_FLOAT_EQ(out->depth[0].at(x, y), 0.5f);
            ASSERT_EQ(out->color[0].at(x, y).a, 255);
        }
    }
}

TEST(Render, NearerSurfaceWinsInEitherOrder) {
    for (bool nearFirst : {true, false}) {
        Scene scene;
        scene.lights = defaultLights();
        Mesh far = test::quadMesh({-1, -1, 0.5f}, {1, 1, 0.5f});
        Mesh near = test::quadMesh({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, -0.5f});
        scene.meshes = nearFirst ? std::vector<Mesh>{near, far} : std::vector<Mesh>{far, near};
        Instance a, b;
        a.mesh = 0, b.mesh = 1;
        a.material.albedo = nearFirst ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        b.material.albedo = nearFirst ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        scene.instances = {a, b};
        RenderSettings s;
        s.width = 40, s.height = 40;
        s.shading = Shading::Flat;
        auto out = makeSoftBackend()->render(scene, test::identityRig(1), s, "multipass");
        ASSERT_TRUE(out) << out.status().message();
        const Rgba8 center = out->color[0].at(20, 20), corner = out->color[0].at(2, 2);
        EXPECT_GT(center.g, 0) << "near (green) quad visible in the middle";
        EXPECT_EQ(center.r, 0);
        EXPECT_GT(corner.r, 0) << "far (red) quad visible at the corner";
        EXPECT_FLOAT_EQ(out->depth[0].at(20, 20), 0.25f);
        EXPECT_FLOAT_EQ(out->depth[0].at(2, 2), 0.75f);
    }
}

TEST(Render, RowZeroIsTheTop) {
    // A quad over the upper half of NDC (y > 0) must appear in the image's top rows.
    Scene scene = test::quadScene({-1, 0, 0}, {1, 1, 0});
    RenderSettings s;
    s.width = 16, s.height = 16;
    auto out = makeSoftBackend()->render(scene, test::identityRig(1), s, "multipass");
    ASSERT_TRUE(out);
    EXPECT_LT(out->depth[0].at(5, 0), 1.0f);
    EXPECT_EQ(out->depth[0].at(5, 15), 1.0f);
    EXPECT_LT(out->depth[0].at(5, 7), 1.0f);
    EXPECT_EQ(out->depth[0].at(5, 8), 1.0f);
}

TEST(Render, NearPlaneClipping) {
    // A ground plane from behind the camera to far in front: it must fill exactly the rows below
    // the horizon (plus nothing above), with depths in [0, 1] and no wrap-around from behind.
    Scene scene;
    scene.lights = defaultLights();
    Mesh ground;
    ground.positions = {{-50, -1, 5}, {50, -1, 5}, {50, -1, -60}, {-50, -1, -60}};
    ground.normals.assign(4, {0, 1, 0});
    ground.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes = {ground};
    scene.instances = {Instance{}};
    Camera cam;
    cam.position = {0, 0, 0};
    cam.target = {0, 0, -1};
    cam.near = 0.5f, cam.far = 100.0f, cam.aspect = 1.0f, cam.fovYDegrees = 60.0f;
    auto rig = makeListRig(cam, {View{cam.viewFromWorld(), cam.clipFromView(), {}, {}}});
    ASSERT_TRUE(rig);
    RenderSettings s;
    s.width = 64, s.height = 64;
    auto out = makeSoftBackend()->render(scene, *rig, s, "multipass");
    ASSERT_TRUE(out) << out.status().message();
    const DepthImage& d = out->depth[0];
    // The plane y = −1 at distance 60 projects to ndc y = −(1/60)/tan(30°) ≈ −0.029: rows below
    // image row ~33 are covered, rows above 31 are not.
    for (int x = 0; x < s.width; ++x) {
        for (int y = 0; y < 31; ++y) ASSERT_EQ(d.at(x, y), 1.0f) << x << "," << y;
        for (int y = 34; y < s.height; ++y) {
            ASSERT_LT(d.at(x, y), 1.0f) << x << "," << y;
            ASSERT_GE(d.at(x, y), 0.0f);
        }
    }
    // Nearer rows (image bottom) have smaller depth.
    EXPECT_LT(d.at(32, 63), d.at(32, 40));
}

TEST(Render, TriangleBehindTheCameraDrawsNothing) {
    Scene scene = test::triangleScene({{-1, -1, 3}, {1, -1, 3}, {0, 1, 3}});
    Camera cam;
    cam.position = {0, 0, 0};
    cam.target = {0, 0, -1};
    auto rig = makeListRig(cam, {View{cam.viewFromWorld(), cam.clipFromView(), {}, {}}});
    ASSERT_TRUE(rig);
    RenderSettings s;
    s.width = 32, s.height = 32;
    auto out = makeSoftBackend()->render(scene, *rig, s, "multipass");
    ASSERT_TRUE(out);
    for (float v : out->depth[0].depth) ASSERT_EQ(v, 1.0f);
}

TEST(Render, BackFaceCulling) {
    // Counter-clockwise (front) and clockwise (back) triangles side by side.
    Scene scene = test::triangleScene({{-0.9f, -0.5f, 0},
                                       {-0.1f, -0.5f, 0},
                                       {-0.5f, 0.5f, 0},
                                       {0.1f, -0.5f, 0},
                                       {0.5f, 0.5f, 0},
                                       {0.9f, -0.5f, 0}});
    RenderSettings s;
    s.width = 40, s.height = 20;
    for (bool cull : {false, true}) {
        s.cullBackFaces = cull;
        auto out = makeSoftBackend()->render(scene, test::identityRig(1), s, "multipass");
        ASSERT_TRUE(out);
        EXPECT_LT(out->depth[0].at(10, 12), 1.0f) << "front face always drawn";
        EXPECT_EQ(out->depth[0].at(30, 12) < 1.0f, !cull) << "back face drawn iff not culling";
    }
}

TEST(Render, BadInputGivesAStatus) {
    auto backend = makeSoftBackend();
    Scene scene = test::quadScene({-1, -1, 0}, {1, 1, 0});
    RenderSettings s;
    s.width = 0;
    auto r = backend->render(scene, test::identityRig(1), s, "multipass");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Usage);
    s.width = 16;
    Rig big = test::identityRig(1);
    big.views.assign(kMaxViews + 1, big.views[0]);
    r = backend->render(scene, big, s, "multipass");
    ASSERT_FALSE(r);
    EXPECT_NE(r.status().message().find("views"), std::string::npos) << r.status().message();
    Rig none = test::identityRig(1);
    none.views.clear();
    EXPECT_FALSE(backend->render(scene, none, s, "multipass"));
    EXPECT_EQ(backend->render(scene, test::identityRig(1), s, "nonsense").status().code(),
              ErrorCode::Usage);
    Scene empty;
    EXPECT_FALSE(backend->render(empty, test::identityRig(1), s, "multipass"));
    // Framebuffers beyond any reasonable memory: a Status, not std::bad_alloc.
    RenderSettings huge;
    huge.width = 16384, huge.height = 16384;
    r = backend->render(scene, test::identityRig(8), huge, "unified");
    ASSERT_FALSE(r);
    EXPECT_NE(r.status().message().find("GiB"), std::string::npos) << r.status().message();
    Rig nan = test::identityRig(1);
    nan.views[0].clipFromView[0][0] = std::nanf("");
    EXPECT_FALSE(backend->render(scene, nan, s, "multipass"));
}

// ---- wireframe ---------------------------------------------------------------------------------

TEST(Wireframe, StereoLiangBarskyEqualsClippingEachViewOnItsOwn) {
    // adelson1991: the bottom/top borders depend only on y, which the views share; clipping them
    // once and then left/right per view must give each view's own 4-border result exactly.
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-200.0f, 300.0f);
    int clipped = 0, rejected = 0;
    for (int i = 0; i < 20000; ++i) {
        const float y0 = u(rng), y1 = i % 50 == 0 ? y0 : u(rng);
        float sy0 = 0.0f, sy1 = 1.0f;
        const bool yOk = detail::liangBarskyAxis(y0, y1 - y0, 0.0f, 100.0f, sy0, sy1);
        for (int view = 0; view < 4; ++view) {
            const float x0 = u(rng), x1 = i % 70 == 0 ? x0 : u(rng);
            float t0 = 0.0f, t1 = 1.0f;  // this view on its own: left, right, bottom, top
            const bool own = detail::liangBarskyAxis(x0, x1 - x0, 0.0f, 160.0f, t0, t1) &&
                             detail::liangBarskyAxis(y0, y1 - y0, 0.0f, 100.0f, t0, t1);
            float s0 = sy0, s1 = sy1;  // shared bottom/top, then this view's left/right
            const bool shared = yOk && detail::liangBarskyAxis(x0, x1 - x0, 0.0f, 160.0f, s0, s1);
            ASSERT_EQ(own, shared) << i;
            if (own) {
                ASSERT_EQ(std::memcmp(&t0, &s0, 4), 0) << i;
                ASSERT_EQ(std::memcmp(&t1, &s1, 4), 0) << i;
                clipped += t0 > 0.0f || t1 < 1.0f;
            } else {
                ++rejected;
            }
        }
    }
    EXPECT_GT(clipped, 1000);
    EXPECT_GT(rejected, 1000);
}

TEST(Wireframe, DrawsTheEdgesOnly) {
    Scene scene = test::triangleScene({{-0.8f, -0.8f, 0}, {0.8f, -0.8f, 0}, {0.0f, 0.8f, 0}});
    RenderSettings s;
    s.width = 100, s.height = 100;
    s.wireframe = true;
    auto out = makeSoftBackend()->render(scene, test::identityRig(1), s, "multipass");
    ASSERT_TRUE(out);
    long drawn = 0;
    for (float z : out->depth[0].depth) drawn += z < 1.0f;
    // Perimeter ≈ 80 + 2·89 px; one pixel per column or row of each edge.
    EXPECT_GT(drawn, 150);
    EXPECT_LT(drawn, 300);
    EXPECT_EQ(out->depth[0].at(50, 50), 1.0f) << "the interior stays empty";
    // The bottom edge lies on window y = 10 (± rounding): image row 89 or 90.
    EXPECT_LT(std::min(out->depth[0].at(50, 89), out->depth[0].at(50, 90)), 1.0f)
        << "the bottom edge";
}

// ---- SIMD kernels ----------------------------------------------------------------------------

/// The SIMD kernel tables this build has and this CPU runs (each is checked against the scalar
/// reference).
std::vector<const detail::Kernels*> simdKernels() {
    std::vector<const detail::Kernels*> out;
    const SimdPath best = detail::bestSupportedSimd();
    if (detail::avx2Kernels() && best != SimdPath::Scalar) out.push_back(detail::avx2Kernels());
    if (detail::avx512Kernels() && best == SimdPath::Avx512) out.push_back(detail::avx512Kernels());
    return out;
}

TEST(Kernels, SimdPathsEqualScalar) {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    const std::size_t n = 1000 + 13;
    std::vector<float> x(n), y(n), z(n), w(n);
    for (std::size_t i = 0; i < n; ++i) {
        w[i] = i % 17 == 0 ? -u(rng) : std::abs(u(rng)) + (i % 5 == 0 ? 0.0f : 0.01f);
        x[i] = u(rng) * (i % 7 == 0 ? 100.0f : 1.0f), y[i] = u(rng) * (i % 11 == 0 ? 100.0f : 1.0f);
        z[i] = u(rng);
    }
    struct Out {
        std::vector<std::uint8_t> cy, cx;
        std::vector<float> q, zw;
        std::vector<std::int32_t> sy, sx;
    };
    auto run = [&](const detail::Kernels& k) {
        Out o{std::vector<std::uint8_t>(n), std::vector<std::uint8_t>(n),
              std::vector<float>(n),        std::vector<float>(n),
              std::vector<std::int32_t>(n), std::vector<std::int32_t>(n)};
        k.projectYZW(y.data(), z.data(), w.data(), n, 768.0f, o.cy.data(), o.q.data(), o.sy.data(),
                     o.zw.data());
        k.projectX(x.data(), w.data(), o.q.data(), n, 1024.0f, o.cx.data(), o.sx.data());
        return o;
    };
    const Out ref = run(detail::scalarKernels());
    for (const detail::Kernels* k : simdKernels()) {
        const Out o = run(*k);
        for (std::size_t i = 0; i < n; ++i) {
            ASSERT_EQ(o.cy[i], ref.cy[i]) << i;
            ASSERT_EQ(o.cx[i], ref.cx[i]) << i;
            if (ref.cy[i] & detail::kClipYZW) continue;  // unprojectable: values unused
            ASSERT_EQ(o.sy[i], ref.sy[i]) << i;
            ASSERT_EQ(std::memcmp(&o.q[i], &ref.q[i], 4), 0) << i;
            ASSERT_EQ(std::memcmp(&o.zw[i], &ref.zw[i], 4), 0) << i;
            if (ref.cx[i] & detail::kClipX) continue;
            ASSERT_EQ(o.sx[i], ref.sx[i]) << i;
        }
    }
}

TEST(Kernels, RowClipXSimdEqualsScalar) {
    // A long row's guard-band bits from its outermost shears: centre x within a few w of the
    // guard band's edges (±64 w), shears that move it across them, w of both signs and near 0,
    // the convergence below and above w; every byte of any[] (pre-set bits kept) against the
    // scalar reference, and the reference against outcodeX of every view between the shears.
    std::mt19937 rng(64);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::size_t n = 1000 + 9;
    std::vector<float> cx(n), w(n);
    std::vector<std::uint8_t> start(n);
    for (std::size_t i = 0; i < n; ++i) {
        w[i] = i % 13 == 0 ? -2.0f * std::abs(u(rng)) : 0.001f + 4.0f * std::abs(u(rng));
        const float edge = (i % 2 == 0 ? 64.0f : -64.0f) * w[i];
        cx[i] = i % 3 == 0 ? u(rng) * w[i] : edge + 3.0f * u(rng);
        start[i] = std::uint8_t(rng() % 4 == 0 ? detail::kClipLeft : 0);
    }
    const float lo = -0.8f, hi = 1.3f, convergence = 1.7f;
    std::vector<std::uint8_t> ref = start;
    detail::scalarKernels().rowClipX(cx.data(), w.data(), n, lo, hi, convergence, ref.data());
    long clipped = 0;
    for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t views = start[i];
        for (int k = 0; k <= 20; ++k) {
            const float s = k == 20 ? hi : lo + (hi - lo) * float(k) / 20.0f;
            views |= detail::outcodeX(cx[i] + s * (w[i] - convergence), w[i]) & detail::kClipX;
        }
        ASSERT_EQ(ref[i], views) << i;
        clipped += (ref[i] & ~start[i]) != 0;
    }
    EXPECT_GT(clipped, 100) << "the vertices must cross the guard band";
    for (const detail::Kernels* k : simdKernels()) {
        std::vector<std::uint8_t> got = start;
        k->rowClipX(cx.data(), w.data(), n, lo, hi, convergence, got.data());
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], ref[i]) << i;
    }
}

TEST(Kernels, RowSnapXEqualsProjectXOfEveryView) {
    // A sheared row's interleaved snapped x (the vertex stage's sxv) for rows of 1..8 views:
    // centre x inside the view and near the guard band's edges, w of both signs and near 0, a
    // vertex count that leaves a tail; the scalar reference against shearClip + projectX of each
    // view (what the vertex stage stored before), and every SIMD table's kernel, where it has
    // one, against the reference bit for bit.
    std::mt19937 rng(65);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::size_t n = 1000 + 11;
    std::vector<float> cx(n), w(n), q(n);
    for (std::size_t i = 0; i < n; ++i) {
        w[i] = i % 17 == 0 ? -2.0f * std::abs(u(rng)) : 0.001f + 4.0f * std::abs(u(rng));
        q[i] = 1.0f / w[i];
        const float edge = (i % 2 == 0 ? 64.0f : -64.0f) * w[i];
        cx[i] = i % 3 == 0 ? edge + 3.0f * u(rng) : u(rng) * w[i];
    }
    const float convergence = 1.7f, width = 1024.0f;
    const detail::Kernels& scalar = detail::scalarKernels();
    ASSERT_NE(scalar.rowSnapX, nullptr);
    int tested = 0;
    for (int nv = 1; nv <= detail::kLaneBlock; ++nv) {
        std::vector<float> rowShears(static_cast<std::size_t>(nv));
        for (int k = 0; k < nv; ++k) rowShears[std::size_t(k)] = -0.9f + 0.31f * float(k);
        std::vector<std::int32_t> ref(n * std::size_t(nv), -1);
        scalar.rowSnapX(cx.data(), w.data(), q.data(), n, rowShears.data(), nv, convergence, width,
                        ref.data());
        long zeros = 0;
        for (int k = 0; k < nv; ++k) {
            std::vector<float> x(n);
            for (std::size_t i = 0; i < n; ++i)
                x[i] = detail::shearClip(cx[i], rowShears[std::size_t(k)], w[i], convergence);
            std::vector<std::uint8_t> code(n);
            std::vector<std::int32_t> sx(n);
            scalar.projectX(x.data(), w.data(), q.data(), n, width, code.data(), sx.data());
            for (std::size_t i = 0; i < n; ++i) {
                ASSERT_EQ(ref[i * std::size_t(nv) + std::size_t(k)], sx[i]) << nv << " " << k;
                zeros += (code[i] & detail::kClipX) != 0;
            }
        }
        EXPECT_GT(zeros, 100) << "some vertices must lie past the guard band";
        for (const detail::Kernels* kt : simdKernels()) {
            if (!kt->rowSnapX) continue;
            ++tested;
            std::vector<std::int32_t> got(n * std::size_t(nv), -1);
            kt->rowSnapX(cx.data(), w.data(), q.data(), n, rowShears.data(), nv, convergence, width,
                         got.data());
            for (std::size_t i = 0; i < got.size(); ++i)
                ASSERT_EQ(got[i], ref[i]) << nv << " " << i;
        }
    }
    if (detail::bestSupportedSimd() == SimdPath::Avx512) {
        EXPECT_GT(tested, 0) << "AVX-512 has one";
    }
}

TEST(Kernels, ShadeVerticesSimdEqualsScalar) {
    // Random positions and normals (some zero, some facing away from every light), 1..3 lights,
    // a rotated/scaled instance, several shininess values: every output float bit for bit.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    const std::size_t n = 1000 + 11;
    std::vector<glm::vec3> pos(n), nrm(n);
    for (std::size_t i = 0; i < n; ++i) {
        pos[i] = {u(rng), u(rng), u(rng)};
        nrm[i] = i % 97 == 0 ? glm::vec3(0.0f) : glm::vec3(u(rng), u(rng), u(rng));
    }
    pos[5] = glm::vec3(0.0f, 0.0f, 3.0f);  // at the eye: v is NaN
    const DirectionalLight lights[3] = {
        {glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f)), {1.0f, 0.9f, 0.8f}},
        {glm::normalize(glm::vec3(-0.6f, 0.2f, 0.7f)), {0.3f, 0.4f, 0.6f}},
        {glm::normalize(glm::vec3(0.1f, -0.9f, -0.3f)), {0.5f, 0.5f, 0.5f}}};
    const glm::mat4 world =
        glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), {0.5f, -1.0f, 0.2f}), 0.7f,
                               glm::vec3(0.2f, 1.0f, 0.3f)),
                   glm::vec3(1.5f, 0.7f, 1.1f));
    const glm::mat3 normalFrom = glm::transpose(glm::inverse(glm::mat3(world)));
    for (int lightCount = 1; lightCount <= 3; ++lightCount) {
        for (float shininess : {1.0f, 32.0f, 77.5f, 0.5f, 1000.0f, 0.0f}) {
            ShadingContext ctx{std::span<const DirectionalLight>(lights, std::size_t(lightCount)),
                               glm::vec3(0.12f), glm::vec3(0.0f, 0.0f, 3.0f)};
            Material m{{0.8f, 0.6f, 0.4f}, 0.25f, shininess};
            std::vector<float> ref(3 * n), got(3 * n);
            detail::scalarKernels().shadeVertices(pos.data(), nrm.data(), n, world, normalFrom, ctx,
                                                  m, ref.data());
            for (const detail::Kernels* k : simdKernels()) {
                std::fill(got.begin(), got.end(), -1.0f);
                k->shadeVertices(pos.data(), nrm.data(), n, world, normalFrom, ctx, m, got.data());
                for (std::size_t i = 0; i < 3 * n; ++i) {
                    if (std::isnan(ref[i]) && std::isnan(got[i])) continue;  // payloads may differ
                    ASSERT_EQ(std::memcmp(&got[i], &ref[i], 4), 0)
                        << "vertex " << i / 3 << " lights " << lightCount << " shininess "
                        << shininess;
                }
            }
        }
    }
}

TEST(Kernels, SpecularPowSimdEqualsScalar) {
    // lighting.h's specularPow vectorized: a dense sweep of x (every 331st float bit pattern in
    // [0, 1.01], so zero, denormals, x = 1 and a little above), plus special values, bit for bit.
    std::vector<float> x;
    for (std::uint32_t b = 0; b <= std::bit_cast<std::uint32_t>(1.01f); b += 331)
        x.push_back(std::bit_cast<float>(b));
    for (float v : {0.0f, -0.0f, 1.0f, 0x1p-149f, 0x1p-126f, 0x1.fffffep-127f, 0.70710677f,
                    0.70710683f, 1.4142135f, 2.0f, 1e30f, std::numeric_limits<float>::infinity(),
                    std::numeric_limits<float>::quiet_NaN()}) {
        x.push_back(v);
    }
    std::vector<float> ref(x.size()), got(x.size());
    for (float s : {1.0f, 32.0f, 77.5f, 1000.0f, 0.5f, 0.0f, 3e4f}) {
        detail::scalarKernels().specularPow(x.data(), x.size(), s, ref.data());
        for (std::size_t i = 0; i < x.size(); ++i) {
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ref[i]),
                      std::bit_cast<std::uint32_t>(specularPow(x[i], s)));
        }
        for (const detail::Kernels* k : simdKernels()) {
            std::fill(got.begin(), got.end(), -1.0f);
            k->specularPow(x.data(), x.size(), s, got.data());
            for (std::size_t i = 0; i < x.size(); ++i) {
                if (std::isnan(ref[i]) && std::isnan(got[i])) continue;  // payloads may differ
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got[i]),
                          std::bit_cast<std::uint32_t>(ref[i]))
                    << "x " << x[i] << " s " << s;
            }
        }
    }
}

TEST(Kernels, TransformPointsSimdEqualsScalar) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-50.0f, 50.0f);
    const std::size_t n = 1000 + 7;
    std::vector<glm::vec3> pos(n);
    for (auto& p : pos) p = {u(rng), u(rng), u(rng)};
    const glm::mat4 m =
        glm::perspective(0.9f, 1.3f, 0.1f, 100.0f) *
        glm::lookAt(glm::vec3(3.0f, 2.0f, 9.0f), glm::vec3(0.1f, 0.2f, -0.3f), glm::vec3(0, 1, 0)) *
        glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0.3f, 1.0f, 0.1f));
    std::vector<float> ref(4 * n), got(4 * n);
    detail::scalarKernels().transformPoints(pos.data(), n, m, &ref[0], &ref[n], &ref[2 * n],
                                            &ref[3 * n]);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec4 c = detail::transformPoint(m, pos[i]);
        for (int r = 0; r < 4; ++r)
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ref[r * n + i]),
                      std::bit_cast<std::uint32_t>(c[r]));
    }
    for (const detail::Kernels* k : simdKernels()) {
        for (std::size_t count : {n, std::size_t(5), std::size_t(16), std::size_t(17)}) {
            std::fill(got.begin(), got.end(), -1.0f);
            k->transformPoints(pos.data(), count, m, &got[0], &got[n], &got[2 * n], &got[3 * n]);
            for (std::size_t i = 0; i < n; ++i) {
                for (int r = 0; r < 4; ++r) {
                    const float want = i < count ? ref[r * n + i] : -1.0f;
                    ASSERT_EQ(std::bit_cast<std::uint32_t>(got[r * n + i]),
                              std::bit_cast<std::uint32_t>(want))
                        << "vertex " << i << " of " << count;
                }
            }
        }
    }
}

TEST(Kernels, SetupViewsSimdEqualsScalar) {
    // Random small and large triangles seen from 1..64 views: every field the caller reads.
    std::mt19937 rng(4242);
    std::uniform_int_distribution<std::int32_t> jitter(-900, 900);
    std::uniform_int_distribution<std::int32_t> pos(-2000, 300000);
    int smallSeen = 0, generalSeen = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        const int n = 1 + int(rng() % 64);
        const std::int32_t cy = pos(rng), cx = pos(rng);
        const bool big = iter % 4 == 0;
        std::int32_t y[3];
        for (auto& v : y) v = cy + (big ? jitter(rng) * 20 : jitter(rng) / 2);
        detail::YSetup ys;
        detail::setupY(ys, y[0], y[1], y[2], 0, 767);
        if (ys.rowMin > ys.rowMax) continue;
        std::int32_t x[3][kMaxViews];
        for (int k = 0; k < n; ++k) {
            for (int i = 0; i < 3; ++i)
                x[i][k] = cx + k * 37 + (big ? jitter(rng) * 20 : jitter(rng) / 2);
        }
        detail::ViewsSetup ref, got;
        const std::uint64_t refLanes =
            detail::scalarKernels().setupViews(ys, x[0], x[1], x[2], n, 1024, ref);
        for (int v = 0; v < n; ++v) {
            ASSERT_EQ((refLanes >> v) & 1u, std::uint64_t(ref.mask[v] != 0))
                << iter << " view " << v;
        }
        if (n < 64) {
            ASSERT_EQ(refLanes >> n, 0u) << "no lanes past n";
        }
        for (const detail::Kernels* k : simdKernels()) {
            ASSERT_EQ(k->setupViews(ys, x[0], x[1], x[2], n, 1024, got), refLanes) << iter;
            for (int v = 0; v < n; ++v) {
                ASSERT_EQ(got.mask[v], ref.mask[v]) << iter << " view " << v;
                if (ref.mask[v] == 0) continue;
                ASSERT_EQ(got.colMin[v], ref.colMin[v]);
                if (ref.mask[v] < 0) continue;
                ASSERT_EQ(got.area[v], ref.area[v]);
                for (int i = 0; i < 3; ++i) {
                    ASSERT_EQ(got.e[i][v], ref.e[i][v]);
                    ASSERT_EQ(got.sx[i][v], ref.sx[i][v]);
                    ASSERT_EQ(got.sy[i][v], ref.sy[i][v]);
                    ASSERT_EQ(got.bias[i][v], ref.bias[i][v]);
                }
            }
        }
        for (int v = 0; v < n; ++v) smallSeen += ref.mask[v] > 0, generalSeen += ref.mask[v] < 0;
    }
    EXPECT_GT(smallSeen, 1000);
    EXPECT_GT(generalSeen, 1000);
}

/// A random triangle of a long sheared row of n views (x derived per view from the center):
/// its center clip x, w − convergence (convergence 4) and 1/w per vertex, the views' shears
/// (centered, `stepScale` times a random step in [-1, 1]) and the y setup shared by the views in
/// an image of `height` rows. `spread`: the vertices' offsets from their center, as a fraction of
/// w (big triangles: 0.3). False when no row center is covered.
struct ShearedCase {
    detail::ShearedTri t;
    float shears[kMaxViews];
    detail::YSetup ys;
};
bool randomShearedCase(std::mt19937& rng, int n, bool big, float spread, float stepScale,
                       int height, ShearedCase& c) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const float w0 = 2.0f + 3.0f * (unit(rng) + 1.0f), conv = 4.0f;
    float y[3];
    const float cx = unit(rng) * w0 * 0.8f, cy = unit(rng) * w0 * 0.8f;
    for (int j = 0; j < 3; ++j) {
        const float w = w0 + unit(rng) * (big ? 1.0f : 0.01f);
        c.t.cx[j] = cx + unit(rng) * (big ? 0.3f : spread) * w;
        c.t.wc[j] = w - conv;
        c.t.q[j] = 1.0f / w;
        y[j] = cy + unit(rng) * (big ? 0.3f : spread) * w;
    }
    const float step = unit(rng) * stepScale;
    for (int k = 0; k < n; ++k) c.shears[k] = (float(k) - 0.5f * float(n - 1)) * step;
    const float h = float(height);
    detail::setupY(c.ys, detail::snapY(y[0], c.t.q[0], h), detail::snapY(y[1], c.t.q[1], h),
                   detail::snapY(y[2], c.t.q[2], h), 0, height - 1);
    return c.ys.rowMin <= c.ys.rowMax;
}

TEST(Kernels, SetupShearedSimdEqualsScalar) {
    // Small and large triangles of a long sheared row (x derived per view from the center):
    // the derived x of every view, and every setup field the caller reads.
    std::mt19937 rng(777);
    const float conv = 4.0f;
    int seen = 0;
    for (int iter = 0; iter < 2000; ++iter) {
        const int n = 1 + int(rng() % 64);
        ShearedCase row;
        if (!randomShearedCase(rng, n, iter % 4 == 0, 0.004f, 0.02f, 768, row)) continue;
        const detail::ShearedTri& t = row.t;
        const float* shears = row.shears;
        const detail::YSetup& ys = row.ys;
        detail::ViewsSetup ref, got;
        detail::ViewsX refX, gotX;
        const std::uint64_t refLanes =
            detail::scalarKernels().setupSheared(ys, t, shears, n, 1024, ref, refX);
        // The views with a pixel-center column, packed in view order, with their x.
        int m = 0;
        for (int k = 0; k < n; ++k) {
            std::int32_t x[3];
            for (int j = 0; j < 3; ++j) {
                x[j] = detail::snapX(detail::shearClip(t.cx[j], shears[k], t.wc[j] + conv, conv),
                                     t.q[j], 1024.0f);
            }
            if (detail::noColumns(x[0], x[1], x[2], 1024)) continue;
            ASSERT_EQ(refX.view[m], k);
            for (int j = 0; j < 3; ++j) ASSERT_EQ(refX.x[j][m], x[j]);
            ++m;
        }
        if (m < 64) {
            ASSERT_EQ(refLanes >> m, 0u);
        }
        for (const detail::Kernels* k : simdKernels()) {
            ASSERT_EQ(k->setupSheared(ys, t, shears, n, 1024, got, gotX), refLanes) << iter;
            for (int v = 0; v < m; ++v) {
                ASSERT_EQ(gotX.view[v], refX.view[v]);
                for (int j = 0; j < 3; ++j) ASSERT_EQ(gotX.x[j][v], refX.x[j][v]);
                if (!((refLanes >> v) & 1u)) continue;
                ASSERT_EQ(got.mask[v], ref.mask[v]) << iter << " view " << v;
                ASSERT_EQ(got.colMin[v], ref.colMin[v]);
                if (ref.mask[v] < 0) continue;
                ASSERT_EQ(got.area[v], ref.area[v]);
                for (int i = 0; i < 3; ++i) {
                    ASSERT_EQ(got.e[i][v], ref.e[i][v]);
                    ASSERT_EQ(got.sx[i][v], ref.sx[i][v]);
                    ASSERT_EQ(got.sy[i][v], ref.sy[i][v]);
                    ASSERT_EQ(got.bias[i][v], ref.bias[i][v]);
                }
            }
        }
        seen += std::popcount(refLanes);
    }
    EXPECT_GT(seen, 1000);
}

template <class T>
using Images = std::vector<std::vector<T>>;  // one image per view

/// Views [0, n) of two sets of images equal, color and depth bit for bit.
::testing::AssertionResult sameImages(int n, const Images<float>& gotDepth,
                                      const Images<std::uint32_t>& gotColor,
                                      const Images<float>& refDepth,
                                      const Images<std::uint32_t>& refColor) {
    for (int v = 0; v < n; ++v) {
        for (std::size_t i = 0; i < refColor[v].size(); ++i) {
            if (gotColor[v][i] != refColor[v][i]) {
                return ::testing::AssertionFailure() << "view " << v << " pixel " << i << " color "
                                                     << gotColor[v][i] << " != " << refColor[v][i];
            }
            if (std::bit_cast<std::uint32_t>(gotDepth[v][i]) !=
                std::bit_cast<std::uint32_t>(refDepth[v][i])) {
                return ::testing::AssertionFailure() << "view " << v << " pixel " << i << " depth "
                                                     << gotDepth[v][i] << " != " << refDepth[v][i];
            }
        }
    }
    return ::testing::AssertionSuccess();
}

/// k.drawSheared into views [0, n) of depth / color: through the tables of the separate images
/// (block false: blockStride 0), or with the images copied into one block, the kernel told its
/// stride (blockStride), and copied back after.
int drawShearedInto(const detail::Kernels& k, bool block, const detail::YSetup& ys,
                    const detail::ShearedTri& t, const float* shears, int n,
                    const std::uint64_t* culled, int width, int height,
                    const detail::FragmentTri& tri, bool flat, Images<float>& depth,
                    Images<std::uint32_t>& color, detail::ViewsX& xs) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    std::vector<float> depthBlock(block ? pixels * std::size_t(n) : 0);
    std::vector<std::uint32_t> colorBlock(depthBlock.size());
    std::vector<float*> dp(kMaxViews, nullptr);
    std::vector<std::uint32_t*> cp(kMaxViews, nullptr);
    for (int v = 0; v < n; ++v) {
        if (block) {
            std::copy(depth[v].begin(), depth[v].end(), depthBlock.begin() + v * pixels);
            std::copy(color[v].begin(), color[v].end(), colorBlock.begin() + v * pixels);
            dp[v] = depthBlock.data() + v * pixels, cp[v] = colorBlock.data() + v * pixels;
        } else {
            dp[v] = depth[v].data(), cp[v] = color[v].data();
        }
    }
    const int count = k.drawSheared(ys, t, shears, n, culled, width, height, tri, flat, dp.data(),
                                    cp.data(), block ? std::int32_t(pixels) : 0, xs);
    for (int v = 0; block && v < n; ++v) {
        std::copy_n(depthBlock.begin() + v * pixels, pixels, depth[v].begin());
        std::copy_n(colorBlock.begin() + v * pixels, pixels, color[v].begin());
    }
    return count;
}

TEST(Kernels, ShadeLanesSimdEqualsScalar) {
    // One triangle's fragments in up to 64 views (Vertex and Flat, untextured): random
    // triangles set up by setupViews on a small image, views' depth images holding random
    // depths (so that some fragments pass and some fail), vertex colors outside [0, 1] too
    // (the clamp), lanes mapped to views through a shuffled slot table. Every image byte and the
    // lanes left to the general walk.
    constexpr int kW = 96, kH = 64;
    std::mt19937 rng(9191);
    std::uniform_int_distribution<std::int32_t> pos(0, kW * 256 - 1), jitter(-700, 700);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int passed = 0, covered = 0, general = 0;
    Images<float> depth0(64, std::vector<float>(kW * kH)), refDepth = depth0, gotDepth = depth0;
    Images<std::uint32_t> color0(64, std::vector<std::uint32_t>(kW * kH)), refColor = color0,
                                                                           gotColor = color0;
    for (int iter = 0; iter < 300; ++iter) {
        const int n = 1 + int(rng() % 64);
        const bool big = iter % 5 == 0;
        const std::int32_t cx = pos(rng), cy = pos(rng) * kH / kW;
        std::int32_t y[3];
        for (auto& v : y) v = cy + (big ? jitter(rng) * 8 : jitter(rng) / 3);
        detail::YSetup ys;
        detail::setupY(ys, y[0], y[1], y[2], 0, kH - 1);
        if (ys.rowMin > ys.rowMax) continue;
        std::int32_t x[3][kMaxViews];
        for (int k = 0; k < n; ++k)
            for (int i = 0; i < 3; ++i)
                x[i][k] = cx + k * 29 + (big ? jitter(rng) * 8 : jitter(rng) / 3);
        detail::ViewsSetup s;
        const std::uint64_t lanes =
            detail::scalarKernels().setupViews(ys, x[0], x[1], x[2], n, kW, s);
        detail::FragmentTri tri;
        float attr[3][3];
        for (int j = 0; j < 3; ++j) {
            tri.z[j] = unit(rng);
            tri.q[j] = 0.2f + unit(rng);
            for (float& a : attr[j]) a = unit(rng) * 1.4f - 0.2f;
            tri.attr[j] = attr[j];
        }
        tri.flat = std::uint32_t(rng());
        // Lane k draws into view slot[k] (a permutation); 64 views' images.
        std::uint8_t slot[kMaxViews + 16] = {};
        for (int k = 0; k < n; ++k) slot[k] = std::uint8_t(k);
        std::shuffle(slot, slot + n, rng);
        for (int v = 0; v < n; ++v) {
            for (float& d : depth0[v]) d = unit(rng);
            for (std::uint32_t& c : color0[v]) c = std::uint32_t(rng());
        }
        for (const bool flat : {false, true}) {
            auto run = [&](const detail::Kernels& k, Images<float>& depth,
                           Images<std::uint32_t>& color) {
                std::vector<float*> dp;
                std::vector<std::uint32_t*> cp;
                for (int v = 0; v < n; ++v) {
                    depth[v] = depth0[v], color[v] = color0[v];
                    dp.push_back(depth[v].data()), cp.push_back(color[v].data());
                }
                return k.shadeLanes(s, lanes, ys.rowMin, kW, kH, tri, flat, slot, dp.data(),
                                    cp.data());
            };
            const std::uint64_t refGeneral = run(detail::scalarKernels(), refDepth, refColor);
            for (int k = 0; k < n; ++k) {
                ASSERT_EQ((refGeneral >> k) & 1u,
                          std::uint64_t(((lanes >> k) & 1u) && s.mask[k] < 0));
            }
            for (int v = 0; v < n; ++v) {
                for (int i = 0; i < kW * kH; ++i) {
                    if (refDepth[v][i] != depth0[v][i]) ++passed;
                }
            }
            for (const detail::Kernels* k : simdKernels()) {
                ASSERT_EQ(run(*k, gotDepth, gotColor), refGeneral) << iter;
                ASSERT_TRUE(sameImages(n, gotDepth, gotColor, refDepth, refColor)) << iter;
            }
        }
        for (int k = 0; k < n; ++k) {
            covered += s.mask[k] > 0;
            general += s.mask[k] < 0;
        }
    }
    EXPECT_GT(passed, 1000);   // fragments that passed the depth test
    EXPECT_GT(covered, 1000);  // lanes with covered centers
    EXPECT_GT(general, 100);   // lanes left to the general walk
}

TEST(Kernels, DrawShearedEqualsRasterTrianglePerView) {
    // The fused long-row kernel (setup and fragments of all views of one triangle, rows of up
    // to kMaxViews): small and large triangles of a sheared row, some views culled, depth images
    // holding random depths.
    // The reference draws each view on its own: its x from the center (shearClip, snapX) and
    // rasterTriangle through FragmentSink, the views drawSheared returns drawn the same way
    // after it. Every path's images, bit for bit, and the views it returns.
    constexpr int kW = 96, kH = 64;
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> depthDist(0.0f, 1.0f);
    const float conv = 4.0f;
    int passed = 0, general = 0, culledViews = 0, skippedGeneral = 0;
    Images<float> depth0(kMaxViews, std::vector<float>(kW * kH)), refDepth = depth0,
                                                                 gotDepth = depth0;
    Images<std::uint32_t> color0(kMaxViews, std::vector<std::uint32_t>(kW * kH)), refColor = color0,
                                                                           gotColor = color0;
    std::vector<const detail::Kernels*> paths{&detail::scalarKernels()};
    for (const detail::Kernels* k : simdKernels()) {
        if (k->drawSheared) paths.push_back(k);
    }
    for (int iter = 0; iter < 300; ++iter) {
        const int n = 1 + int(rng() % kMaxViews);
        ShearedCase row;
        if (!randomShearedCase(rng, n, iter % 5 == 0, 0.03f, 0.03f * 64.0f / float(std::max(n, 64)),
                               kH, row)) {
            continue;
        }
        const detail::ShearedTri& t = row.t;
        const float* shears = row.shears;
        const detail::YSetup& ys = row.ys;
        std::uint64_t culled[2] = {};
        if (iter % 3 == 0) {
            for (std::uint64_t& c : culled) c = std::uint64_t(rng()) << 32 | rng();
        }
        auto isCulled = [&](int k) { return (culled[k / 64] >> (k % 64)) & 1u; };
        detail::FragmentTri tri;
        float attr[3][3];
        for (int j = 0; j < 3; ++j) {
            tri.z[j] = depthDist(rng);
            tri.q[j] = t.q[j];
            for (float& a : attr[j]) a = depthDist(rng) * 1.4f - 0.2f;
            tri.attr[j] = attr[j];
        }
        tri.flat = std::uint32_t(rng());
        for (int v = 0; v < n; ++v) {
            for (float& d : depth0[v]) d = depthDist(rng);
            for (std::uint32_t& c : color0[v]) c = std::uint32_t(rng());
        }
        for (const bool flat : {false, true}) {
            auto reset = [&](Images<float>& depth, Images<std::uint32_t>& color) {
                for (int v = 0; v < n; ++v) depth[v] = depth0[v], color[v] = color0[v];
            };
            auto drawView = [&](Images<float>& depth, Images<std::uint32_t>& color, int v,
                                const std::int32_t x[3]) {
                const detail::Target target{color[v].data(), depth[v].data(), kW, kH};
                if (flat) {
                    detail::FragmentSink<Shading::Flat> sink{target, &tri, {}};
                    detail::rasterTriangle(ys, x, kW, sink);
                } else {
                    detail::FragmentSink<Shading::Vertex> sink{target, &tri, {}};
                    detail::rasterTriangle(ys, x, kW, sink);
                }
            };
            // Reference: every view that is not culled, on its own.
            reset(refDepth, refColor);
            for (int k = 0; k < n; ++k) {
                if (isCulled(k)) continue;
                std::int32_t x[3];
                for (int j = 0; j < 3; ++j) {
                    x[j] =
                        detail::snapX(detail::shearClip(t.cx[j], shears[k], t.wc[j] + conv, conv),
                                      t.q[j], float(kW));
                }
                drawView(refDepth, refColor, k, x);
            }
            for (int v = 0; v < n; ++v) {
                for (int i = 0; i < kW * kH; ++i) passed += refDepth[v][i] != depth0[v][i];
            }
            std::vector<int> refViews;
            for (const detail::Kernels* k : paths) {
                reset(gotDepth, gotColor);
                detail::ViewsX xs{};  // shadeGroup reads all 8 view bytes of a group
                // Odd cases: the images in one block (blockStride).
                const int count = drawShearedInto(*k, iter % 2 == 1, ys, t, shears, n,
                                                  iter % 6 == 1 ? nullptr : culled, kW, kH, tri,
                                                  flat, gotDepth, gotColor, xs);
                std::vector<int> views;
                for (int i = 0; i < count; ++i) {
                    views.push_back(xs.view[i]);
                    ASSERT_FALSE(isCulled(xs.view[i]));
                    const std::int32_t x[3] = {xs.x[0][i], xs.x[1][i], xs.x[2][i]};
                    drawView(gotDepth, gotColor, xs.view[i], x);
                }
                ASSERT_TRUE(std::is_sorted(views.begin(), views.end()));
                if (k == paths.front()) {
                    refViews = views;
                    general += count;
                } else {
                    // A SIMD path may skip views that cannot cover a center of a one-row
                    // triangle's row (packOnRow) without walking them: a subset, and the
                    // images below show that the skipped ones draw nothing.
                    ASSERT_TRUE(
                        std::includes(refViews.begin(), refViews.end(), views.begin(), views.end()))
                        << iter;
                    if (ys.rowMin == ys.rowMax) {
                        skippedGeneral += int(refViews.size() - views.size());
                    } else {
                        ASSERT_EQ(views, refViews) << iter;
                    }
                }
                ASSERT_TRUE(sameImages(n, gotDepth, gotColor, refDepth, refColor)) << iter;
            }
        }
        for (int k = 0; k < n; ++k) culledViews += int(isCulled(k));
    }
    EXPECT_GT(passed, 1000);       // fragments that passed the depth test
    EXPECT_GT(general, 100);       // views left to the general walk
    EXPECT_GT(culledViews, 1000);  // views taken out by `culled`
    if (paths.size() > 1) {
        EXPECT_GT(skippedGeneral, 10);  // wide views off the row's centers
    }
}

TEST(Kernels, DrawShearedKeepsTheFirstOfEqualDepths) {
    // Every fragment of a second draw of the same triangle, with other colors, ties the depth
    // the first draw left: the depth test is GL_LESS, so the second draw writes nothing and the
    // first colors stay — in every path, as in each view drawn on its own (rasterTriangle
    // through FragmentSink). The random depths of DrawShearedEqualsRasterTrianglePerView are
    // never equal to a fragment's, so a `<=` for `<` would pass there.
    constexpr int kW = 96, kH = 64;
    std::mt19937 rng(1357);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float conv = 4.0f;
    const Images<float> depth0(kMaxViews, std::vector<float>(kW * kH, 1.0f));
    const Images<std::uint32_t> color0(kMaxViews, std::vector<std::uint32_t>(kW * kH, 0u));
    Images<float> refDepth = depth0, gotDepth = depth0;
    Images<std::uint32_t> refColor = color0, gotColor = color0;
    std::vector<const detail::Kernels*> paths{&detail::scalarKernels()};
    for (const detail::Kernels* k : simdKernels()) {
        if (k->drawSheared) paths.push_back(k);
    }
    int kept = 0;
    for (int iter = 0; iter < 120; ++iter) {
        const int n = 1 + int(rng() % kMaxViews);
        ShearedCase row;
        if (!randomShearedCase(rng, n, iter % 5 == 0, 0.03f, 0.03f * 64.0f / float(std::max(n, 64)),
                               kH, row)) {
            continue;
        }
        // Two draws: the same depths and 1/w, other attributes and flat colors.
        detail::FragmentTri tris[2];
        float attr[2][3][3];
        for (int j = 0; j < 3; ++j) {
            tris[0].z[j] = tris[1].z[j] = unit(rng);
            tris[0].q[j] = tris[1].q[j] = row.t.q[j];
            for (int d = 0; d < 2; ++d) {
                for (float& a : attr[d][j]) a = unit(rng);
                tris[d].attr[j] = attr[d][j];
            }
        }
        tris[0].flat = 0xff0000ffu, tris[1].flat = 0xff00ff00u;
        for (const bool flat : {false, true}) {
            auto drawView = [&](Images<float>& depth, Images<std::uint32_t>& color, int v,
                                const std::int32_t x[3], const detail::FragmentTri& tri) {
                const detail::Target target{color[v].data(), depth[v].data(), kW, kH};
                if (flat) {
                    detail::FragmentSink<Shading::Flat> sink{target, &tri, {}};
                    detail::rasterTriangle(row.ys, x, kW, sink);
                } else {
                    detail::FragmentSink<Shading::Vertex> sink{target, &tri, {}};
                    detail::rasterTriangle(row.ys, x, kW, sink);
                }
            };
            for (int v = 0; v < n; ++v) refDepth[v] = depth0[v], refColor[v] = color0[v];
            for (const detail::FragmentTri& tri : tris) {
                for (int k = 0; k < n; ++k) {
                    std::int32_t x[3];
                    for (int j = 0; j < 3; ++j) {
                        x[j] = detail::snapX(
                            detail::shearClip(row.t.cx[j], row.shears[k], row.t.wc[j] + conv, conv),
                            row.t.q[j], float(kW));
                    }
                    drawView(refDepth, refColor, k, x, tri);
                }
            }
            for (int v = 0; v < n; ++v) {
                for (int i = 0; i < kW * kH; ++i) kept += refDepth[v][i] != 1.0f;
            }
            for (const detail::Kernels* k : paths) {
                for (int v = 0; v < n; ++v) gotDepth[v] = depth0[v], gotColor[v] = color0[v];
                for (const detail::FragmentTri& tri : tris) {
                    detail::ViewsX xs{};
                    const int count =
                        drawShearedInto(*k, iter % 2 == 1, row.ys, row.t, row.shears, n, nullptr,
                                        kW, kH, tri, flat, gotDepth, gotColor, xs);
                    for (int i = 0; i < count; ++i) {
                        const std::int32_t x[3] = {xs.x[0][i], xs.x[1][i], xs.x[2][i]};
                        drawView(gotDepth, gotColor, xs.view[i], x, tri);
                    }
                }
                ASSERT_TRUE(sameImages(n, gotDepth, gotColor, refDepth, refColor)) << iter;
            }
        }
    }
    EXPECT_GT(kept, 1000);  // fragments the first draw wrote and the second tied
}

TEST(Kernels, DrawShearedKeepsEveryViewThatCoversACenter) {
    // One-row triangles whose vertices sit on, or 1–3 / 256 px beside, pixel centers and the
    // row's center line (edges on the line, vertices on a center: the fill rule's ties), in
    // rows of 1..kMaxViews views: drawSheared's SIMD paths skip views from an estimate of each
    // view's span on the row (packOnRow), which must never drop a view that covers a center.
    // Also: rows whose shears move every vertex by exactly one pixel a view (w = 2, so that the
    // ties recur in every view), triangles taller than the band cut to its one row, and long
    // thin ones reaching far into the guard band (where the margin's relative part matters).
    // Every fragment passes (depth images at 1), so every covered center shows; the reference
    // draws each view on its own (rasterTriangle), as DrawShearedEqualsRasterTrianglePerView.
    constexpr int kW = 24, kH = 6, kRow = 2;
    std::mt19937 rng(2468);
    std::uniform_int_distribution<int> nudge(-3, 3), column(4, kW - 5), pick(0, 3);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const float conv = 4.0f;
    const Images<float> depth0(kMaxViews, std::vector<float>(kW * kH, 1.0f));
    const Images<std::uint32_t> color0(kMaxViews, std::vector<std::uint32_t>(kW * kH, 0u));
    Images<float> refDepth = depth0, gotDepth = depth0;
    Images<std::uint32_t> refColor = color0, gotColor = color0;
    int covered = 0, tested = 0, whole = 0, cut = 0, far = 0;
    for (int iter = 0; iter < 4000; ++iter) {
        const int n = 1 + int(rng() % kMaxViews);
        const bool wholeSteps = iter % 4 == 0;  // w = 2: a vertex moves -1 px a view
        const bool tall = iter % 4 == 1;        // rows beyond the band's one row
        const int farVertex = iter % 8 == 2 ? int(rng() % 3) : -1;
        // Window coordinates (px) of the center view: on a center / the center line, or nudged.
        detail::ShearedTri t;
        std::int32_t sy[3];
        const int col = column(rng);
        float attr[3][3] = {};
        detail::FragmentTri tri;
        for (int j = 0; j < 3; ++j) {
            const float w = wholeSteps ? 2.0f : 3.0f + 0.5f * unit(rng);
            float wx = float(col + (pick(rng) == 0 ? 1 : 0)) + 0.5f +
                       float(pick(rng) ? 0 : nudge(rng)) / 256.0f +
                       (pick(rng) == 0 ? 0.4f * unit(rng) : 0.0f);
            if (j == farVertex) wx += (unit(rng) < 0.0f ? -1.0f : 1.0f) * float(kW) * 30.0f;
            const float wy = float(kRow) + 0.5f +
                             (tall ? 1.8f * unit(rng) : (pick(rng) ? 0.0f : 0.45f * unit(rng))) +
                             float(pick(rng) ? 0 : nudge(rng)) / 256.0f;
            t.cx[j] = (wx / float(kW) * 2.0f - 1.0f) * w;
            t.wc[j] = w - conv;
            t.q[j] = 1.0f / w;
            sy[j] = detail::snapY((wy / float(kH) * 2.0f - 1.0f) * w, t.q[j], float(kH));
            tri.z[j] = 0.5f, tri.q[j] = t.q[j], tri.attr[j] = attr[j];
        }
        tri.flat = 0xff00ff00u;
        detail::YSetup ys;
        detail::setupY(ys, sy[0], sy[1], sy[2], tall ? kRow : 0, tall ? kRow : kH - 1);
        if (ys.rowMin != ys.rowMax) continue;
        // Shears that move a vertex by whole pixels (w = 2: wc / w = -1) or by fractions of one
        // between views.
        float shears[kMaxViews];
        const float step = (wholeSteps ? 1.0f : 0.37f * unit(rng)) * 2.0f / float(kW);
        for (int k = 0; k < n; ++k) shears[k] = (float(k) - float(n / 2)) * step;
        whole += int(wholeSteps), cut += int(tall), far += int(farVertex >= 0);
        ++tested;
        for (int v = 0; v < n; ++v) refDepth[v] = depth0[v], refColor[v] = color0[v];
        for (int k = 0; k < n; ++k) {
            std::int32_t x[3];
            for (int j = 0; j < 3; ++j) {
                x[j] = detail::snapX(detail::shearClip(t.cx[j], shears[k], t.wc[j] + conv, conv),
                                     t.q[j], float(kW));
            }
            detail::FragmentSink<Shading::Flat> sink{
                detail::Target{refColor[k].data(), refDepth[k].data(), kW, kH}, &tri, {}};
            detail::rasterTriangle(ys, x, kW, sink);
        }
        for (int v = 0; v < n; ++v) {
            for (const std::uint32_t c : refColor[v]) covered += int(c != 0u);
        }
        for (const detail::Kernels* k : simdKernels()) {
            if (!k->drawSheared) continue;
            for (int v = 0; v < n; ++v) gotDepth[v] = depth0[v], gotColor[v] = color0[v];
            detail::ViewsX xs{};  // shadeGroup reads all 8 view bytes of a group
            const int count = drawShearedInto(*k, iter % 2 == 1, ys, t, shears, n, nullptr, kW, kH,
                                              tri, true, gotDepth, gotColor, xs);
            for (int i = 0; i < count; ++i) {
                const std::int32_t x[3] = {xs.x[0][i], xs.x[1][i], xs.x[2][i]};
                detail::FragmentSink<Shading::Flat> sink{
                    detail::Target{gotColor[xs.view[i]].data(), gotDepth[xs.view[i]].data(), kW,
                                   kH},
                    &tri,
                    {}};
                detail::rasterTriangle(ys, x, kW, sink);
            }
            ASSERT_TRUE(sameImages(n, gotDepth, gotColor, refDepth, refColor)) << iter;
        }
    }
    EXPECT_GT(tested, 2500);
    EXPECT_GT(covered, 20000);  // covered centers
    EXPECT_GT(whole, 500);
    EXPECT_GT(cut, 500);
    EXPECT_GT(far, 200);
}

}  // namespace
}  // namespace mvr::raster
