// Tests of the gl backend's own behaviour: creation without a context, error paths, forced EGL
// platforms, view limits, row order, what auto picks. Its pixels against soft:multipass and
// gl:multipass, method by method (and sorbier2008's gs-mrt / gs-depthmap errors), are the
// conformance suite's (tests/conformance, bounds in tolerances.h). Small sizes keep it fast.
#include <unistd.h>

#include <cstdlib>

#include <gtest/gtest.h>

#include "../conformance/tolerances.h"
#include "gl_test_util.h"
#include "mvr/gl/composite_gpu.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

constexpr int kW = 160, kH = 120;
// An exact method vs gl:multipass: tests/conformance/tolerances.h (kGlExact) says why.
constexpr int kColorThreshold = conformance::kGlExact.channel;
constexpr double kMaxMismatch = conformance::kGlExact.first.fraction;

RenderSettings settings(Shading shading, bool cull = false, bool wire = false) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = shading;
    s.cullBackFaces = cull;
    s.wireframe = wire;
    s.clearColor = {0.1f, 0.15f, 0.2f};
    return s;
}

// ---- basics and errors ---------------------------------------------------------------------

TEST(GlBackend, CreatesWithoutContext) {
    auto b = makeGlBackend();  // must make no EGL call
    EXPECT_EQ(b->name(), "gl");
    const auto m = b->methods();
    EXPECT_EQ(m.front(), "multipass");
    EXPECT_EQ(m.back(), "auto");
    EXPECT_EQ(m.size(), 10u);
}

TEST(GlBackend, UnknownMethodIsUsageError) {
    const Status s = backend().supports("warp-drive");
    EXPECT_EQ(s.code(), ErrorCode::Usage);
    EXPECT_NE(s.message().find("warp-drive"), std::string::npos);
}

// Runs one test of this binary in a child process with extra environment variables; the
// child's exit status (0 = passed or skipped).
int runChild(const std::string& env, const std::string& test) {
    char exe[4096] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
    if (n <= 0) return -1;
    const std::string cmd = env + " '" + std::string(exe, static_cast<std::size_t>(n)) +
                            "' --gtest_filter=" + test + " > /dev/null 2>&1";
    return std::system(cmd.c_str());
}

// Without any EGL vendor library (glvnd finds none) the backend must report "no EGL display"
// as ErrorCode::Unsupported: run this same binary with glvnd pointed at nothing.
TEST(GlBackend, NoDisplayIsUnsupportedNotACrash) {
    if (std::getenv("MVR_GL_TEST_EXPECT_NO_EGL")) {
        const Status s = makeGlBackend()->supports("multipass");
        if (s) MVR_SKIP(NotApplicable) << "this libEGL ignores __EGL_VENDOR_LIBRARY_FILENAMES";
        EXPECT_EQ(s.code(), ErrorCode::Unsupported);
        EXPECT_EQ(s.message().rfind("no EGL display", 0), 0u) << s.message();
        const std::vector<Image> pair = {Image(2, 2), Image(2, 2)};
        auto r = composeGpu("anaglyph-color", pair);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.status().code(), ErrorCode::Unsupported);
        return;
    }
    EXPECT_EQ(
        runChild("MVR_GL_TEST_EXPECT_NO_EGL=1 __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json",
                 "GlBackend.NoDisplayIsUnsupportedNotACrash"),
        0);
}

