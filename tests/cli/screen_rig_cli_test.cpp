// `mvr render --rig screen` end to end: a physical screen and tracked eyes in mm (the geometry
// itself is tested in tests/core/screen_rig_test.cpp), and every refusal as one error line.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"
#include "mvr/core/image.h"
#include "mvr/io/png.h"

namespace mvr {
namespace {

class ScreenRigCli : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-screen-cli-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(mDir);
        std::ofstream(mDir / "pyramid.obj")
            << "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv 0 1.5 0\n"
               "f 1 2 3\nf 1 3 4\nf 1 5 2\nf 2 5 3\nf 3 5 4\nf 4 5 1\n";
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    test::CliRun run(const std::string& args) const { return test::runMvr(mDir, args); }

    void expectError(const std::string& args, const std::string& needle) const {
        const test::CliRun r = run("render pyramid.obj --size 64x36 -q -o out " + args);
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;
        EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(mDir / "out")) << args;
    }

    /// The number of pixels where `a` and `b` differ.
    static int differing(const Image& a, const Image& b) {
        int n = 0;
        for (std::size_t i = 0; i < a.rgba.size(); ++i) n += a.rgba[i] != b.rgba[i];
        return n;
    }

    std::filesystem::path mDir;
};

TEST_F(ScreenRigCli, TwoEyesOfTheDefaultScreenAndAMovedHead) {
    test::CliRun r = run("render pyramid.obj --rig screen --size 96x54 -q -o a");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");  // 96x54 is the default 597.9x336.3 mm screen's aspect: no stretch note
    auto l = readPng(mDir / "a/view-0.png"), rr = readPng(mDir / "a/view-1.png");
    ASSERT_TRUE(l && rr);
    EXPECT_EQ(l->width, 96);
    EXPECT_EQ(l->height, 54);
    EXPECT_GT(differing(*l, *rr), 20);  // two eyes 63 mm apart see different images
    r = run("render pyramid.obj --rig screen --size 96x54 --head 200,0,600 -q -o b");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto l2 = readPng(mDir / "b/view-0.png");
    ASSERT_TRUE(l2);
    EXPECT_GT(differing(*l, *l2), 20);  // the head moved 200 mm right: the view moved
    r = run("render pyramid.obj --rig screen --size 64x64 -o c");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning: the views are 64x64"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--size 64x36 keeps the pixels square"), std::string::npos) << r.err;
    // The comfort line's budget is the eyes' own separation: 70 mm, half of it at 60 cm.
    r = run("render pyramid.obj --rig screen --ipd-mm 70 --size 96x54 -o d");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("budget 3.50 cm (desktop: half the 7 cm eye separation)"), std::string::npos)
        << r.out;
}

// The tracked monitors' presets: --rig screen on their screen in mm, the side by side the SR
// weaver takes, the comfort report in cm of that screen; another --rig overrides the screen.
TEST_F(ScreenRigCli, TrackedMonitorPresetsAreTheirScreens) {
    test::CliRun r = run("render pyramid.obj --display odyssey-3d --size 192x108 -q -o preset "
                         "--report-json preset.json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = run("render pyramid.obj --rig screen --screen-mm 597.7x336.2 --size 192x108 --format sbs "
            "-q -o given");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto preset = readPng(mDir / "preset/sbs.png"), given = readPng(mDir / "given/sbs.png");
    ASSERT_TRUE(preset && given);
    EXPECT_EQ(preset->width, 384);
    EXPECT_EQ(differing(*preset, *given), 0);
    const std::string report = test::slurp(mDir / "preset.json");
    EXPECT_NE(report.find("\"width_cm\": 59.77"), std::string::npos) << report;
    EXPECT_NE(report.find("\"viewing_distance_cm\": 60"), std::string::npos) << report;
    r = run("render pyramid.obj --display odyssey-3d --rig toein --size 192x108 -q -o toein");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto toein = readPng(mDir / "toein/sbs.png");
    ASSERT_TRUE(toein);
    EXPECT_GT(differing(*toein, *preset), 20);
    r = run("info --displays");
    for (const char* name : {"odyssey-3d", "spatiallabs-view", "sony-sr1", "sony-sr2"})
        EXPECT_NE(r.out.find(name), std::string::npos) << name;
    EXPECT_NE(r.out.find("596.7x335.7 mm"), std::string::npos) << r.out;
}

