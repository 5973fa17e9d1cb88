// `mvr view` end to end, as a user runs it: the built `mvr` binary in a window on an Xvfb
// server (Mesa: GLX for the window, EGL llvmpipe for the gl backend) started by this test.
//
// What is checked:
//  - the screenshot of a few frames equals `mvr render` of the same view and format;
//  - scripted keys change what is shown (separation, method, wireframe) and the HUD is drawn
//    at screen depth (the same pixels in both eyes of a side-by-side frame);
//  - no display → "error: mvr view: …" and exit 3; a bad --script → exit 1; quad-buffer
//    without a stereo visual → a one-line message and the anaglyph.
//
// Tolerance for screenshot vs `mvr render`: every channel within 1/255. The two runs use the
// same backend code on the same driver, and the window shows the composed frame 1:1
// (texelFetch, no filtering) on a 24-bit visual. What may differ is where the anaglyph is
// mixed: on the GPU by composite::anaglyphGlsl() (the viewer's default; `mvr render --backend
// gl` too, through gl::composeGpu) or on the CPU by composite::compose() — GPU pow() vs the
// CPU's sRGB tables, at most 1/255 apart (src/composite/README.md). Measured on llvmpipe:
// --compose gpu identical to `mvr render --backend gl`, --compose cpu 1 pixel off by 1/255;
// the soft-backend sbs frame (CPU on both sides) identical.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "../gl/engine_fixture.h"

#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "mvr_test_support.h"

extern char** environ;

namespace mvr {
namespace {

namespace fs = std::filesystem;

using test::CliRun;

std::string envOr(const char* name, const char* fallback) {
    const char* v = std::getenv(name);
    return v && *v ? v : fallback;
}

bool onPath(const std::string& program) {
    const std::string path = envOr("PATH", "/usr/bin:/bin");
    std::size_t start = 0;
    while (start <= path.size()) {
        std::size_t end = path.find(':', start);
        if (end == std::string::npos) end = path.size();
        if (::access((fs::path(path.substr(start, end - start)) / program).c_str(), X_OK) == 0) {
            return true;
        }
        start = end + 1;
    }
    return false;
}

/// An Xvfb server on a free display number (Xvfb picks it: -displayfd), for the whole suite.
class Xvfb {
public:
    bool start(std::string& why) {
        if (!onPath("Xvfb")) {
            why = "Xvfb is not installed (Debian: xvfb)";
            return false;
        }
        int fds[2];
        if (::pipe(fds) != 0) {
            why = "pipe() failed";
            return false;
        }
        const std::string fd = std::to_string(fds[1]);
        const char* argv[] = {"Xvfb",         "-displayfd", fd.c_str(), "-screen", "0",
                              "1280x1024x24", "-nolisten",  "tcp",      nullptr};
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addclose(&actions, fds[0]);
        posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
        const int rc =
            posix_spawnp(&mPid, "Xvfb", &actions, nullptr, const_cast<char**>(argv), environ);
        posix_spawn_file_actions_destroy(&actions);
        ::close(fds[1]);
        if (rc != 0) {
            ::close(fds[0]);
            mPid = -1;
            why = "cannot start Xvfb";
            return false;
        }
        // Xvfb writes the display number and a newline once it accepts connections.
        std::string number;
        pollfd p{fds[0], POLLIN, 0};
        while (::poll(&p, 1, 15000) > 0) {
            char c = 0;
            if (::read(fds[0], &c, 1) != 1 || c == '\n') break;
            number += c;
        }
        ::close(fds[0]);
        if (number.empty()) {
            why = "Xvfb did not report a display within 15 s";
            stop();
            return false;
        }
        mDisplay = ":" + number;
        return true;
    }
    void stop() {
        if (mPid > 0) {
            ::kill(mPid, SIGTERM);
            ::waitpid(mPid, nullptr, 0);
            mPid = -1;
        }
    }
    const std::string& display() const { return mDisplay; }

private:
    pid_t mPid = -1;
    std::string mDisplay;
};

class ViewCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        sXvfb = new Xvfb;
        if (!sXvfb->start(sWhyNoDisplay)) {
            delete sXvfb;
            sXvfb = nullptr;
        }
    }
    static void TearDownTestSuite() {
        if (sXvfb) sXvfb->stop();
        delete sXvfb;
        sXvfb = nullptr;
    }