// MVR_EGL_PLATFORM picks the platform: "device" (Mesa offers its software device too) must
// render like the default; a bad value is a Usage error naming the choices.
TEST(GlBackend, ForcedPlatforms) {
    if (const char* p = std::getenv("MVR_GL_TEST_PLATFORM")) {
        auto b = makeGlBackend();
        const Status s = b->supports("multipass");
        if (std::string(p) == "bogus") {
            EXPECT_EQ(s.code(), ErrorCode::Usage);
            EXPECT_NE(s.message().find("expected device, surfaceless or default"),
                      std::string::npos)
                << s.message();
            return;
        }
        if (!s) MVR_SKIP(NoGlContext) << s.message();
        std::string all;
        for (const auto& l : b->info()) all += l + "\n";
        EXPECT_NE(all.find(std::string("EGL platform: ") + p), std::string::npos) << all;
        const Scene& scene = defaultScene();
        auto r = b->render(scene, rigFor(scene, 2, 1), RenderSettings{.width = 64, .height = 48},
                           "gs-layered");
        EXPECT_TRUE(r) << r.status().message();
        return;
    }
    MVR_SKIP_WITHOUT_GL();
    EXPECT_EQ(
        runChild("MVR_GL_TEST_PLATFORM=bogus MVR_EGL_PLATFORM=bogus", "GlBackend.ForcedPlatforms"),
        0);
    EXPECT_EQ(runChild("MVR_GL_TEST_PLATFORM=surfaceless MVR_EGL_PLATFORM=surfaceless",
                       "GlBackend.ForcedPlatforms"),
              0);
    EXPECT_EQ(runChild("MVR_GL_TEST_PLATFORM=device MVR_EGL_PLATFORM=device",
                       "GlBackend.ForcedPlatforms"),
              0);
}

TEST(GlBackend, InfoNamesDriverAndLimits) {
    MVR_SKIP_WITHOUT_GL();
    const auto lines = backend().info();
    std::string all;
    for (const auto& l : lines) all += l + "\n";
    EXPECT_NE(all.find("GL_RENDERER"), std::string::npos) << all;
    EXPECT_NE(all.find("GL_MAX_GEOMETRY_SHADER_INVOCATIONS"), std::string::npos) << all;
    EXPECT_NE(all.find("method gs-layered"), std::string::npos) << all;
}

TEST(GlBackend, MultiviewSupportedOrClearlyUnsupported) {
    MVR_SKIP_WITHOUT_GL();
    const Status s = backend().supports("multiview");
    if (s) return;  // a driver with GL_OVR_multiview: covered by the conformance suite
    EXPECT_EQ(s.code(), ErrorCode::Unsupported);
    EXPECT_NE(s.message().find("GL_OVR_multiview"), std::string::npos) << s.message();
    const Scene& scene = defaultScene();
    auto r = backend().render(scene, rigFor(scene, 2, 1), settings(Shading::Flat), "multiview");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Unsupported);
}

TEST(GlBackend, StereoOnlyMethodsRefuseOtherViewCounts) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    for (const char* m : {"gs-mrt", "gs-depthmap"}) {
        auto r = backend().render(scene, rigFor(scene, 3, 1), settings(Shading::Flat), m);
        ASSERT_FALSE(r) << m;
        EXPECT_EQ(r.status().code(), ErrorCode::Usage);
        EXPECT_NE(r.status().message().find("exactly 2 views"), std::string::npos)
            << r.status().message();
    }
}

TEST(GlBackend, ViewLimitsAreReportedNotCrashed) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 8, 8);  // 64 views
    ASSERT_EQ(rig.viewCount(), 64);
    RenderSettings s = settings(Shading::Pixel);
    s.width = 32;
    s.height = 24;
    auto ref = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    for (const char* m : {"gs-invocations", "viewport-array", "gs-layered", "instanced-layer",
                          "kalaiah-emulation"}) {
        auto r = backend().render(scene, rig, s, m);
        if (r) {
            ASSERT_EQ(r->color.size(), 64u) << m;
            for (int v = 0; v < 64; ++v) {
                EXPECT_LE(
                    compareImages(ref->color[v], r->color[v], kColorThreshold).differingPixels, 2)
                    << m << " view " << v;
            }
            continue;
        }
        // A driver limit, named (llvmpipe batches them all: 32 invocations, 16 viewports, …).
        EXPECT_EQ(r.status().code(), ErrorCode::Unsupported) << m << ": " << r.status().message();
        EXPECT_NE(r.status().message().find("GL_MAX_"), std::string::npos) << r.status().message();
    }
    // Beyond kMaxViews the rig itself cannot be built; a hand-made one is refused.
    Rig tooMany = rig;
    while (tooMany.viewCount() <= kMaxViews) tooMany.views.push_back(tooMany.views.back());
    auto r = backend().render(scene, tooMany, s, "multipass");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Usage);
}

