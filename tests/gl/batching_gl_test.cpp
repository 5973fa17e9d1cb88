// Tests of the gl backend's batching (kalaiah2007 §3): a method given more views than one of
// its passes takes draws them in ceil(N / limit) passes, each pass's views into their places.
// The per-pass limits are read from `info()` ("L views per pass, batches beyond"), so the
// tests also check what `mvr info` says. Small images and the procedural scene keep them fast
// on llvmpipe.
#include <cstdlib>
#include <map>
#include <regex>

#include <fmt/format.h>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "../conformance/tolerances.h"
#include "gl_test_util.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

constexpr int kW = 64, kH = 48;

RenderSettings smallSettings() {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = Shading::Vertex;
    s.clearColor = {0.1f, 0.15f, 0.2f};
    return s;
}

// A row of `n` off-axis views spanning about a third of the camera distance.
Rig rowOf(const Scene& scene, int n) {
    const Camera cam = cameraFor(scene, static_cast<float>(kW) / kH);
    RigParams p;
    p.columns = n;
    p.rows = 1;
    const float dist = glm::length(cam.position - cam.target);
    p.convergence = dist;
    p.interaxial = 0.3f * dist / static_cast<float>(n);
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

// Views [first, first + n) of `rig` as a rig of their own (a row).
Rig slice(const Rig& rig, int first, int n) {
    Rig r = rig;
    r.views.assign(rig.views.begin() + first, rig.views.begin() + first + n);
    r.columns = n;
    r.rows = 1;
    return r;
}

// The per-pass view limit of every method that batches, from info()'s
// "method NAME: supported, L views per pass…, batches beyond" (vertex shading: the first L).
std::map<std::string, int> perPassLimits() {
    std::map<std::string, int> limits;
    const std::regex re(R"(^method ([a-z-]+): supported, (\d+) views per pass.*batches beyond$)");
    for (const std::string& line : backend().info()) {
        std::smatch m;
        if (std::regex_match(line, m, re)) limits[m[1]] = std::atoi(m[2].str().c_str());
    }
    return limits;
}

// The methods that take any view count (all but the fixed-count ones and auto).
std::vector<std::string> batchingMethods() {
    std::vector<std::string> out;
    for (const std::string& m : backend().methods()) {
        if (m == "gs-mrt" || m == "gs-depthmap" || m == "auto") continue;
        if (backend().supports(m)) out.push_back(m);
    }
    return out;
}

// `got` vs gl:multipass's `ref`, view by view, within tolerances.h's kGlExact.
void expectWithinGlExact(const RenderOutput& ref, const RenderOutput& got, const std::string& m) {
    const conformance::Bound b = conformance::kGlExact;
    ASSERT_EQ(got.color.size(), ref.color.size()) << m;
    ASSERT_EQ(got.depth.size(), ref.depth.size()) << m;
    const double pixels = static_cast<double>(kW) * kH;
    for (std::size_t v = 0; v < ref.color.size(); ++v) {
        const double off = static_cast<double>(
            compareImages(ref.color[v], got.color[v], b.channel).differingPixels);
        EXPECT_TRUE(b.shareFor(static_cast<int>(v)).holds(off / pixels))
            << m << " view " << v << ": " << off << " pixels off";
        const double d = depthMismatch(ref.depth[v], got.depth[v], b.depth, nullptr);
        EXPECT_TRUE(b.depthShare.holds(d)) << m << " view " << v << ": depth " << d;
    }
}

TEST(GlBatching, InfoNamesThePerPassLimit) {
    MVR_SKIP_WITHOUT_GL();
    const auto limits = perPassLimits();
    for (const auto& [m, l] : limits) {
        EXPECT_GE(l, 1) << m;
        EXPECT_LT(l, kMaxViews) << m;
    }
    // llvmpipe: 16 viewports, 32 GS invocations; a driver with more may take them all at once.
    if (backend().supports("viewport-array") && limits.count("viewport-array")) {
        EXPECT_GE(limits.at("viewport-array"), 2);
    }
}

// 100 views (a light-field panel's row) on every method, against gl:multipass; the number of
// passes is ceil(100 / the method's per-pass limit).
TEST(GlBatching, HundredViewsOnEveryMethodMatchMultipass) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    const Rig rig = rowOf(scene, 100);
    ASSERT_EQ(rig.viewCount(), 100);
    const RenderSettings s = smallSettings();
    auto ref = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    ASSERT_EQ(ref->color.size(), 100u);
    const auto limits = perPassLimits();
    for (const std::string& m : batchingMethods()) {
        auto r = backend().render(scene, rig, s, m);
        ASSERT_TRUE(r) << m << ": " << r.status().message();
        expectWithinGlExact(*ref, *r, m);
        const auto stats = backend().lastStats();
        ASSERT_TRUE(stats) << m;
        const int limit = limits.count(m) ? limits.at(m) : kMaxViews;
        EXPECT_EQ(stats->passes, (100 + limit - 1) / limit) << m << " (" << limit << " a pass)";
    }
}

