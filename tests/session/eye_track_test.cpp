// --rig screen's eye track (mvr/session/screen.h): the CSV a tracker logs read and checked, the
// eyes interpolated between its rows (computed here), and each frame of a sequence rendered
// with the rig a still gets from the same eyes given by --eyes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <glm/glm.hpp>

#include "mvr/session/prepare.h"
#include "mvr/session/screen.h"
#include "mvr/session/sequence.h"

namespace mvr::session {
namespace {

namespace fs = std::filesystem;

class EyeTrackTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               fmt::format("mvr-eye-track-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(mDir / name) << text;
        return (mDir / name).string();
    }
    fs::path mDir;
};

TEST_F(EyeTrackTest, RowsAreInterpolatedAndHeldAtTheEnds) {
    const ScreenCorners screen = screenOfSize(600.0f, 340.0f);
    const std::string file = write("eyes.csv",
                                   "t,lx,ly,lz,rx,ry,rz\r\n# a comment\n\n"
                                   "0.5,-30,0,600,30,0,600\n"
                                   "1.5,70,20,500,130,20,500\n");
    auto track = readEyeTrack(file, screen);
    ASSERT_TRUE(track) << track.status().message();
    ASSERT_EQ(track->samples.size(), 2u);
    EXPECT_DOUBLE_EQ(track->duration(), 1.5);
    // Before the first row and after the last: held.
    EXPECT_EQ(track->at(0.0, screen).leftEye, glm::vec3(-30, 0, 600));
    EXPECT_EQ(track->at(9.0, screen).rightEye, glm::vec3(130, 20, 500));
    // A quarter of the way: 0.75 of the first row and 0.25 of the second.
    const ScreenEyes e = track->at(0.75, screen);
    const glm::vec3 left = 0.75f * glm::vec3(-30, 0, 600) + 0.25f * glm::vec3(70, 20, 500);
    const glm::vec3 right = 0.75f * glm::vec3(30, 0, 600) + 0.25f * glm::vec3(130, 20, 500);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(e.leftEye[i], left[i], 1e-4f) << i;
        EXPECT_NEAR(e.rightEye[i], right[i], 1e-4f) << i;
    }
    EXPECT_EQ(e.screen.lowerLeft, screen.lowerLeft);
}

TEST_F(EyeTrackTest, BadFilesNameTheFileAndTheLine) {
    const ScreenCorners screen = screenOfSize(600.0f, 340.0f);
    auto message = [&](const std::string& text) {
        auto t = readEyeTrack(write("bad.csv", text), screen);
        EXPECT_FALSE(t) << text;
        EXPECT_EQ(t ? ErrorCode::Internal : t.status().code(), ErrorCode::Input) << text;
        const std::string m = t ? std::string() : t.status().message();
        const std::string prefix = "--eye-track " + (mDir / "bad.csv").string() + ": ";
        EXPECT_EQ(m.rfind(prefix, 0), 0u) << m;
        return m.substr(std::min(m.size(), prefix.size()));
    };
    EXPECT_EQ(message("0,-30,0,600,30,0\n"),
              "line 1: expected 7 numbers t,lx,ly,lz,rx,ry,rz, got 6");
    EXPECT_EQ(message("t,l\n0,-30,0,600,30,0,600\nx,1,2,3,4,5,6\n"),
              "line 3: 'x,1,2,3,4,5,6' is not numbers t,lx,ly,lz,rx,ry,rz");
    EXPECT_EQ(message("1,-30,0,600,30,0,600\n1,-30,0,600,30,0,600\n"),
              "line 2: time 1 does not follow 1 (times must increase)");
    EXPECT_EQ(message("0,-30,0,nan,30,0,600\n"), "line 1: nan is not a finite number within 1e6");
    EXPECT_NE(message("0,-30,0,-600,30,0,-600\n").find("line 1"), std::string::npos);
    EXPECT_EQ(message("# nothing\n"), "no samples (rows t,lx,ly,lz,rx,ry,rz)");
    auto missing = readEyeTrack((mDir / "none.csv").string(), screen);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.status().message(),
              "--eye-track " + (mDir / "none.csv").string() + ": file not found");
}

/// The view matrices of a prepared --rig screen recipe.
std::vector<glm::mat4> screenViews(const RenderRecipe& r) {
    auto p = prepare(r);
    EXPECT_TRUE(p) << p.status().message();
    std::vector<glm::mat4> out;
    if (p)
        for (const auto& v : p->rig.views) out.push_back(v.clipFromView * v.viewFromWorld);
    return out;
}

void expectSameViews(const std::vector<glm::mat4>& a, const std::vector<glm::mat4>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t v = 0; v < a.size(); ++v)
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                EXPECT_NEAR(a[v][i][j], b[v][i][j], 1e-4f * (1.0f + std::abs(b[v][i][j])))
                    << v << " [" << i << "][" << j << "]";
}