TEST(GlBackend, BadInputIsAStatus) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    RenderSettings s = settings(Shading::Flat);
    s.width = 0;
    auto r = backend().render(scene, rigFor(scene, 2, 1), s, "multipass");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Usage);

    Scene empty;
    auto r2 = backend().render(empty, rigFor(scene, 2, 1), settings(Shading::Flat), "gs-layered");
    ASSERT_FALSE(r2);
    EXPECT_EQ(r2.status().code(), ErrorCode::Input);

    // Too big to hold: refused before anything is allocated.
    RenderSettings huge = settings(Shading::Flat);
    huge.width = 16384;
    huge.height = 16384;
    auto r4 = backend().render(scene, rigFor(scene, 3, 1), huge, "gs-layered");
    ASSERT_FALSE(r4);
    EXPECT_EQ(r4.status().code(), ErrorCode::Unsupported);
    EXPECT_NE(r4.status().message().find("GiB"), std::string::npos) << r4.status().message();

    Rig noViews = rigFor(scene, 2, 1);
    noViews.views.clear();
    auto r3 = backend().render(scene, noViews, settings(Shading::Flat), "multipass");
    ASSERT_FALSE(r3);
    EXPECT_EQ(r3.status().code(), ErrorCode::Usage);
}

// Row 0 of the output must be the top of the picture: a triangle above the camera axis
// lands in the upper half.
TEST(GlBackend, RowZeroIsTop) {
    MVR_SKIP_WITHOUT_GL();
    Scene scene;
    Mesh m;
    m.positions = {{-1.0f, 0.2f, 0.0f}, {1.0f, 0.2f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.indices = {0, 1, 2};
    scene.meshes.push_back(m);
    scene.instances.push_back({0, glm::mat4(1.0f), Material{{1.0f, 0.0f, 0.0f}, 0.0f, 8.0f}});
    scene.lights = {{{0, 0, 1}, {1, 1, 1}}};
    Camera cam;
    cam.position = {0, 0, 3};
    auto rig = makeRig(cam, RigParams{});
    ASSERT_TRUE(rig);
    for (const char* method : {"multipass", "gs-layered", "kalaiah-emulation", "gs-mrt"}) {
        auto r = backend().render(scene, *rig, settings(Shading::Flat), method);
        ASSERT_TRUE(r) << r.status().message();
        const Image& img = r->color[0];
        int top = 0, bottom = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                if (img.at(x, y).r > 200) (y < kH / 2 ? top : bottom)++;
        EXPECT_GT(top, 100) << method;
        EXPECT_EQ(bottom, 0) << method;
        if (!r->depth.empty()) {
            // Nothing drawn: the clear value 1. The triangle (z = 0 world, 3 units away):
            // window depth strictly inside (0, 1).
            EXPECT_EQ(r->depth[0].at(0, kH - 1), 1.0f) << method;
            EXPECT_GT(r->depth[0].at(kW / 2, kH / 4), 0.0f) << method;
            EXPECT_LT(r->depth[0].at(kW / 2, kH / 4), 1.0f) << method;
        }
    }
}

// ---- auto --------------------------------------------------------------------------------------

TEST(GlBackend, AutoPicksAMeasuredExactMethod) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 4, 1);
    const RenderSettings s = settings(Shading::Vertex);
    auto r = backend().render(scene, rig, s, "auto");
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_NE(r->method, "auto");
    EXPECT_NE(r->method, "gs-mrt");
    EXPECT_NE(r->method, "gs-depthmap");
    EXPECT_NE(r->note.find("auto picked " + r->method), std::string::npos) << r->note;
    EXPECT_NE(r->note.find("multipass"), std::string::npos) << r->note;
    auto ref = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref);
    for (int v = 0; v < 4; ++v) {
        const ImageDiff d = compareImages(ref->color[v], r->color[v], kColorThreshold);
        EXPECT_LE(d.differingPixels, kMaxMismatch * kW * kH);
    }
    auto again = backend().render(scene, rig, s, "auto");  // cached choice
    ASSERT_TRUE(again);
    EXPECT_EQ(again->method, r->method);
    const auto stats = lastFrameStats(backend());
    ASSERT_TRUE(stats.has_value());
    EXPECT_EQ(stats->method, r->method);
    EXPECT_GT(stats->totalWallMs, 0.0);
}

}  // namespace
}  // namespace mvr::gl::test
