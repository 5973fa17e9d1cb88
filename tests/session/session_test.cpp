// mvr::session: a recipe prepared as `mvr render` prepares it (defaults, a display preset's
// values and outputs, the options' messages) and written by writeOutputs(), the one writer of a
// frame's files.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/core/framing.h"
#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"
#include "mvr/session/surfaces.h"

namespace mvr::session {
namespace {

TEST(SessionPrepare, DefaultRecipeIsTheDefaultRender) {
    RenderRecipe recipe;
    recipe.size = "64x48";
    auto p = prepare(recipe);
    ASSERT_TRUE(p) << p.status().message();
    EXPECT_EQ(p->sceneName, "default scene");
    EXPECT_EQ(p->rig.viewCount(), 2);
    EXPECT_EQ(p->settings.width, 64);
    EXPECT_EQ(p->settings.height, 48);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    auto framed = frameScene(makeDefaultScene(), FramingParams{}, settings);
    ASSERT_TRUE(framed);
    EXPECT_EQ(p->rig.interaxial, framed->rig.interaxial);
    EXPECT_EQ(p->rig.convergence, framed->rig.convergence);
    EXPECT_TRUE(p->formats.empty());
    RenderRecipe unsized;  // no size: 1024x768
    auto q = prepare(unsized);
    ASSERT_TRUE(q);
    EXPECT_EQ(q->settings.width, 1024);
    EXPECT_EQ(q->settings.height, 768);
}

TEST(SessionPrepare, BadValuesNameTheirOption) {
    auto message = [](const RenderRecipe& r) {
        auto p = prepare(r);
        EXPECT_FALSE(p);
        EXPECT_EQ(p ? ErrorCode::Internal : p.status().code(), ErrorCode::Usage);
        return p ? std::string() : p.status().message();
    };
    RenderRecipe r;
    r.views = 0;
    EXPECT_EQ(message(r), "--views 0: view count 0 is out of range (expected 1..128)");
    r = {};
    r.fov = -1.0;
    EXPECT_EQ(message(r), "--fov -1 is out of range (expected 0 < fov < 180 degrees)");
    r = {};
    r.size = "12";
    EXPECT_EQ(message(r), "--size '12' is not of the form WxH (e.g. 1024x768)");
    r = {};
    r.grid = 3;
    EXPECT_EQ(message(r), "--grid 3 needs a model file (the default scene is not gridded)");
    r = {};
    r.separationAuto = true;
    EXPECT_NE(message(r).find("--separation auto needs --screen-width"), std::string::npos);
}

TEST(SessionPrepare, DisplayPresetFillsWhatIsNotGiven) {
    RenderRecipe r;
    r.display = "portrait";
    auto p = prepare(r);
    ASSERT_TRUE(p) << p.status().message();
    EXPECT_EQ(p->rig.viewCount(), 48);
    EXPECT_EQ(p->viewConeDegrees, 40.0f);
    EXPECT_EQ(p->formats, std::vector<std::string>{"quilt"});
    EXPECT_EQ(p->compose.quiltColumns, 8);
    EXPECT_EQ(p->compose.quiltRows, 6);
    r.views = 3;  // given: the preset does not override it (nor its quilt, then)
    r.size = "30x40";
    p = prepare(r);
    ASSERT_TRUE(p) << p.status().message();
    EXPECT_EQ(p->rig.viewCount(), 3);
    EXPECT_EQ(p->settings.width, 30);
    EXPECT_EQ(p->compose.quiltColumns, 0);
}

TEST(SessionPrepare, ModelWarningsGoToTheSink) {
    RenderRecipe r;
    r.models = {"/nonexistent/model.obj"};
    std::vector<std::string> lines;
    auto p = prepare(r, [&](const std::string& l) { lines.push_back(l); });
    ASSERT_FALSE(p);
    EXPECT_EQ(p.status().code(), ErrorCode::Input);
}

std::vector<std::string> names(const WrittenFrame& w) {
    std::vector<std::string> out;
    for (const std::string& p : w.paths) out.push_back(std::filesystem::path(p).filename());
    return out;
}

RenderOutput renderSmall(const Prepared& p, Backend& backend) {
    auto out = backend.render(p.scene, p.rig, p.settings, backend.defaultMethod());
    EXPECT_TRUE(out) << out.status().message();
    return out ? std::move(out).value() : RenderOutput{};
}

TEST(SessionOutputs, OneWriterForEveryFrame) {
    const auto dir = std::filesystem::path(testing::TempDir()) / "mvr_session_outputs";
    std::filesystem::remove_all(dir);
    auto backend = makeBackend("soft", {.threads = 2});
    ASSERT_TRUE(backend);
    RenderRecipe r;
    r.size = "32x24";
    auto p = prepare(r);
    ASSERT_TRUE(p);
    const RenderOutput pair = renderSmall(*p, **backend);
    FrameOutputs outputs{{"sbs", "jps"}, true, {}};
    auto w = writeOutputs(dir / "pair", pair, p->rig, outputs, backend->get(), "sbs");
    ASSERT_TRUE(w) << w.status().message();
    EXPECT_EQ(names(*w), (std::vector<std::string>{"view-0.png", "depth-0.png", "view-1.png",
                                                   "depth-1.png", "anaglyph.png", "sbs.png",
                                                   "jps.jps"}));
    // The anaglyph is Dubois' red-cyan of the pair; the kept image is the file's.
    auto anaglyph = readPng(dir / "pair" / "anaglyph.png");
    auto expected = composite::compose(composite::kDefaultAnaglyph, pair.color, {});
    ASSERT_TRUE(anaglyph && expected);
    EXPECT_EQ(anaglyph->rgba, expected->rgba);
    ASSERT_TRUE(w->kept);
    auto sbs = readPng(dir / "pair" / "sbs.png");
    ASSERT_TRUE(sbs);
    EXPECT_EQ(w->kept->rgba, sbs->rgba);

    r.views = 3;  // no anaglyph for three views; no backend: composed on the CPU
    p = prepare(r);
    ASSERT_TRUE(p);
    const RenderOutput three = renderSmall(*p, **backend);
    w = writeOutputs(dir / "three", three, p->rig, {{"quilt"}, false, {}}, nullptr);
    ASSERT_TRUE(w) << w.status().message();
    EXPECT_EQ(names(*w).size(), 4u);
    EXPECT_FALSE(std::filesystem::exists(dir / "three" / "anaglyph.png"));
    EXPECT_FALSE(w->kept);

    std::filesystem::create_directories(dir);
    { std::ofstream(dir / "blocker") << "a file"; }
    w = writeOutputs(dir / "blocker" / "out", three, p->rig, {}, nullptr);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.status().code(), ErrorCode::Output);
    EXPECT_NE(w.status().message().find("cannot create output directory"), std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST(SessionSurfaces, BuildsAndRefuses) {
    SurfaceRecipe s;
    s.sky = "gradient";
    s.labels = {"HI@0.5,0.5"};
    auto built = buildSurfaces(s);
    ASSERT_TRUE(built) << built.status().message();
    EXPECT_TRUE(built->any());
    s.letterbox = 60;
    auto bad = buildSurfaces(s);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(), "--letterbox 60: must be in (0, 50) percent of the height");
}

}  // namespace
}  // namespace mvr::session

namespace mvr::session {
namespace {

// writeOutputs() encodes a frame's PNGs on workers: every job runs once, and the error is the
// first in the jobs' order, whichever finishes first.
TEST(SessionParallelWrites, EveryJobRunsOnceAndTheFirstErrorInOrderWins) {
    std::vector<std::atomic<int>> runs(40);
    std::vector<std::function<Status()>> jobs;
    for (int i = 0; i < 40; ++i) {
        jobs.push_back([&runs, i]() -> Status {
            ++runs[std::size_t(i)];
            if (i == 7 || i == 31) return outputError(fmt::format("job {}", i));
            return {};
        });
    }
    for (int threads : {1, 2, 5, 0}) {
        for (auto& r : runs) r = 0;
        const Status s = runParallel(jobs, threads);
        ASSERT_FALSE(s);
        EXPECT_EQ(s.message(), "job 7") << threads << " threads";
        for (auto& r : runs) EXPECT_EQ(r.load(), 1);
    }
    EXPECT_TRUE(runParallel({}, 4));
}

}  // namespace
}  // namespace mvr::session