// Frame f of a sequence has the rig of a still whose --eyes are the track's eyes at f / fps.
TEST_F(EyeTrackTest, EachFrameHasTheRigOfItsEyes) {
    const std::string file = write("eyes.csv",
                                   "0,-31.5,0,600,31.5,0,600\n"
                                   "2,168.5,40,500,231.5,40,500\n");
    RenderRecipe r;
    r.size = "96x54";
    r.rig = "screen";
    r.screen.eyeTrack = file;
    r.sequence.frames = 5;
    r.sequence.fps = 2.0;
    auto p = prepare(r);
    ASSERT_TRUE(p) << p.status().message();
    ASSERT_TRUE(p->eyeTrack);
    auto plan = planSequence(r.sequence);
    ASSERT_TRUE(plan);
    FrameStepper stepper(*p, *plan);
    for (int f : {0, 1, 3, 4}) {
        auto rig = stepper.advance(f);
        ASSERT_TRUE(rig) << rig.status().message();
        const float w = std::min(1.0f, f / 2.0f / 2.0f);  // t = f / fps over the 2 s between rows
        const glm::vec3 l = glm::mix(glm::vec3(-31.5f, 0, 600), glm::vec3(168.5f, 40, 500), w);
        const glm::vec3 rr = glm::mix(glm::vec3(31.5f, 0, 600), glm::vec3(231.5f, 40, 500), w);
        RenderRecipe still;
        still.size = "96x54";
        still.rig = "screen";
        still.screen.eyes = fmt::format("{},{},{};{},{},{}", l.x, l.y, l.z, rr.x, rr.y, rr.z);
        std::vector<glm::mat4> views;
        for (const auto& v : rig->views) views.push_back(v.clipFromView * v.viewFromWorld);
        SCOPED_TRACE(fmt::format("frame {}", f));
        expectSameViews(views, screenViews(still));
    }
}

// The SR runtimes' factors: --depth-factor 2 doubles the eyes' distance about their midpoint,
// --look-around 0.5 halves the head's offset from the default head (0, 0, 600), for fixed
// eyes and for a track's.
TEST_F(EyeTrackTest, DepthAndLookAroundFactorsMoveTheEyesAsComputed) {
    RenderRecipe r;
    r.size = "96x54";
    r.rig = "screen";
    r.screen.eyes = "-21.5,10,600;41.5,10,600";  // midpoint (10, 10, 600), 63 mm apart
    r.screen.depthFactor = 2.0;
    r.screen.lookAround = 0.5;
    RenderRecipe expected = r;
    expected.screen.depthFactor.reset();
    expected.screen.lookAround.reset();
    // midpoint (5, 5, 600), half distance 63
    expected.screen.eyes = "-58,5,600;68,5,600";
    expectSameViews(screenViews(r), screenViews(expected));
    // A track's eyes, the same factors, frame 0.
    r.screen.eyes.clear();
    r.screen.eyeTrack = write("eyes.csv", "0,-21.5,10,600,41.5,10,600\n");
    r.sequence.frames = 1;
    expectSameViews(screenViews(r), screenViews(expected));
    // Out of range: one message naming the option and value.
    r.screen.depthFactor = 0.0;
    auto bad = prepare(r);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(), "--depth-factor 0 is out of range (expected > 0 .. 10)");
    r.screen.depthFactor = 1.0;
    r.screen.lookAround = -1.0;
    bad = prepare(r);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(), "--look-around -1 is out of range (expected 0 .. 10)");
}

TEST_F(EyeTrackTest, ATrackNeedsASequenceAndExcludesFixedEyes) {
    const std::string file = write("eyes.csv", "0,-31.5,0,600,31.5,0,600\n");
    RenderRecipe r;
    r.size = "96x54";
    r.rig = "screen";
    r.screen.eyeTrack = file;
    auto still = prepare(r);
    ASSERT_FALSE(still);
    EXPECT_EQ(still.status().message(),
              fmt::format("--eye-track {} needs a sequence (--frames F: frame f takes the eyes at "
                          "time f/--fps)",
                          file));
    r.sequence.frames = 2;
    r.screen.head = "0,0,500";
    auto both = prepare(r);
    ASSERT_FALSE(both);
    EXPECT_EQ(both.status().message(), "--eye-track excludes --head");
    r.screen.head.clear();
    r.rig = "offaxis";
    auto noScreen = prepare(r);
    ASSERT_FALSE(noScreen);
    EXPECT_NE(noScreen.status().message().find("need --rig screen"), std::string::npos);
}

}  // namespace
}  // namespace mvr::session