    void SetUp() override {
        mvr = ::mvr::test::mvrBinary();
        if (!fs::exists(mvr)) FAIL() << mvr << " not built";
        bunny = fs::path(envOr("MVR_SHARED_DIR", MVR_TEST_SHARED_DIR)) / "models" /
                "stanford-bunny.obj";
        dir = fs::temp_directory_path() /
              fmt::format("mvr-view-test-{}-{}", ::getpid(),
                          ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override {
        if (!dir.empty() && !HasFailure()) fs::remove_all(dir);
    }

    void needDisplay() {
        if (!sXvfb) MVR_SKIP(NoDisplay) << sWhyNoDisplay;
        if (!fs::exists(bunny)) MVR_SKIP(ModelsMissing) << bunny << " not found (set MVR_SHARED_DIR)";
    }

    /// Runs `mvr ARGS` in `dir`, on the test's display (or none with display = false).
    CliRun run(const std::string& args, bool display = true,
               const std::string& extraEnv = "") const {
        const std::string env =
            (display ? fmt::format("DISPLAY='{}'", sXvfb ? sXvfb->display() : "")
                     : std::string("-u DISPLAY")) +
            " " + extraEnv;
        return test::runShell(
            fmt::format("cd '{}' && env {} '{}' {}", dir.string(), env, mvr.string(), args));
    }

    Image read(const fs::path& p) const {
        Result<Image> image = readPng(p);
        EXPECT_TRUE(image) << image.status().message();
        return image ? *image : Image();
    }

    /// Fraction of pixels whose RGB differ by more than `threshold`.
    static double differingFraction(const Image& a, const Image& b, int threshold = 8) {
        const ImageDiff d = compareImages(a, b, threshold);
        return double(d.differingPixels) / double(std::max(1, a.width * a.height));
    }

    std::string model() const { return "'" + bunny.string() + "'"; }

    /// The largest RGB difference between `small` and the same-sized region of `big` whose
    /// top-left corner is (x0, y0).
    static int regionDelta(const Image& big, int x0, int y0, const Image& small) {
        if (x0 < 0 || y0 < 0 || x0 + small.width > big.width || y0 + small.height > big.height)
            return 256;
        int worst = 0;
        for (int y = 0; y < small.height; ++y) {
            for (int x = 0; x < small.width; ++x) {
                const Rgba8 p = big.at(x0 + x, y0 + y), q = small.at(x, y);
                worst = std::max(
                    {worst, std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
            }
        }
        return worst;
    }

    static Xvfb* sXvfb;
    static std::string sWhyNoDisplay;
    fs::path mvr, bunny, dir;
};

Xvfb* ViewCli::sXvfb = nullptr;
std::string ViewCli::sWhyNoDisplay;

TEST_F(ViewCli, NoDisplayIsAnErrorWithExitCode3) {
    const CliRun r = run("view --frames 1", /*display=*/false);
    EXPECT_EQ(r.exitCode, 3) << r.output;
    EXPECT_NE(r.output.find("error: mvr view: cannot open a window"), std::string::npos)
        << r.output;
}

TEST_F(ViewCli, BadScriptIsAUsageError) {
    const CliRun r = run("view --frames 1 --script 'm,nonsense'", /*display=*/false);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("error: --script: token 2 'nonsense'"), std::string::npos) << r.output;
}

TEST_F(ViewCli, ScreenshotMatchesRenderAnaglyph) {
    // Both anaglyph composites of the viewer: on the CPU (composite::compose, as mvr render) and
    // mixed on the GPU by composite::anaglyphGlsl (the default).
    needDisplay();
    const std::string view = model() + " --size 320x240 --backend gl --method multipass";
    CliRun r = run("render " + view + " --format anaglyph-dubois -o render -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image expected = read(dir / "render" / "anaglyph-dubois.png");
    for (const std::string compose : {"cpu", "gpu"}) {
        r = run("view " + view + " --frames 3 --no-hud --compose " + compose +
                " --screenshot shot.png");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("wrote shot.png (320x240)"), std::string::npos) << r.output;
        const Image shot = read(dir / "shot.png");
        ASSERT_EQ(shot.width, expected.width);
        ASSERT_EQ(shot.height, expected.height);
        const ImageDiff d = compareImages(shot, expected);
        std::printf("--compose %s: max delta %d, %ld pixels differ\n", compose.c_str(), d.maxDelta,
                    compareImages(shot, expected, 0).differingPixels);
        EXPECT_LE(d.maxDelta, 1) << compose << ": worst pixel " << d.worstX << "," << d.worstY;
    }
}

TEST_F(ViewCli, ScreenshotMatchesRenderSideBySideFromTheSoftBackend) {
    // A window twice as wide as one view, the CPU backend shown as a texture.
    needDisplay();
    const std::string view = model() + " --size 160x120 --backend soft --method unified";
    CliRun r = run("view " + view + " --format sbs --frames 2 --no-hud --screenshot sbs.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("render " + view + " --format sbs -o render -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image shot = read(dir / "sbs.png");
    const Image expected = read(dir / "render" / "sbs.png");
    ASSERT_EQ(shot.width, 320);
    ASSERT_EQ(shot.height, 120);
    const ImageDiff d = compareImages(shot, expected);
    EXPECT_LE(d.maxDelta, 1) << "worst pixel " << d.worstX << "," << d.worstY;
}

// --rig screen: two presses of 4 move the head 40 mm left; the window then shows what `mvr
// render --head -40,0,600` writes (the eyes' geometry: tests/core/screen_rig_test.cpp).
TEST_F(ViewCli, TheHeadKeysShowTheEyesOfAMovedHead) {
    needDisplay();
    const std::string view = model() + " --rig screen --size 160x90 --backend soft --method unified";
    CliRun r = run("view " + view + " --format sbs --script 4,4 --frames 4 --no-hud --screenshot s.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("render " + view + " --head -40,0,600 --format sbs -o moved -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("render " + view + " --format sbs -o still -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image shot = read(dir / "s.png");
    const Image expected = read(dir / "moved" / "sbs.png");
    ASSERT_EQ(shot.width, 320);
    ASSERT_EQ(shot.height, 90);
    EXPECT_LE(compareImages(shot, expected).maxDelta, 1);
    EXPECT_GT(differingFraction(shot, read(dir / "still" / "sbs.png"), 8), 0.002);  // it moved
    // A ctrl+left drag (scripted head:DX:DY): a 320 px window over a 640 mm screen, so 20 px
    // left and 10 px up move the head 40 mm left and 20 mm up.
    const std::string wide = view + " --screen-mm 640x360";
    r = run("view " + wide + " --format sbs --script head:-20:-10 --frames 3 --no-hud --screenshot d.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("render " + wide + " --head -40,20,600 --format sbs -o dragged -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_LE(compareImages(read(dir / "d.png"), read(dir / "dragged" / "sbs.png")).maxDelta, 1);
    // An eye track replayed (scripted: frame i at i/24 s): frame 24 has the eyes of t = 1 s.
    std::ofstream(dir / "eyes.csv") << "t,lx,ly,lz,rx,ry,rz\n0,-31.5,0,600,31.5,0,600\n"
                                       "1,-71.5,0,600,-8.5,0,600\n";
    r = run("view " + view + " --format sbs --eye-track eyes.csv --frames 25 --no-hud --screenshot t.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_LE(compareImages(read(dir / "t.png"), expected).maxDelta, 1);
    // An eye track without --rig screen is refused.
    r = run("view " + model() + " --eye-track eyes.csv --frames 1", false);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("error: --eye-track eyes.csv needs --rig screen"), std::string::npos)
        << r.output;
}

TEST_F(ViewCli, ScriptedKeysChangeSeparationMethodAndWireframe) {
    needDisplay();
    const std::string view = model() + " --size 240x180 --backend gl --method multipass --no-hud";
    CliRun r = run("view " + view + " --frames 2 --screenshot base.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image base = read(dir / "base.png");

    // Separation: eight '+' presses, 0.25 % of the screen width each: 3.02 % → 5.02 %. The
    // bunny spans about ±0.5 % of parallax around the screen plane, so its edges' colour
    // fringes move by a pixel or two.
    r = run("view " + view + " --frames 9 --script '+,+,+,+,+,+,+,+' --screenshot sep.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("separation 5.02% of screen width"), std::string::npos) << r.output;
    const Image sep = read(dir / "sep.png");
    const double moved = differingFraction(base, sep);
    RecordProperty("separation_differing_fraction", std::to_string(moved));
    std::printf("separation +2%%: %.4f of the pixels differ by > 8/255\n", moved);
    EXPECT_GT(moved, 0.01) << "wider separation should move the colour fringes";

    // Method: 'M' goes back from gl:multipass to the last method, soft:unified; the frame must
    // then be the soft backend's image.
    r = run("view " + view + " --frames 2 --script M --screenshot soft.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("method soft:unified"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("last: soft:unified"), std::string::npos) << r.output;
    r = run("render " + model() +
            " --size 240x180 --backend soft --method unified "
            "--format anaglyph-dubois -o soft -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_LE(
        compareImages(read(dir / "soft.png"), read(dir / "soft" / "anaglyph-dubois.png")).maxDelta,
        1);

    // Wireframe.
    r = run("view " + view + " --frames 2 --script w --screenshot wire.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("wireframe on"), std::string::npos) << r.output;
    const double wire = differingFraction(base, read(dir / "wire.png"));
    std::printf("wireframe: %.4f of the pixels differ by > 8/255\n", wire);
    EXPECT_GT(wire, 0.02);
}

TEST_F(ViewCli, HudIsAtScreenDepthInBothEyes) {
    // In a side-by-side frame the HUD's text pixels must sit at the same place in both halves
    // (zero parallax), while the scene behind them differs between the eyes.
    needDisplay();
    CliRun r =
        run("view " + model() + " --size 200x150 --format sbs --frames 2 --screenshot hud.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image hud = read(dir / "hud.png");
    ASSERT_EQ(hud.width, 400);
    const Rgba8 ink{240, 240, 240, 255};
    int inked = 0;
    for (int y = 0; y < 40; ++y) {
        for (int x = 0; x < 200; ++x) {
            const bool left = hud.at(x, y) == ink, right = hud.at(x + 200, y) == ink;
            EXPECT_EQ(left, right) << "HUD pixel " << x << "," << y << " differs between the eyes";
            inked += left;
        }
    }
    EXPECT_GT(inked, 100) << "no HUD text found";
}

TEST_F(ViewCli, ViewSizeFollowsTheWindow) {
    // Resized to 300x100 in side-by-side: two 150x100 views, separation kept.
    needDisplay();
    const CliRun r =
        run("view --size 160x120 --format sbs --frames 3 --script size:300:100 "
            "--screenshot resized.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("150x100 per view, separation 3.02%"), std::string::npos) << r.output;
    const Image shot = read(dir / "resized.png");
    EXPECT_EQ(shot.width, 300);
    EXPECT_EQ(shot.height, 100);
}

TEST_F(ViewCli, WithoutEglTheDefaultBackendFallsBackToSoft) {
    // libglvnd pointed at no EGL vendor: the gl backend has no context (the window, GLX, does).
    needDisplay();
    const std::string noEgl = "__EGL_VENDOR_LIBRARY_DIRS=/nonexistent";
    CliRun r = run("view --size 160x120 --frames 1", true, noEgl);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("gl backend unavailable (no EGL display"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("last: soft:unified"), std::string::npos) << r.output;
    r = run("view --size 160x120 --frames 1 --backend gl", true, noEgl);
    EXPECT_EQ(r.exitCode, 3) << r.output;
    EXPECT_NE(r.output.find("error: no EGL display"), std::string::npos) << r.output;
}

// N views (issue 13): the viewer steps through the views of a Looking Glass Portrait row and
// shows its quilt. Every picture is checked against `mvr render` of the same options (the soft
// backend on both sides: the same CPU code, so within 1/255 — the bound of the other
// screenshot tests), and the quilt's layout is checked tile by tile by this test's own
// arithmetic: the preset's 8×6 grid, view v in column v % 8 and row v / 8 counted from the
// bottom (Looking Glass: view 0 bottom left), tiles of one view's size.
TEST_F(ViewCli, StepsThroughTheViewsOfAQuilt) {
    needDisplay();
    constexpr int kW = 120, kH = 160, kColumns = 8, kRows = 6, kViews = 48;
    // --aa 1: the viewer takes one sample a pixel, where mvr render's presets take 4.
    const std::string scene = "--display portrait --size 120x160 --aa 1 --backend soft --method unified";
    CliRun r = run("render " + scene + " --write views,composites -o render -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto renderedView = [&](int v) { return read(dir / "render" / fmt::format("view-{}.png", v)); };

    // Single view, stepped: '<' from view 0 wraps to 47, then '>' x3 → 2, '>' → 3; 'p' writes
    // the frame as shown (step.png → step-1.png, …).
    r = run("view " + scene +
            " --format view --no-hud --frames 9 --script '<,p,>,>,>,p,>,p' "
            "--screenshot step.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("view 47 of 48"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("view 3 of 48"), std::string::npos) << r.output;
    const int expected[] = {47, 2, 3};
    std::vector<Image> shots;
    for (int k = 0; k < 3; ++k) {
        shots.push_back(read(dir / fmt::format("step-{}.png", k + 1)));
        const Image& shot = shots.back();
        ASSERT_EQ(shot.width, kW);
        ASSERT_EQ(shot.height, kH);
        const ImageDiff d = compareImages(shot, renderedView(expected[k]));
        EXPECT_LE(d.maxDelta, 1) << "step " << k << " should show view " << expected[k]
                                 << "; worst pixel " << d.worstX << "," << d.worstY;
    }
    // The steps show different pictures (the views differ across the cone).
    EXPECT_GT(compareImages(shots[0], shots[1], 8).differingPixels, 50);

    // The quilt: the preset's output by default under --display.
    r = run("view " + scene + " --no-hud --frames 2 --screenshot quilt.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find(", quilt, window 960x960"), std::string::npos) << r.output;
    const Image quilt = read(dir / "quilt.png");
    ASSERT_EQ(quilt.width, kColumns * kW);
    ASSERT_EQ(quilt.height, kRows * kH);
    for (int v = 0; v < kViews; ++v) {
        const Image view = renderedView(v);
        const int x0 = (v % kColumns) * kW, y0 = (kRows - 1 - v / kColumns) * kH;
        EXPECT_LE(regionDelta(quilt, x0, y0, view), 1)
            << "quilt tile of view " << v << " at " << x0 << "," << y0;
    }
    // And it is `mvr render`'s quilt file.
    EXPECT_LE(compareImages(quilt, read(dir / "render" / "quilt_qs8x6a0.75.png")).maxDelta, 1);
}

// The viewer shows the views as rendered, without angular anti-aliasing (a post-process of
// written views, docs/displays.md), which `mvr render` applies by default to a view cone.
constexpr const char* kUnfiltered = " --angular-aa off";

TEST_F(ViewCli, ConeKeysAndTheCalibrationsViewCone) {
    // '+' twice: the cone 40 → 50 degrees; the single view 0 is then `mvr render --view-cone
    // 50`'s view 0 (and no longer the 40-degree one).
    needDisplay();
    // --aa 1: the viewer takes one sample a pixel, where mvr render's presets take 4.
    const std::string scene = "--display portrait --size 120x160 --aa 1 --backend soft --method unified";
    CliRun r = run("render " + scene + kUnfiltered + " --view-cone 50 --write views -o cone50 -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("render " + scene + kUnfiltered + " --write views -o cone40 -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("view " + scene +
            " --format view --no-hud --frames 3 --script '+,+' --screenshot c.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("view cone 50 degrees"), std::string::npos) << r.output;
    const Image shot = read(dir / "c.png");
    EXPECT_LE(compareImages(shot, read(dir / "cone50" / "view-0.png")).maxDelta, 1);
    EXPECT_GT(compareImages(shot, read(dir / "cone40" / "view-0.png"), 8).differingPixels, 50);

    // A calibration: its viewCone (30) is the default cone and the lenticular image (at its
    // screen size, 240x320) the default output; both as `mvr render` with the same file.
    std::FILE* f = std::fopen((dir / "visual.json").c_str(), "w");
    ASSERT_TRUE(f);
    std::fputs(R"({"pitch": {"value": 52.59}, "slope": {"value": -7.08}, "center": {"value": 0.82},
        "viewCone": {"value": 30.0}, "DPI": {"value": 324.0}, "screenW": {"value": 240.0},
        "screenH": {"value": 320.0}})",
               f);
    std::fclose(f);
    r = run("render " + scene + kUnfiltered + " --lenticular-calibration visual.json -o len -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("view " + scene +
            " --lenticular-calibration visual.json --no-hud --frames 2 --screenshot len.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("view cone 30 degrees from the calibration"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(", lenticular, window 240x320"), std::string::npos) << r.output;
    const Image len = read(dir / "len.png");
    ASSERT_EQ(len.width, 240);
    EXPECT_LE(compareImages(len, read(dir / "len" / "lenticular.png")).maxDelta, 1);
}

TEST_F(ViewCli, StereoModesOfARowShowAdjacentViews) {
    // sbs of a 5-view row after '>' twice: views 2 | 3, each `mvr render`'s.
    needDisplay();
    const std::string scene =
        "--views 5 --view-cone 30 --size 100x80 --backend soft --method unified";
    CliRun r = run("render " + scene + kUnfiltered + " -o row -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("view " + scene +
            " --format sbs --no-hud --frames 3 --script '>,>' --screenshot s.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("views 2 and 3 of 5"), std::string::npos) << r.output;
    const Image sbs = read(dir / "s.png");
    ASSERT_EQ(sbs.width, 200);
    ASSERT_EQ(sbs.height, 80);
    const Image left = read(dir / "row" / "view-2.png"), right = read(dir / "row" / "view-3.png");
    EXPECT_LE(regionDelta(sbs, 0, 0, left), 1);
    EXPECT_LE(regionDelta(sbs, 100, 0, right), 1);
    // A grid is not a row.
    r = run("view --view-grid 2x2 --frames 1", /*display=*/false);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("error: mvr view shows a row of views: 2x2"), std::string::npos)
        << r.output;
}

TEST_F(ViewCli, QuadBufferWithoutStereoVisualFallsBack) {
    needDisplay();
    const CliRun r = run("view " + model() + " --size 160x120 --format quad-buffer --frames 1 -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Xvfb has no stereo visual; on a driver with one this line is absent.
    if (r.output.find("quad-buffer") != std::string::npos) {
        EXPECT_NE(r.output.find("no stereo visual (GLFW_STEREO); showing anaglyph-dubois instead"),
                  std::string::npos)
            << r.output;
    }
}

// A file shaped like Khronos's 2CylinderEngine (tests/gl/engine_fixture.h: 40 meshes and
// materials, 16-bit indices), which made the gl backend fail on every method and mvr view die
// on its first frame: the viewer shows it on gl, and its screenshot is `mvr render`'s anaglyph.
TEST_F(ViewCli, ShowsAManyMeshFileOnTheGlBackend) {
    needDisplay();
    gl::test::writeEngineGlb(dir / "engine.glb");
    const std::string view = "engine.glb --size 160x120 --backend gl --method multipass";
    CliRun r = run("render " + view + " --format anaglyph-dubois -o render -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("view " + view + " --frames 3 --no-hud --compose cpu --screenshot shot.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image shot = read(dir / "shot.png"), expected = read(dir / "render" / "anaglyph-dubois.png");
    ASSERT_EQ(shot.width, expected.width);
    EXPECT_LE(compareImages(shot, expected).maxDelta, 1);
    // Not an empty frame: the parts cover a good share of it.
    EXPECT_GT(differingFraction(shot, Image(160, 120, shot.at(0, 0))), 0.05);
}

}  // namespace
}  // namespace mvr