// One view over each limit: two passes, the second of one view; every view is the same
// method's image of that view rendered without batching (the views of each pass as a rig of
// their own), pixel for pixel, colour and depth.
TEST(GlBatching, JustOverTheLimitIsTheUnbatchedImages) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    const RenderSettings s = smallSettings();
    const auto limits = perPassLimits();
    if (limits.empty()) MVR_SKIP(NotApplicable) << "no method here batches below kMaxViews";
    for (const auto& [m, limit] : limits) {
        const int n = limit + 1;
        const Rig rig = rowOf(scene, n);
        auto r = backend().render(scene, rig, s, m);
        ASSERT_TRUE(r) << m << ": " << r.status().message();
        ASSERT_TRUE(backend().lastStats());
        EXPECT_EQ(backend().lastStats()->passes, 2) << m;
        ASSERT_EQ(r->color.size(), static_cast<std::size_t>(n));
        auto first = backend().render(scene, slice(rig, 0, limit), s, m);
        ASSERT_TRUE(first) << m << ": " << first.status().message();
        EXPECT_EQ(backend().lastStats()->passes, 1) << m;
        auto last = backend().render(scene, slice(rig, limit, 1), s, m);
        ASSERT_TRUE(last) << m << ": " << last.status().message();
        for (int v = 0; v < n; ++v) {
            const RenderOutput& one = v < limit ? *first : *last;
            const std::size_t i = static_cast<std::size_t>(v < limit ? v : 0);
            EXPECT_EQ(r->color[v].rgba, one.color[i].rgba) << m << " view " << v;
            EXPECT_EQ(r->depth[v].depth, one.depth[i].depth) << m << " view " << v;
        }
        auto ref = backend().render(scene, rig, s, "multipass");
        ASSERT_TRUE(ref) << ref.status().message();
        expectWithinGlExact(*ref, *r, m);
    }
}

// RenderSettings::depth = false: no depth images come back (RenderOutput::depth is empty),
// and the colour is the same, byte for byte, on every method, batched or not.
TEST(GlBatching, DepthNotAskedIsNotReadBack) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    const Rig rig = rowOf(scene, 20);
    RenderSettings s = smallSettings();
    for (const std::string& m : batchingMethods()) {
        auto with = backend().render(scene, rig, s, m);
        s.depth = false;
        auto without = backend().render(scene, rig, s, m);
        s.depth = true;
        ASSERT_TRUE(with && without) << m;
        EXPECT_EQ(with->depth.size(), 20u) << m;
        EXPECT_TRUE(without->depth.empty()) << m;
        ASSERT_EQ(without->color.size(), 20u) << m;
        for (std::size_t v = 0; v < 20; ++v)
            EXPECT_EQ(with->color[v].rgba, without->color[v].rgba) << m << " view " << v;
    }
}

// Without depth images each view's depth range is measured on the GPU (RenderOutput::
// depthRange): the nearest and farthest drawn depth of the read-back images, bit for bit, on
// every target kind, in one pass and across passes (40 views: two targets of 32 layers or more
// than a geometry-shader pass); a rig looking away from the scene drew nothing in any view.
class DepthRanges : public testing::TestWithParam<const char*> {
protected:
    void SetUp() override {
        if (*GetParam()) setenv("MVR_GL_DEPTH_RANGES", GetParam(), 1);
    }
    void TearDown() override { unsetenv("MVR_GL_DEPTH_RANGES"); }
};

// "": the driver's own path (software: read into scratch memory, reduced on the CPU);
// "gpu": the compute reduction hardware drivers use, forced.
INSTANTIATE_TEST_SUITE_P(GlBatching, DepthRanges, testing::Values("", "gpu"),
                         [](const auto& info) {
                             return std::string(*info.param ? info.param : "driver_default");
                         });