// Sony's panels lean back 45 degrees: the presets render the tilted screen, the same as the
// corners computed here (a 345.4 x 194.3 mm panel about its centre: up (0, cos, -sin)) and as
// --screen-tilt 45; upright, the eyes see something else.
TEST_F(ScreenRigCli, SonysPresetsAreTiltedScreens) {
    const std::string common = "render pyramid.obj --size 192x108 --format sbs -q ";
    test::CliRun r = run(common + "--display sony-sr1 -o preset");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = run(common + "--rig screen --screen-mm 345.4x194.3 --screen-tilt 45 -o tilt");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const double w = 345.4 / 2, h = 194.3 / 2, c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
    // The default head: 600 mm from the panel's centre along its normal (0, s, c).
    r = run(common + fmt::format("--rig screen --screen-corners '{0},{1},{2};{3},{1},{2};{0},{4},{5}' "
                                 "--head 0,{6},{7} -o corners",
                                 -w, -h * c, h * s, w, h * c, -h * s, 600 * s, 600 * c));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = run(common + "--rig screen --screen-mm 345.4x194.3 -o upright");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto preset = readPng(mDir / "preset/sbs.png"), tilt = readPng(mDir / "tilt/sbs.png");
    auto corners = readPng(mDir / "corners/sbs.png"), upright = readPng(mDir / "upright/sbs.png");
    ASSERT_TRUE(preset && tilt && corners && upright);
    EXPECT_EQ(differing(*preset, *tilt), 0);
    EXPECT_LE(differing(*preset, *corners), 4);  // the corners as printed: rounded to 6 digits
    EXPECT_GT(differing(*preset, *upright), 100);
}

TEST_F(ScreenRigCli, NonsenseIsOneErrorLineNamingTheOption) {
    expectError("--rig screen --views 3", "--rig screen renders two views (the eyes), not --views 3");
    expectError("--rig screen --view-grid 2x1", "--rig screen excludes --view-grid 2x1");
    expectError("--rig screen --separation 0.1", "--rig screen excludes --separation 0.1");
    expectError("--screen-mm 600x340", "need --rig screen");
    expectError("--head 0,0,500", "need --rig screen");
    expectError("--rig screen --screen-mm 0x5", "--screen-mm 0x5: out of range");
    expectError("--rig screen --screen-mm big", "--screen-mm big: expected WxH in millimetres");
    expectError("--rig screen --ipd-mm -1", "--ipd-mm -1 is out of range");
    expectError("--rig screen --eyes 0,0,500", "--eyes 0,0,500: expected left;right");
    expectError("--rig screen --eyes '-30,0,500;30,x,500'", "'30,x,500' is not X,Y,Z");
    expectError("--rig screen --eyes '-30,0,500;30,0,500' --head 0,0,500", "--eyes excludes --head");
    expectError("--rig screen --eyes '-30,0,-500;30,0,-500'", "--eyes -30,0,-500;30,0,-500");
    expectError("--rig screen --head 0,0,-600", "--head 0,0,-600");
    expectError("--rig screen --screen-corners '0,0,0;600,0,0;100,300,0'", "--screen-corners");
    expectError("--rig screen --screen-corners '0,0,0;600,0,0;0,300,0' --screen-mm 600x300",
                "--screen-corners excludes --screen-mm 600x300");
    expectError("--rig screen --screen-tilt 90", "--screen-tilt 90 is out of range (expected -85 .. 85 degrees)");
    expectError("--rig screen --screen-corners '0,0,0;600,0,0;0,300,0' --screen-tilt 10",
                "--screen-corners excludes --screen-tilt 10");
    expectError("--screen-tilt 45", "need --rig screen");
}

}  // namespace
}  // namespace mvr