TEST_P(DepthRanges, WithoutDepthImagesAreTheImagesRanges) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    RenderSettings s = smallSettings();
    for (int views : {3, 40}) {
        const Rig rig = rowOf(scene, views);
        for (const std::string& m : batchingMethods()) {
            s.depth = true;
            auto with = backend().render(scene, rig, s, m);
            s.depth = false;
            auto without = backend().render(scene, rig, s, m);
            ASSERT_TRUE(with && without) << m;
            ASSERT_EQ(with->depth.size(), std::size_t(views)) << m;
            EXPECT_TRUE(with->depthRange.empty()) << m;
            ASSERT_TRUE(without->depth.empty()) << m;
            ASSERT_EQ(without->depthRange.size(), std::size_t(views)) << m;
            for (int v = 0; v < views; ++v) {
                float nearest = 1.0f, farthest = 0.0f;
                for (float d : with->depth[std::size_t(v)].depth) {
                    if (d < 1.0f) nearest = std::min(nearest, d), farthest = std::max(farthest, d);
                }
                ASSERT_LT(nearest, farthest) << m << " view " << v << " drew the scene";
                const DepthRange& r = without->depthRange[std::size_t(v)];
                EXPECT_EQ(r.nearest, nearest) << m << " view " << v << " of " << views;
                EXPECT_EQ(r.farthest, farthest) << m << " view " << v << " of " << views;
                EXPECT_TRUE(r.drew()) << m;
            }
        }
    }
    Rig away = rowOf(scene, 4);
    for (View& v : away.views) v.viewFromWorld = glm::rotate(glm::mat4(1.0f), glm::pi<float>(),
                                                             glm::vec3(0, 1, 0)) * v.viewFromWorld;
    s.depth = false;
    for (const std::string& m : batchingMethods()) {
        auto r = backend().render(scene, away, s, m);
        ASSERT_TRUE(r) << m << ": " << r.status().message();
        ASSERT_EQ(r->depthRange.size(), 4u) << m;
        for (const DepthRange& d : r->depthRange) EXPECT_FALSE(d.drew()) << m;
    }
}

// A driver that declares more geometry-shader output than it links (NVIDIA: "can only emit 78
// vertices of this size" where GL_MAX_GEOMETRY_OUTPUT_VERTICES allows 42 views): reproduced by
// MVR_GL_GS_EMIT_LIMIT. gs-layered and viewport-array then draw passes of the views the driver
// links (emit / 3), info says so, and the images are still gl:multipass's.
class GsEmitLimit : public testing::TestWithParam<int> {
protected:
    void SetUp() override { setenv("MVR_GL_GS_EMIT_LIMIT", std::to_string(GetParam()).c_str(), 1); }
    void TearDown() override { unsetenv("MVR_GL_GS_EMIT_LIMIT"); }
};

TEST_P(GsEmitLimit, GeometryShaderMethodsBatchAtWhatTheDriverLinks) {
    MVR_SKIP_WITHOUT_GL();
    const int emit = GetParam();
    auto b = makeGlBackend();
    const Scene& scene = defaultScene();
    const Rig rig = rowOf(scene, 45);
    const RenderSettings s = smallSettings();
    auto ref = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    std::map<std::string, std::string> lines;
    for (const std::string& line : b->info()) {
        const std::size_t colon = line.find(':');
        if (line.rfind("method ", 0) == 0 && colon != std::string::npos)
            lines[line.substr(7, colon - 7)] = line;
    }
    for (const std::string m : {"gs-layered", "viewport-array"}) {
        if (!b->supports(m)) continue;
        auto r = b->render(scene, rig, s, m);
        ASSERT_TRUE(r) << m << ": " << r.status().message();
        expectWithinGlExact(*ref, *r, m);
        // Each pass draws at most emit / 3 views (3 vertices a view): at least that many passes.
        const int linked = emit / 3;
        ASSERT_TRUE(b->lastStats());
        EXPECT_GE(b->lastStats()->passes, (45 + linked - 1) / linked) << m;
        // info() names the count the driver links when it is below the declared one.
        const std::string& line = lines[m];
        const std::regex declared(R"(declared (\d+))");
        std::smatch d;
        ASSERT_TRUE(std::regex_search(line, d, declared)) << line;
        if (std::atoi(d[1].str().c_str()) > linked) {
            EXPECT_NE(line.find(fmt::format("the driver links {}", linked)), std::string::npos)
                << line;
        }
    }
}

// 78: NVIDIA's figure (26 views, below the 32 layers a target holds; viewport-array's 16
// viewports stay below it); 24: 8 views, below both.
INSTANTIATE_TEST_SUITE_P(Gl, GsEmitLimit, testing::Values(78, 24));

// auto measures the exact methods, batched ones among them, and renders 100 views.
TEST(GlBatching, AutoRendersManyViews) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = defaultScene();
    const Rig rig = rowOf(scene, 72);
    auto r = backend().render(scene, rig, smallSettings(), "auto");
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_EQ(r->color.size(), 72u);
    EXPECT_EQ(r->note.find("view limit"), std::string::npos) << r->note;
}

}  // namespace
}  // namespace mvr::gl::test
