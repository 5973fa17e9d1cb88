// `mvr render` and `mvr info` end to end: outputs, the stereo geometry of real renders, and one
// clear error line with the right exit code for every kind of bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/core.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli_util.h"
#include "mvr/core/image.h"
#include "mvr/io/exr.h"
#include "mvr/io/png.h"

namespace mvr {
namespace {

using test::CliRun;
using test::mvrBinary;
using test::sharedModels;

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        std::replace(name.begin(), name.end(), '/', '_');  // parametrised tests: "Name/0"
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-cli-test-{}-{}", ::getpid(), name);
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    CliRun run(const std::string& args) const { return test::runMvr(mDir, args); }

    /// Expects exactly one line on stderr, starting "error: " and containing `needle`.
    void expectError(const std::string& args, int code, const std::string& needle) const {
        const CliRun r = run(args);
        EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
        const std::string firstLine = r.err.substr(0, r.err.find('\n'));
        EXPECT_NE(firstLine.find(needle), std::string::npos) << args << ": " << r.err;
        EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2)
            << r.err;  // the error (+ a usage hint)
    }

    std::filesystem::path write(const std::string& name, const std::string& bytes) const {
        std::ofstream(mDir / name, std::ios::binary) << bytes;
        return mDir / name;
    }

    std::filesystem::path mDir;
};

TEST_F(Cli, HelpDocumentsTheContract) {
    const CliRun r = run("render --help");
    EXPECT_EQ(r.exitCode, 0);
    for (const char* opt :
         {"--grid", "--views", "--view-grid", "--rig", "--interaxial", "--separation",
          "--convergence", "--fov", "--size", "--shading", "--backend", "--method", "-o"}) {
        EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
    }
    EXPECT_EQ(run("--help").exitCode, 0);
    const CliRun info = run("info");
    EXPECT_EQ(info.exitCode, 0);
    EXPECT_NE(info.out.find("backend soft"), std::string::npos);
    EXPECT_NE(info.out.find("multipass"), std::string::npos);
}

TEST_F(Cli, DefaultSceneWritesViewsAndAnaglyph) {
    const CliRun r = run("render --size 160x120 -o out");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* f : {"view-0.png", "view-1.png", "anaglyph.png"}) {
        auto img = readPng(mDir / "out" / f);
        ASSERT_TRUE(img) << f << ": " << img.status().message();
        EXPECT_EQ(img->width, 160);
        EXPECT_EQ(img->height, 120);
    }
    EXPECT_NE(r.out.find("out/anaglyph.png"), std::string::npos);  // says where it wrote them
    auto left = readPng(mDir / "out/view-0.png");
    auto right = readPng(mDir / "out/view-1.png");
    EXPECT_GT(compareImages(*left, *right).differingPixels, 100);  // two different eyes
}

// --depth-format exr: a plane at z = 0 seen from (0, 0, 5) looking down -Z is at eye-space
// distance 5 everywhere it is drawn (the test's own geometry), +inf where it is not; read back
// with OpenEXR's reader.
TEST_F(Cli, ExrDepthIsTheEyeSpaceDistance) {
    write("plane.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n");
    const CliRun r = run("render plane.obj --views 1 --size 64x48 --camera-position 0,0,5 "
                         "--look-at 0,0,0 --depth --depth-format exr --write depth -q -o e");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto depth = readDepthExr(mDir / "e/depth-0.exr");
    ASSERT_TRUE(depth) << depth.status().message();
    ASSERT_EQ(depth->width, 64);
    ASSERT_EQ(depth->height, 48);
    EXPECT_NEAR(depth->distance[24 * 64 + 32], 5.0f, 1e-3f);  // the centre: on the plane
    // Pixel (40, 16): x = 0.27 and y = 0.31 of the half-extents 2.76 x 2.07 at distance 5
    // (fov 45 degrees, aspect 4:3), so (0.73, 0.65) on the plane: still distance 5.
    EXPECT_NEAR(depth->distance[16 * 64 + 40], 5.0f, 1e-3f);
    EXPECT_TRUE(std::isinf(depth->distance[0]));               // a corner: 2.07 > 1 half-height
    EXPECT_FALSE(std::filesystem::exists(mDir / "e/depth-0.png"));
    expectError("render --depth --depth-format tiff -o x", 1,
                "--depth-format tiff: expected png16 or exr");
}

// --write chooses the files: each kind alone, and a display preset's default (its quilt).
TEST_F(Cli, WriteChoosesTheFiles) {
    auto files = [&](const std::string& dir) {
        std::vector<std::string> names;
        for (const auto& e : std::filesystem::directory_iterator(mDir / dir))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return fmt::format("{}", fmt::join(names, " "));
    };
    ASSERT_EQ(run("render --size 32x24 --write views -q -o a").exitCode, 0);
    EXPECT_EQ(files("a"), "view-0.png view-1.png");
    ASSERT_EQ(run("render --size 32x24 --format sbs --write composites -q -o b").exitCode, 0);
    EXPECT_EQ(files("b"), "anaglyph.png sbs.png");
    ASSERT_EQ(run("render --size 32x24 --write depth,cameras -q -o c").exitCode, 0);
    EXPECT_EQ(files("c"), "cameras.json depth-0.png depth-1.png");
    // --depth adds its files to a --write that leaves them out.
    ASSERT_EQ(run("render --size 32x24 --views 3 --write views --depth -q -o d").exitCode, 0);
    EXPECT_EQ(files("d"), "depth-0.png depth-1.png depth-2.png view-0.png view-1.png view-2.png");
    const CliRun quilt = run("render --display portrait --views 4 --size 30x40 -q -o e");
    ASSERT_EQ(quilt.exitCode, 0) << quilt.err;
    EXPECT_EQ(files("e"), "quilt_qs2x2a0.75.png");
    // The same pixels whatever else is written.
    ASSERT_EQ(run("render --size 32x24 --format sbs -q -o f").exitCode, 0);
    auto alone = readPng(mDir / "b/sbs.png");
    auto full = readPng(mDir / "f/sbs.png");
    ASSERT_TRUE(alone && full);
    EXPECT_EQ(alone->rgba, full->rgba);
}

// --background transparent: alpha 0 where nothing is drawn (the framed bunny's corners), 255
// on the bunny (the centre), and the colours the opaque render has everywhere.
TEST_F(Cli, ATransparentBackgroundIsAlphaZeroWhereNothingIsDrawn) {
    const std::string bunny = "'" + (test::modelsDir() / "stanford-bunny.obj").string() + "'";
    if (!std::filesystem::exists(test::modelsDir() / "stanford-bunny.obj"))
        MVR_SKIP(ModelsMissing) << bunny;
    ASSERT_EQ(run("render " + bunny + " --size 64x48 --background transparent -q -o t").exitCode, 0);
    ASSERT_EQ(run("render " + bunny + " --size 64x48 -q -o o").exitCode, 0);
    for (const char* view : {"view-0.png", "view-1.png"}) {
        auto t = readPng(mDir / "t" / view);
        auto o = readPng(mDir / "o" / view);
        ASSERT_TRUE(t && o) << view;
        int clear = 0, opaque = 0;
        for (std::size_t i = 0; i < t->rgba.size(); i += 4) {
            for (int c = 0; c < 3; ++c) ASSERT_EQ(t->rgba[i + c], o->rgba[i + c]) << view << i;
            ASSERT_EQ(o->rgba[i + 3], 255);
            const std::uint8_t a = t->rgba[i + 3];
            ASSERT_TRUE(a == 0 || a == 255) << int(a);
            (a == 0 ? clear : opaque)++;
        }
        EXPECT_GT(clear, 0) << view;
        EXPECT_GT(opaque, 0) << view;
        EXPECT_EQ(t->rgba[3], 0) << view;  // the top-left corner
        EXPECT_EQ(t->rgba[4 * (24 * 64 + 32) + 3], 255) << view;  // the centre: the bunny
    }
    // A composite laid out from the views keeps their alpha.
    ASSERT_EQ(run("render " + bunny + " --size 64x48 --background transparent --format sbs "
                  "--write composites -q -o s").exitCode, 0);
    auto sbs = readPng(mDir / "s/sbs.png");
    ASSERT_TRUE(sbs);
    EXPECT_EQ(sbs->rgba[3], 0);
}

// An option the command would ignore is a warning naming it (the render goes on).
TEST_F(Cli, IgnoredOptionsAreWarnings) {
    const CliRun r = run("render --size 32x24 --shadow-map-size 512 --fps 30 --jpeg-quality 80 "
                         "--lenticular-pitch 50 -q -o w");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* line :
         {"warning: --shadow-map-size is ignored without --shadows\n",
          "warning: --fps is ignored without a sequence (--frames, --orbit or --camera-path)\n",
          "warning: --jpeg-quality is ignored without --format jps or mpo\n",
          "warning: --lenticular-pitch is ignored without a lenticular image (--format "
          "lenticular)\n"})
        EXPECT_NE(r.err.find(line), std::string::npos) << line << r.err;
    // Used, they are not warned of.
    const CliRun used = run("render --size 32x24 --shadows --shadow-map-size 512 --format jps "
                            "--jpeg-quality 80 -q -o u");
    ASSERT_EQ(used.exitCode, 0) << used.err;
    EXPECT_EQ(used.err.find("is ignored"), std::string::npos) << used.err;
}

TEST_F(Cli, VillageSceneRendersLikeAnyScene) {
    const CliRun r = run("render --scene village --size 160x120 -o out");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto left = readPng(mDir / "out/view-0.png");
    auto def = run("render --size 160x120 -o def");
    ASSERT_EQ(def.exitCode, 0) << def.err;
    auto other = readPng(mDir / "def/view-0.png");
    ASSERT_TRUE(left && other);
    EXPECT_GT(compareImages(*left, *other).differingPixels, 1000);  // not the default scene
}

TEST_F(Cli, ViewGridNamesViewsInOrder) {
    const CliRun r = run("render --size 64x48 --view-grid 3x2 -o grid");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (int v = 0; v < 6; ++v)
        EXPECT_TRUE(std::filesystem::exists(mDir / fmt::format("grid/view-{}.png", v)));
    EXPECT_FALSE(std::filesystem::exists(mDir / "grid/view-6.png"));
    EXPECT_FALSE(std::filesystem::exists(mDir / "grid/anaglyph.png"));  // only for a pair
}

/// Covered pixels' bounds and horizontal centroid (background = the corner pixel's color).
struct Coverage {
    int top = 1 << 30, bottom = -1;
    double centroidX = 0;
    long count = 0;
};
Coverage coverage(const Image& img) {
    const Rgba8 bg = img.at(0, 0);
    Coverage c;
    double sx = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!(img.at(x, y) == bg)) {
                c.top = std::min(c.top, y);
                c.bottom = std::max(c.bottom, y);
                sx += x;
                ++c.count;
            }
    c.centroidX = c.count ? sx / c.count : 0;
    return c;
}

// The bunny, behind the convergence plane: both eyes see it with the same vertical extent (off-axis:
// no vertical parallax) and the right eye sees it further right (positive parallax).
TEST_F(Cli, BunnyEyesOffsetHorizontallyOnly) {
    const auto bunny = sharedModels() / "stanford-bunny.obj";
    if (!std::filesystem::exists(bunny)) MVR_SKIP(ModelsMissing) << "no " << bunny;
    const CliRun r = run(fmt::format(
        "render '{}' --size 200x150 --separation 0.05 --convergence 0.1 -o bunny", bunny.string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto left = readPng(mDir / "bunny/view-0.png");
    auto right = readPng(mDir / "bunny/view-1.png");
    ASSERT_TRUE(left && right);
    const Coverage l = coverage(*left), rc = coverage(*right);
    ASSERT_GT(l.count, 2000);
    EXPECT_EQ(l.top, rc.top);
    EXPECT_EQ(l.bottom, rc.bottom);
    EXPECT_NEAR(double(l.count), double(rc.count), 0.05 * l.count);
    EXPECT_GT(rc.centroidX - l.centroidX, 2.0);  // behind the screen: right image shifted right
    // Toe-in, for comparison, gives vertical parallax somewhere (keystone), so extents may differ;
    // with convergence in front of the bunny, parallel eyes shift it the other way: negative parallax.
    const CliRun p = run(fmt::format(
        "render '{}' --size 200x150 --rig parallel --separation 0.05 -o par", bunny.string()));
    ASSERT_EQ(p.exitCode, 0) << p.err;
    const Coverage pl = coverage(*readPng(mDir / "par/view-0.png")),
                   pr = coverage(*readPng(mDir / "par/view-1.png"));
    EXPECT_LT(pr.centroidX - pl.centroidX,
              -2.0);  // parallel rig: everything in front of the screen
}

// The comfort line says why a rig is uncomfortable, and --separation 50 (5000 % of the screen
// width: parallax of several screen widths) is not "comfortable" (issue 13's measured case).
TEST_F(Cli, TheComfortLineFlagsAnAbsurdSeparation) {
    const CliRun fine = run("render --size 64x48 -o fine");
    ASSERT_EQ(fine.exitCode, 0) << fine.err;
    EXPECT_NE(fine.out.find("(comfortable: "), std::string::npos) << fine.out;
    const CliRun wide = run("render --size 64x48 --separation 50 -o wide");
    ASSERT_EQ(wide.exitCode, 0) << wide.err;
    EXPECT_NE(wide.out.find("uncomfortable: parallax beyond one screen width"), std::string::npos)
        << wide.out;
}

// --orbit without --frames: a frame every 5 degrees (session::kOrbitDegreesPerFrame).
TEST_F(Cli, AnOrbitWithoutFramesTakesAFrameEveryFiveDegrees) {
    const CliRun r = run("render --views 1 --size 16x12 --orbit 20 -q -o orbit");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    int frames = 0;
    for (const auto& e : std::filesystem::directory_iterator(mDir / "orbit"))
        frames += e.is_directory() && e.path().filename().string().rfind("frame-", 0) == 0;
    EXPECT_EQ(frames, 4);  // 20 / 5
    EXPECT_TRUE(std::filesystem::exists(mDir / "orbit/frame-0003/view-0.png"));
}

TEST_F(Cli, VersionPrintsTheVersion) {
    const CliRun r = run("--version");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out, std::string("mvr ") + MVR_VERSION + "\n");
}

TEST_F(Cli, BadNumbersAreUsageErrors) {
    expectError("render --views 0", 1, "view count");
    expectError("render --views 129", 1, "view count");
    expectError("render --elevation 95", 1, "--elevation 95 is out of range (expected -90..90");
    expectError("render --camera-position 1,2", 1,
                "--camera-position 1,2: expected X,Y,Z (three numbers)");
    expectError("render --background 2,0,0", 1, "--background 2,0,0: each of R,G,B must be in 0..1");
    expectError("render --distance far", 1, "'far' is not a number or auto");
    expectError("render --quilt 2x1", 1, "--quilt lays out a quilt, and no quilt is written");
    expectError("render --png-compression tiny", 1,
                "--png-compression tiny: expected fast, default or small");
    expectError("render --convergence 1000", 1,
                "--convergence 1000: convergence 1000 is beyond the far plane");
    expectError("render --views 4 --view-cone 180", 1, "--view-cone 180 is out of range");
    expectError("render --views 4 --view-cone 40 --interaxial 0.1", 1,
                "--interaxial excludes --view-cone");
    expectError("render --views 4 --view-cone 40 --separation 0.1", 1,
                "--view-cone 40 excludes --separation");
    expectError("render --view-grid 3x3 --view-cone 40", 1, "needs an off-axis row");
    expectError("render --view-grid 3by3", 1, "--view-grid");
    expectError("render --size 0x10", 1, "--size");
    expectError("render --size -5x5", 1, "--size");
    expectError("render --size 99999x10", 1, "--size");
    expectError("render --size big", 1, "--size");
    expectError("render --interaxial nan", 1, "--interaxial");
    expectError("render --separation inf", 1, "--separation");
    expectError("render --convergence -1", 1, "--convergence");
    expectError("render --convergence 0", 1, "--convergence");
    expectError("render --fov 180", 1, "--fov");
    expectError("render --fov nan", 1, "--fov");
    expectError("render --grid 0 x.obj", 1, "--grid");
    expectError("render --views abc", 1, "--views");
}

TEST_F(Cli, UnknownNamesAreUsageErrors) {
    expectError("render --backend vulkan", 1, "unknown backend 'vulkan'");
    expectError("render --method teleport", 1, "teleport");
    expectError("render --rig fisheye", 1, "unknown rig 'fisheye'");
    expectError("render --shading toon", 1, "unknown shading 'toon'");
    expectError("frobnicate", 1, "frobnicate");
}

TEST_F(Cli, BadModelFilesAreInputErrors) {
    expectError("render nowhere.obj", 2, "file not found");
    expectError(fmt::format("render '{}'", write("empty.obj", "").string()), 2, "empty");
    expectError(
        fmt::format("render '{}'", write("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n").string()), 2,
        "no triangles");
    expectError(fmt::format("render '{}'",
                            write("flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n").string()),
                2, "degenerate");
    expectError(
        fmt::format("render '{}'",
                    write("cut.ply", "ply\nformat ascii 1.0\nelement vertex 3\nprop").string()),
        2, "PLY");
    expectError(fmt::format("render '{}'", write("junk.gltf", "{\"asset\": {").string()), 2,
                "junk.gltf");
    expectError(fmt::format("render '{}'", mDir.string()), 2, "not a regular file");
}

TEST_F(Cli, UnwritableOutputIsAnOutputError) {
    write("file", "x");
    expectError("render --size 8x8 -o file/sub", 4, "output directory");
}

// Every refusal names its culprit: the option and its value, or the file and the line or
// element and the reason; and exits with its category's code (1 usage, 2 input, 3 unsupported).
TEST_F(Cli, EveryRefusalNamesItsCulprit) {
    const std::string nanObj = write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n").string();
    const std::string infObj =
        write("inf.obj", "# cube\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 -inf\r\nf 1 2 3\r\n").string();
    const std::string zeroObj = write("zero.obj", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n").string();
    const std::string plyHead =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\n";
    const std::string nanPly = write("nan.ply", plyHead +
                                                    "element face 1\nproperty list uchar int "
                                                    "vertex_indices\nend_header\n0 0 0\nnan 1 0\n"
                                                    "0 1 0\n3 0 1 2\n")
                                   .string();
    const std::string hugePly =
        write("huge.ply",
              "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n"
              "property float x\nproperty float y\nproperty float z\nend_header\n")
            .string();
    const std::string badStrip = write("strip.ply", plyHead +
                                                        "element tristrips 1\nproperty list int "
                                                        "int vertex_indices\nend_header\n0 0 0\n"
                                                        "1 0 0\n0 1 0\n4 0 1 2 -5\n")
                                     .string();
    // The options added since the table was made: stereo displays, shadows, surfaces,
    // placements and sequences.
    const std::string oddSky = mDir.string() + "/odd.png";
    ASSERT_TRUE(writePng(oddSky, Image(6, 5)));
    const std::string textSky = write("sky.png", "not an image\n").string();
    const std::string notJson = write("path.json", "{\"keys\": [").string();
    const std::string badKey =
        write("key.json",
              R"({"keys": [{"time": 0, "position": [0, 0, 6], "target": [0, 0, 0]},)"
              R"( {"time": 1, "position": [0, 6], "target": [0, 0, 0]}]})")
            .string();
    const std::string backwards =
        write("back.json",
              R"([{"time": 1, "position": [0, 0, 6], "target": [0, 0, 0]},)"
              R"( {"time": 0.5, "position": [0, 0, 5], "target": [0, 0, 0]}])")
            .string();
    const struct {
        std::string args;
        int code;
        std::string message;
    } kCases[] = {
        {"--view-cone 200", 1, "--view-cone 200 is out of range (expected 0 < cone < 180 degrees)"},
        {"--view-cone 40 --view-grid 3x2", 1,
         "--view-cone 40 needs an off-axis row of views (--views N, --rig offaxis)"},
        {"--display nosuch", 1, "--display nosuch: unknown display 'nosuch' (expected one of: "},
        {"--screen-width -3", 1,
         "--screen-width -3 is out of range (expected a length in cm, 0 < cm <= 1e6)"},
        {"--screen-width 30 --viewing-distance 0", 1, "--viewing-distance 0 is out of range"},
        {"--viewing-distance 50", 1, "--viewing-distance 50 needs --screen-width"},
        {"--convergence aut", 1, "--convergence: 'aut' is not a number (expected a number or auto)"},
        {"--separation auto", 1, "--separation auto needs --screen-width CM"},
        {"--shadow-map-size 8", 1, "--shadow-map-size 8 is out of range (expected 16..8192)"},
        {"--shadow-map-size abc", 1, "--shadow-map-size = abc"},
        {"--sky nosuch.png", 2,
         "--sky 'nosuch.png': file not found (a PNG, JPEG, .hdr or .exr map, 'gradient' or "
         "'environment')"},
        {"--sky '" + textSky + "'", 2,
         "--sky '" + textSky + "': not a PNG, JPEG, Radiance or OpenEXR image"},
        {"--sky '" + mDir.string() + "'", 2, "--sky '" + mDir.string() + "': not a regular file"},
        {"--sky '" + oddSky + "'", 1,
         "--sky '" + oddSky + "': 6x5 is neither an equirectangular map"},
        {"--letterbox 60", 1, "--letterbox 60: must be in (0, 50) percent of the height"},
        {"--label bad", 1, "--label 'bad': expected TEXT@x,y[,distance]"},
        {"--label 'X@a,b'", 1, "--label 'X@a,b': expected TEXT@x,y[,distance] (numbers)"},
        {"--label-anchor 'A@1,2'", 1, "--label-anchor 'A@1,2': expected TEXT@X,Y,Z"},
        {"m.obj@1,2", 1, "model 'm.obj@1,2': placement '1,2' has 2 numbers (expected FILE@X,Y,Z"},
        {"m.obj@1,a,3", 1, "model 'm.obj@1,a,3': placement '1,a,3' is not a list of numbers"},
        {"--camera-path nosuch.json", 2, "--camera-path nosuch.json: file not found"},
        {"--camera-path '" + mDir.string() + "'", 2,
         "--camera-path " + mDir.string() + ": not a regular file"},
        {"--camera-path '" + notJson + "'", 2, "--camera-path " + notJson + ": not JSON"},
        {"--camera-path '" + badKey + "'", 2,
         "--camera-path " + badKey + ": key 1 position: expected [x, y, z]"},
        {"--camera-path '" + backwards + "'", 2,
         "--camera-path " + backwards + ": camera path: key 1: time 0.5 does not follow key 0's 1"},
        {"--frames -3", 1, "--frames: -3 is out of range (must be a whole number 1..1000000)"},
        {"--frames 2000000", 1, "--frames: 2000000 is out of range (must be a whole number 1..1000000"},
        {"--orbit 1e300", 1, "--orbit 1e+300: at most 360000 degrees"},
        {"--frames 3 --orbit nan", 1, "--orbit nan is not a finite angle"},
        {"--frames 3 --fps 0", 1, "--fps 0 is out of range (expected 0 < fps <= 1000)"},
        {"--frames 3 --frame-range 5:2", 1,
         "--frame-range '5:2' is out of range (expected 0 <= A < B <= 3 frames)"},
        {"--frames 3 --frame-range 99999999999999999999:", 1,
         "--frame-range '99999999999999999999:' is out of range"},
        {"--frames 3 --frame-range abc", 1, "--frame-range 'abc' is not of the form A:B"},
        {"--frames 3 --shard 4/2", 1, "--shard '4/2' is out of range (expected 0 <= I < N)"},
        {"--frames 3 --shard x", 1, "--shard 'x' is not of the form I/N"},
        {"--frame-range 0:1", 1, "--frame-range 0:1 needs a sequence (--frames F, --orbit DEG"},
        {"--shard 0/2", 1, "--shard 0/2 needs a sequence"},
        {"--video out.mkv", 1, "--video out.mkv needs a sequence"},
        {"--background transparent --letterbox 5", 1,
         "--background transparent: not with --letterbox (it paints over the background)"},
        {"--write nope", 1,
         "--write nope: unknown 'nope' (expected a comma list of views, depth, composites, "
         "cameras, video)"},
        {"--write views,", 1, "--write views,: an empty item"},
        {"--write video", 1, "--write video: video, and no --video FILE to write"},
        {"--frames 3 --video out.mkv --write views", 1,
         "--video out.mkv: --write views leaves the video out"},
        {"--frames 3 --video out.avi", 1, "--video out.avi: expected a .mkv or .mp4 file"},
        {"--interaxial 1e30", 1, "--interaxial 1e+30: view 0 has a non-finite matrix or shear"},
        {"--separation 1e30", 1, "--separation 1e+30: view 0 has a non-finite matrix"},
        {"--interaxial -1", 1, "--interaxial -1 is out of range"},
        {"--convergence 0", 1, "--convergence 0 is out of range"},
        {"--fov 200", 1, "--fov 200 is out of range"},
        {"--size 0x5", 1, "--size '0x5' is out of range"},
        {"--size 20", 1, "--size '20' is not of the form WxH"},
        {"--views 129", 1, "--views 129: view count 129 is out of range (expected 1..128)"},
        {"--view-grid 12x11", 1, "--view-grid 12x11: view count 132 is out of range"},
        {"--view-grid 3y3", 1, "--view-grid '3y3' is not of the form CxR"},
        {"--grid 3", 1, "--grid 3 needs a model file"},
        {"--scene town", 1,
         "--scene town is not a known scene (expected default, village or textured)"},
        {"--scene village --grid 3", 1, "--grid 3 needs a model file (the village scene"},
        {"--scene village '" + nanObj + "'", 1,
         "--scene village cannot be combined with model files"},
        {"--shading toon", 1, "--shading toon: unknown shading 'toon'"},
        {"--rig fisheye", 1, "--rig fisheye: unknown rig 'fisheye'"},
        {"--backend vulkan", 1, "--backend vulkan: unknown backend 'vulkan'"},
        {"--method nope", 1, "--method nope: soft backend: unknown method 'nope'"},
        {"'" + nanObj + "'", 2, "nan.obj: line 2: vertex 2 has a NaN coordinate"},
        {"'" + infObj + "'", 2, "inf.obj: line 4: vertex 3 has an infinite coordinate"},
        {"'" + zeroObj + "'", 2, "zero.obj: is degenerate"},
        {"'" + nanPly + "'", 2, "nan.ply: vertex 1 of 3 has a NaN coordinate"},
        {"'" + hugePly + "'", 2,
         "huge.ply: malformed PLY: element 'vertex' claims 1000000000 entries but the file is too "
         "short"},
        {"'" + badStrip + "'", 2,
         "strip.ply: malformed PLY: tristrips 0: negative or huge vertex index -5"},
        {"--size 16384x16384 --views 5", 3,
         "5 views of 16384x16384 need 10.0 GiB of color and depth images (limit 8 GiB)"},
    };
    for (const auto& c : kCases) expectError("render -o out " + c.args, c.code, c.message);
    // Refused before anything is written: no frame folder, no video.
    EXPECT_FALSE(std::filesystem::exists(mDir / "out" / "frame-0000"));
    EXPECT_FALSE(std::filesystem::exists(mDir / "out.mkv"));
}

// The memory budget is checked up front, before any backend allocates, with one message for
// every backend (mvr::validateRequest).
TEST_F(Cli, EveryBackendRefusesAnOutputOverTheBudgetAlike) {
    std::string first;
    for (const char* backend : {"soft", "gl"}) {
        const CliRun r =
            run(fmt::format("render -o out --backend {} --size 16384x16384 --views 5", backend));
        EXPECT_EQ(r.exitCode, 3) << backend << ": " << r.err;
        EXPECT_NE(r.err.find("need 10.0 GiB of color and depth images"), std::string::npos)
            << r.err;
        if (first.empty()) first = r.err;
        EXPECT_EQ(r.err, first) << backend;
    }
    EXPECT_FALSE(std::filesystem::exists(mDir / "out" / "view-0.png"));
}

// What fits depends on the machine: a frame within the fixed budget that this process cannot
// allocate (here under a 1.5 GB address-space limit) is one error line, not an abort. The
// allocation fails on a worker thread (the soft backend clears its images in parallel); the
// thread pool hands the exception to the caller, whose error names the request.
TEST_F(Cli, RunningOutOfMemoryIsOneErrorLine) {
#if defined(__SANITIZE_ADDRESS__)
    MVR_SKIP(NotApplicable) << "ASan reserves terabytes of address space: no ulimit -v under it";
#else
    const CliRun r = test::runMvr(mDir, "render -o out --backend soft --views 40 --size 2048x2048",
                                  "ulimit -v 1500000 && ");
    EXPECT_EQ(r.exitCode, 5) << r.err;  // not 134: std::terminate's abort
    EXPECT_EQ(r.err, "error: soft backend: out of memory rendering 40 views of 2048x2048\n");
    EXPECT_FALSE(std::filesystem::exists(mDir / "out" / "view-0.png"));
#endif
}

// --check renders the reference too and prints, per view, the fraction of pixels that differ.
TEST_F(Cli, CheckPrintsTheArtifactFractionPerView) {
    const CliRun soft = run("render --size 160x120 -o out --check");
    ASSERT_EQ(soft.exitCode, 0) << soft.err;
    for (const char* line :
         {"check: view 0: soft:unified vs soft:multipass: 0.00 % of the pixels differ by more "
          "than 2/255 (0 of 19200); largest difference 0/255",
          "check: view 1: soft:unified vs soft:multipass: 0.00 %"}) {
        EXPECT_NE(soft.out.find(line), std::string::npos) << soft.out;
    }
    const CliRun info = run("info");
    if (info.out.find("backend gl") == std::string::npos) MVR_SKIP(FeatureNotBuilt) << "no gl backend";
    const CliRun mrt = run("render --size 160x120 -o out --backend gl --method gs-mrt --check");
    if (mrt.exitCode == 3) MVR_SKIP(NoGlContext) << mrt.err;  // no EGL driver here
    ASSERT_EQ(mrt.exitCode, 0) << mrt.err;
    EXPECT_NE(mrt.out.find("check: view 0: gl:gs-mrt vs gl:multipass: "), std::string::npos)
        << mrt.out;
    EXPECT_EQ(mrt.out.find("check: view 0: gl:gs-mrt vs gl:multipass: 0.00 %"), std::string::npos)
        << "gs-mrt has artifacts on the default scene (src/gl/README.md)\n"
        << mrt.out;
    const CliRun multi =
        run("render --size 160x120 -o out --backend gl --method multipass --check");
    ASSERT_EQ(multi.exitCode, 0) << multi.err;
    EXPECT_NE(multi.out.find("check: view 1: gl:multipass vs soft:multipass: "), std::string::npos)
        << multi.out;
}

// `mvr render` reads depth images back only when --depth (or a surface drawn against depth)
// asks: the comfort report and the JSON come from each view's depth range, which gl measures
// on the device, and say exactly what they say with the images.
TEST_F(Cli, TheComfortReportNeedsNoDepthImages) {
    const CliRun info = run("info");
    std::vector<std::string> backends = {"soft"};
    if (info.out.find("backend gl") != std::string::npos) backends.push_back("gl");
    for (const std::string& b : backends) {
        const std::string common = "render --views 5 --size 96x72 -q --backend " + b;
        const CliRun plain = run(common + " -o plain --report-json plain.json");
        if (b == "gl" && plain.exitCode == 3) MVR_SKIP(NoGlContext) << plain.err;  // no EGL driver here
        ASSERT_EQ(plain.exitCode, 0) << plain.err;
        const CliRun depth = run(common + " -o depth --depth --report-json depth.json");
        ASSERT_EQ(depth.exitCode, 0) << depth.err;
        EXPECT_FALSE(std::filesystem::exists(mDir / "plain/depth-0.png")) << b;
        EXPECT_TRUE(std::filesystem::exists(mDir / "depth/depth-4.png")) << b;
        const std::string a = test::slurp(mDir / "plain.json"), c = test::slurp(mDir / "depth.json");
        EXPECT_NE(a.find("\"parallax\": {"), std::string::npos) << b << ": " << a;
        EXPECT_EQ(a, c) << b;
    }
}

// A long render shows progress on a terminal only (MVR_PROGRESS_AFTER_MS=0: at once).
TEST_F(Cli, ProgressGoesToATerminalOnly) {
    const CliRun piped = run("render --size 160x120 -o out");
    EXPECT_EQ(piped.err, "");
    const std::string cmd = fmt::format(
        "cd '{}' && MVR_PROGRESS_AFTER_MS=0 script -qec \"'{}' render --size 160x120 -o out\" "
        "/dev/null >tty.txt 2>&1 </dev/null",
        mDir.string(), mvrBinary().string());
    if (std::system("script --version >/dev/null 2>&1") != 0) MVR_SKIP(ToolMissing) << "no script(1)";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    std::ifstream in(mDir / "tty.txt");
    std::stringstream tty;
    tty << in.rdbuf();
    EXPECT_NE(tty.str().find("mvr: rendering 2 views of 160x120 on soft:unified ... "),
              std::string::npos)
        << tty.str();
    EXPECT_NE(tty.str().find("\r\033[K"), std::string::npos) << "the line is erased afterwards";
}

// Real-world layouts render like their plain equivalents (tests/core/mesh_variants_test.cpp
// compares the loaded triangles of every layout; here the soft renders of a few).
TEST_F(Cli, VariantsRenderLikeTheirPlainFiles) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 9\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n";
    const std::string vertices =
        "0 1 0 255 0 0\n0 0 0 255 0 0\n1 1 0 9 9 9\n1 0 0 1 2 3\n2 1 0 0 0 0\n2 0 0 7 7 7\n"
        "0 0 1 1 1 1\n1 0 1 2 2 2\n0 1 1 3 3 3\n";
    const std::vector<std::pair<std::string, std::string>> pairs = {
        {head + "element face 5\nproperty list uchar int vertex_indices\nend_header\n" + vertices +
             "3 1 0 3\n3 3 0 2\n3 3 2 5\n3 5 2 4\n3 6 7 8\n",
         head + "element tristrips 1\nproperty list int int vertex_indices\nend_header\n" +
             vertices + "11 1 0 3 2 5 4 -1 6 7 8 8\n"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
         "f 1 2 3\nf 1 3 4\nf 1 2 6\nf 1 6 5\n",
         "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nvt 0 0\r\nf -4/1 -3/1 \\\r\n -2/1 -1/1\r\n"
         "v 0 0 1\r\nv 1 0 1\r\nf 1 2 -1 -2\r\n"},
    };
    int n = 0;
    for (const auto& [plain, variant] : pairs) {
        const std::string ext = plain.rfind("ply", 0) == 0 ? ".ply" : ".obj";
        std::vector<Image> images;
        for (const std::string* text : {&plain, &variant}) {
            const std::string name = fmt::format("m{}{}", n++, ext);
            const CliRun r = run(fmt::format("render -q --size 96x72 --views 1 -o {} {}",
                                             name + ".out", write(name, *text).string()));
            ASSERT_EQ(r.exitCode, 0) << name << ": " << r.err;
            auto img = readPng(mDir / (name + ".out") / "view-0.png");
            ASSERT_TRUE(img) << img.status().message();
            images.push_back(*img);
        }
        const ImageDiff d = compareImages(images[0], images[1], 1);
        EXPECT_EQ(d.differingPixels, 0) << ext << ": max delta " << d.maxDelta;
        long drawn = 0;
        for (std::size_t i = 0; i < images[0].rgba.size(); i += 4)
            drawn += images[0].rgba[i] != images[0].rgba[0] ? 1 : 0;
        EXPECT_GT(drawn, 100) << ext << ": the model is on screen";
    }
}

// The gs-mrt / gs-depthmap figures README.md and src/gl/README.md quote for the default camera
// are what `mvr render --backend gl --method M --check` prints (measured on llvmpipe; another
// driver rasterizes differently, so only llvmpipe is held to them, within 0.05 points).
TEST_F(Cli, DocsQuoteTheDefaultCameraArtifacts) {
    const CliRun info = run("info");
    if (info.out.find("GL_RENDERER: llvmpipe") == std::string::npos)
        MVR_SKIP(NotApplicable) << "the figures are llvmpipe's";
    auto slurp = [](const std::filesystem::path& p) {
        std::ifstream in(p);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    const std::string readme = slurp(std::filesystem::path(MVR_TEST_SOURCE_DIR) / "README.md");
    const std::string glReadme =
        slurp(std::filesystem::path(MVR_TEST_SOURCE_DIR) / "src" / "gl" / "README.md");
    for (const char* method : {"gs-mrt", "gs-depthmap"}) {
        const CliRun r = run(fmt::format("render -o out --backend gl --method {} --check", method));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        double percent[2] = {-1, -1};
        for (int v = 0; v < 2; ++v) {
            const std::string key =
                fmt::format("check: view {}: gl:{} vs gl:multipass: ", v, method);
            const std::size_t at = r.out.find(key);
            ASSERT_NE(at, std::string::npos) << r.out;
            percent[v] = std::stod(r.out.substr(at + key.size()));
        }
        // The docs' figure: "<left> % / <right> %" in the default-camera row / the method table.
        const std::string row = std::string("| gl:") + method + " |";
        const std::size_t inTable = readme.find(row);
        ASSERT_NE(inTable, std::string::npos);
        const std::string line = readme.substr(inTable, readme.find('\n', inTable) - inTable);
        const std::size_t fig = line.find("% / ");
        ASSERT_NE(fig, std::string::npos) << line;
        const std::size_t start = line.rfind(' ', line.rfind(' ', fig) - 1) + 1;
        const double left = std::stod(line.substr(start)), right = std::stod(line.substr(fig + 4));
        EXPECT_NEAR(left, percent[0], 0.05) << method << ": README.md says " << line;
        EXPECT_NEAR(right, percent[1], 0.05) << method << ": README.md says " << line;
        const std::string quoted = fmt::format("{:.2f} % / {:.2f} %", left, right);
        EXPECT_NE(glReadme.find(quoted), std::string::npos)
            << "src/gl/README.md's default-camera table quotes " << quoted;
    }
}

// Issue 15: the stereo surfaces from the command line (their numbers: tests/core/
// stereo_surfaces_test.cpp). The letterbox's top band lies over the sky (behind the screen),
// the floating window masks the left edge of view 0 where the floor comes out of the screen.
TEST_F(Cli, StereoSurfaces) {
    const CliRun r =
        run("render --size 160x120 --sky gradient --letterbox 10 --floating-window "
            "--label 'HI@0.5,0.5,3' --label-anchor 'A@0,0,0' -o out -q");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto left = readPng(mDir / "out/view-0.png");
    ASSERT_TRUE(left);
    EXPECT_EQ(left->at(80, 0), (Rgba8{0, 0, 0, 255}));  // letterbox
    EXPECT_EQ(left->at(80, 11), (Rgba8{0, 0, 0, 255}));
    EXPECT_NE(left->at(80, 12), (Rgba8{0, 0, 0, 255}));  // sky below the band
    EXPECT_EQ(left->at(0, 60), (Rgba8{0, 0, 0, 255}));   // floating window
    expectError("render --size 64x48 --sky nosuch.png -o out", 2, "--sky 'nosuch.png'");
    expectError("render --size 64x48 --letterbox 60 -o out", 1, "--letterbox 60");
    expectError("render --size 64x48 --label bad -o out", 1, "--label 'bad'");
    expectError("render --size 64x48 --rig toein --floating-window -o out", 3, "off-axis");
}

}  // namespace
}  // namespace mvr

// ---- scenes from files (issue 14): the glTF fixture's nodes where their transforms put them,
// the file's camera, placements ----------------------------------------------------------------

#include <glm/gtc/matrix_transform.hpp>

#include "../core/blender_fixture.h"
#include "../core/gltf_fixture.h"
#include "../core/gltf_maps_fixture.h"
#include "mvr_test_support.h"
#include "tonemap_reference.h"

namespace mvr {
namespace {

/// The pixel rectangle [x0, x1] x [y0, y1] (row 0 at the top) that the box `lo..hi` under
/// `world` covers seen by a camera at `eye` looking down -Z with vertical fov `yfov`.
glm::vec4 projectBox(const glm::mat4& world, glm::vec3 lo, glm::vec3 hi, glm::vec3 eye, float yfov,
                     int w, int h) {
    const glm::mat4 view = glm::lookAt(eye, eye + glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspective(yfov, float(w) / float(h), 0.1f, 100.0f);
    glm::vec4 r(1e9f, 1e9f, -1e9f, -1e9f);
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        const glm::vec4 clip = proj * view * world * glm::vec4(p, 1.0f);
        const float x = (clip.x / clip.w * 0.5f + 0.5f) * w,
                    y = (0.5f - clip.y / clip.w * 0.5f) * h;
        r = glm::vec4(std::min(r.x, x), std::min(r.y, y), std::max(r.z, x), std::max(r.w, y));
    }
    return r;
}

bool isBackground(Rgba8 c, Rgba8 bg) {
    return std::abs(c.r - bg.r) <= 2 && std::abs(c.g - bg.g) <= 2 && std::abs(c.b - bg.b) <= 2;
}

/// Where a point of model space lands in a view of w x h pixels of the fixture's file camera
/// (at GltfFixtureTruth::cameraPosition(), looking down -Z, yfov kYfov): window x, y (row 0 at
/// the top).
glm::vec2 projectPoint(const glm::mat4& world, glm::vec3 p, int w, int h) {
    using test::GltfFixtureTruth;
    const glm::vec3 eye = GltfFixtureTruth::cameraPosition();
    const glm::mat4 view = glm::lookAt(eye, eye + glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    const glm::mat4 proj =
        glm::perspective(GltfFixtureTruth::kYfov, float(w) / float(h), 0.1f, 100.0f);
    const glm::vec4 clip = proj * view * world * glm::vec4(p, 1.0f);
    return {(clip.x / clip.w * 0.5f + 0.5f) * w, (0.5f - clip.y / clip.w * 0.5f) * h};
}

/// The done-when of issue 14 on each backend: the fixture (a parent node with two children
/// that instance one mesh of two primitives, a camera node, a sun and a point light, a
/// textured material) renders seen by the file camera with every node where its transform
/// puts it (the projected boxes computed here, independently of the loader), and its texture
/// visible where the texture coordinates put each texel. gl skips where it cannot run.
class CliGltfBackends : public Cli, public ::testing::WithParamInterface<const char*> {};

TEST_P(CliGltfBackends, NodesWhereTheirTransformsPutThemAndTexelsAtTheirTextureCoordinates) {
    using test::GltfFixtureTruth;
    const std::string backend = GetParam();
    if (backend != "soft") {
        const CliRun info = run("info");
        if (info.out.find("backend " + backend) == std::string::npos)
            MVR_SKIP(FeatureNotBuilt) << "no " << backend << " backend in this build";
    }
    const glm::mat4 worldA = GltfFixtureTruth::parent() * GltfFixtureTruth::childA();
    const glm::mat4 worldB = GltfFixtureTruth::parent() * GltfFixtureTruth::childB();
    for (auto layout : {test::GltfLayout::External, test::GltfLayout::Glb}) {
        const auto model = test::writeGltfFixture(mDir, "scene", layout);
        const int w = 300, h = 200;
        const CliRun r = run(fmt::format("render '{}' --backend {} --views 1 --size {}x{} -o o",
                                         model.string(), backend, w, h));
        if (backend != "soft" && r.exitCode == 3) MVR_SKIP(NoGlContext) << r.err;  // no EGL driver here
        ASSERT_EQ(r.exitCode, 0) << r.err;
        auto img = readPng(mDir / "o/view-0.png");
        ASSERT_TRUE(img) << img.status().message();
        const Rgba8 bg = img->at(0, 0);
        // Each node: its two primitives' boxes (the cube and the small cube above it).
        std::vector<glm::vec4> rects;
        for (const glm::mat4& world : {worldA, worldB}) {
            rects.push_back(projectBox(world, glm::vec3(-0.5f), glm::vec3(0.5f),
                                       GltfFixtureTruth::cameraPosition(), GltfFixtureTruth::kYfov,
                                       w, h));
            rects.push_back(
                projectBox(world, glm::vec3(-0.25f, 0.75f, -0.25f), glm::vec3(0.25f, 1.25f, 0.25f),
                           GltfFixtureTruth::cameraPosition(), GltfFixtureTruth::kYfov, w, h));
        }
        // Inside: each box's projected centre is covered. Outside every box (1 px margin):
        // background.
        for (const glm::vec4& rc : rects) {
            const int cx = int((rc.x + rc.z) / 2), cy = int((rc.y + rc.w) / 2);
            EXPECT_FALSE(isBackground(img->at(cx, cy), bg)) << backend << " " << cx << "," << cy;
        }
        long stray = 0, covered = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                bool inside = false;
                for (const glm::vec4& rc : rects)
                    inside = inside || (x + 0.5f >= rc.x - 1 && x + 0.5f <= rc.z + 1 &&
                                        y + 0.5f >= rc.y - 1 && y + 0.5f <= rc.w + 1);
                const bool bgPixel = isBackground(img->at(x, y), bg);
                if (!inside && !bgPixel) ++stray;
                if (!bgPixel) ++covered;
            }
        EXPECT_EQ(stray, 0) << backend;
        EXPECT_GT(covered, 1200) << backend;
        // The texture at known texture coordinates: the big cube's +Z face of node A carries
        // uv = ((x / h + 1) / 2, (1 - y / h) / 2) (gltf_fixture.h's box, h = 0.5), so texel
        // (i, j) of the 4x4 texture (magnified, NEAREST) has its centre at model x = 0.5 *
        // ((i + 0.5) / 2 - 1), y = 0.5 * (1 - (j + 0.5) / 2), z = 0.5. Row 0 is red, green,
        // blue, white; the other rows yellow. Lit, each keeps its hue.
        struct Texel {
            int i, j;
            const char* name;
        };
        for (const Texel& t : {Texel{0, 0, "red"}, Texel{1, 0, "green"}, Texel{2, 0, "blue"},
                               Texel{3, 0, "white"}, Texel{1, 2, "yellow"}}) {
            const glm::vec3 p(0.5f * ((t.i + 0.5f) / 2.0f - 1.0f),
                              0.5f * (1.0f - (t.j + 0.5f) / 2.0f), 0.5f);
            const glm::vec2 at = projectPoint(worldA, p, w, h);
            const Rgba8 c = img->at(int(at.x), int(at.y));
            const int r8 = c.r, g8 = c.g, b8 = c.b;
            const std::string what = fmt::format("{} texel {} at ({}, {}): {} {} {}", backend,
                                                 t.name, int(at.x), int(at.y), r8, g8, b8);
            const std::string n = t.name;
            bool expected = false;
            if (n == "red") expected = r8 > g8 + 60 && r8 > b8 + 60;
            if (n == "green") expected = g8 > r8 + 60 && g8 > b8 + 60;
            if (n == "blue") expected = b8 > r8 + 60 && b8 > g8 + 60;
            if (n == "yellow") expected = r8 > b8 + 60 && g8 > b8 + 60;
            if (n == "white") {
                expected = std::min({r8, g8, b8}) > 60 &&
                           std::max({r8, g8, b8}) - std::min({r8, g8, b8}) < 60;
            }
            EXPECT_TRUE(expected) << what;
        }
        // Framing the bounds instead (--no-file-camera) is another picture.
        const CliRun other =
            run(fmt::format("render '{}' --backend {} --views 1 --size {}x{} --no-file-camera "
                            "-o n",
                            model.string(), backend, w, h));
        ASSERT_EQ(other.exitCode, 0) << other.err;
        auto img2 = readPng(mDir / "n/view-0.png");
        ASSERT_TRUE(img2);
        EXPECT_GT(compareImages(*img, *img2).differingPixels, 800) << backend;
    }
}

// Blender's exporter layout renders as its hand-written equivalent (blender_fixture.h).
TEST_P(CliGltfBackends, BlenderExporterLayoutRendersAsItsHandWrittenEquivalent) {
    const std::string backend = GetParam();
    if (backend != "soft" && run("info").out.find("backend " + backend) == std::string::npos)
        MVR_SKIP(FeatureNotBuilt) << "no " << backend << " backend in this build";
    const auto exported = test::writeBlenderGltf(mDir, "exported", test::BlenderLayout::Exporter);
    const auto hand = test::writeBlenderGltf(mDir, "hand", test::BlenderLayout::HandWritten);
    const int w = 192, h = 108;
    std::vector<Image> images;
    for (const auto& [model, out] : {std::pair{exported, "e"}, std::pair{hand, "h"}}) {
        const CliRun r = run(fmt::format("render '{}' --backend {} --views 2 --size {}x{} -o {}",
                                         model.string(), backend, w, h, out));
        if (backend != "soft" && r.exitCode == 3) MVR_SKIP(NoGlContext) << r.err;
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
        for (int v = 0; v < 2; ++v) {
            auto img = readPng(mDir / out / fmt::format("view-{}.png", v));
            ASSERT_TRUE(img) << img.status().message();
            images.push_back(std::move(*img));
        }
    }
    for (int v = 0; v < 2; ++v) {
        // TRS against matrices: the same transforms up to float rounding, so at most a few
        // edge pixels may differ.
        const ImageDiff d = compareImages(images[v], images[2 + v], 2);
        EXPECT_LE(d.differingPixels, w * h / 500) << backend << " view " << v;
    }
    // Something of the scene is drawn, textured and lit: not one flat color.
    const Rgba8 bg = images[0].at(0, 0);
    long covered = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) covered += !isBackground(images[0].at(x, y), bg);
    EXPECT_GT(covered, w * h / 20) << backend;
}

// --tonemap (issue 39 item 2): auto is khr-neutral under a file's own lights and none under the
// default lights; each pixel of the neutral picture is the reference curve (written out in
// tonemap_reference.h) of the clamped picture's where that one did not clip (pixel shading:
// both map the same fragment colour); a bad name is a usage error.
TEST_F(Cli, TonemapAutoFollowsWhereTheLightsComeFrom) {
    const auto lit = test::writeBlenderGltf(mDir, "lit", test::BlenderLayout::Exporter);
    // A black background: the curve keeps black, so every pixel can be checked.
    const std::string file = "'" + lit.string() + "' --shading pixel --background 0,0,0";
    auto render = [&](const std::string& args, const std::string& out) -> Image {
        const CliRun r = run(fmt::format("render {} --views 1 --size 96x64 -o {}", args, out));
        EXPECT_EQ(r.exitCode, 0) << r.err;
        auto img = readPng(mDir / out / "view-0.png");
        EXPECT_TRUE(img) << out;
        return img ? std::move(*img) : Image();
    };
    const Image autoLit = render(file, "a");
    const Image neutral = render(file + " --tonemap khr-neutral", "n");
    const Image none = render(file + " --tonemap none", "o");
    const Image aces = render(file + " --tonemap aces", "c");
    EXPECT_EQ(compareImages(autoLit, neutral).differingPixels, 0);
    EXPECT_GT(compareImages(none, neutral, 2).differingPixels, 100);
    EXPECT_GT(compareImages(aces, neutral, 2).differingPixels, 100);
    int checked = 0;
    for (int y = 0; y < none.height; ++y) {
        for (int x = 0; x < none.width; ++x) {
            const Rgba8 c = none.at(x, y), t = neutral.at(x, y);
            if (std::max({c.r, c.g, c.b}) >= 250) continue;  // clipped: the curve saw more
            const glm::dvec3 want =
                test::khrPbrNeutralReference(glm::dvec3(c.r, c.g, c.b) / 255.0) * 255.0;
            // The clamped picture's 8 bits hold the colour to ±0.5 / 255; the curve's slope is
            // at most 1; both round.
            EXPECT_NEAR(t.r, want.x, 1.5) << x << "," << y;
            EXPECT_NEAR(t.g, want.y, 1.5) << x << "," << y;
            EXPECT_NEAR(t.b, want.z, 1.5) << x << "," << y;
            ++checked;
        }
    }
    EXPECT_GT(checked, 96 * 64 / 2);
    // auto's choice is said; a tone mapping given is not.
    const CliRun noted = run(fmt::format("render {} --views 1 --size 32x24 -o t", file));
    EXPECT_NE(noted.err.find("note: --tonemap auto chose khr-neutral"), std::string::npos)
        << noted.err;
    const CliRun given = run(fmt::format("render {} --tonemap aces --views 1 --size 32x24 -o t", file));
    EXPECT_EQ(given.err.find("--tonemap auto"), std::string::npos) << given.err;
    // The default scene's lights are mvr's: auto is none.
    const Image def = render("", "d");
    EXPECT_EQ(compareImages(def, render("--tonemap none", "dn")).differingPixels, 0);
    EXPECT_GT(compareImages(def, render("--tonemap aces", "da"), 2).differingPixels, 100);
    expectError("render --tonemap filmic", 1,
                "--tonemap filmic: not a tone mapping (expected none, khr-neutral, aces or auto)");
}

// --specular per-view (issue 39 item 1): each view's highlights from its own eye. The centre
// view of an odd row is the centre eye, so its image is --specular center's pixel for pixel
// (vertex shading, the default, becomes pixel, with a note); the outer views differ; flat
// shading and a bad name are usage errors.
TEST_F(Cli, SpecularPerViewShadesEachViewFromItsEye) {
    const std::string rig = "render --views 3 --interaxial 0.6 --size 96x64";
    const CliRun centre = run(rig + " --shading pixel -o c");
    ASSERT_EQ(centre.exitCode, 0) << centre.err;
    const CliRun perView = run(rig + " --specular per-view -o p");
    ASSERT_EQ(perView.exitCode, 0) << perView.err;
    EXPECT_NE(perView.err.find("note: --specular per-view shades per pixel"), std::string::npos)
        << perView.err;
    for (int v = 0; v < 3; ++v) {
        auto a = readPng(mDir / "c" / fmt::format("view-{}.png", v));
        auto b = readPng(mDir / "p" / fmt::format("view-{}.png", v));
        ASSERT_TRUE(a && b) << v;
        const ImageDiff d = compareImages(*a, *b, 1);
        if (v == 1) {
            EXPECT_EQ(compareImages(*a, *b).differingPixels, 0);
        } else {
            EXPECT_GT(d.differingPixels, 20) << "view " << v;  // the highlights moved
        }
    }
    expectError("render --specular eye", 1,
                "--specular eye: not a shading eye (expected center or per-view)");
    expectError("render --specular per-view --shading flat", 1,
                "--specular per-view needs --shading pixel or vertex (flat shading has no "
                "highlight)");
}

TEST_F(Cli, TextureMapsAreDrawnPerPixelAndTheirFaultsSaid) {
    const auto file = test::writeMapsGltf(mDir);
    // The default vertex shading becomes pixel for the metallic-roughness maps, said once; the
    // maps the file gets wrong are warnings naming them.
    const CliRun r = run(fmt::format("render {} --views 2 --size 64x48 -o m", file.string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("note: the scene's metallic-roughness and normal maps shade per pixel"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("material 'Moved': its occlusion texture reads other texture "
                         "coordinates"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("texture 'gone.png': file not found: the map is not drawn"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("pixel shading"), std::string::npos) << r.out;
    // Asked for pixel shading, nothing to say; --strict refuses the missing map.
    const CliRun p = run(fmt::format("render {} --views 2 --size 64x48 --shading pixel -o p",
                                     file.string()));
    ASSERT_EQ(p.exitCode, 0) << p.err;
    EXPECT_EQ(p.err.find("shade per pixel"), std::string::npos) << p.err;
    expectError(fmt::format("render {} --strict -o s", file.string()), 2,
                "material 'Lost': texture 'gone.png': file not found");
}

/// A Radiance RGBE file of w × h flat texels of one value per half: `top` above the horizon
/// row, `bottom` below (values with an exact RGBE form: a power of two times k / 256).
void writeRadianceHalves(const std::filesystem::path& path, int w, int h, glm::vec3 top,
                         glm::vec3 bottom) {
    std::ofstream out(path, std::ios::binary);
    out << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << h << " +X " << w << "\n";
    for (int y = 0; y < h; ++y) {
        const glm::vec3 c = y < h / 2 ? top : bottom;
        const float v = std::max({c.x, c.y, c.z});
        int e = 0;
        const float m = std::frexp(v, &e) * 256.0f / v;
        for (int x = 0; x < w; ++x) {
            out << char(std::uint8_t(c.x * m)) << char(std::uint8_t(c.y * m))
                << char(std::uint8_t(c.z * m)) << char(std::uint8_t(e + 128));
        }
    }
}

TEST_F(Cli, AnEnvironmentMapLightsTheSceneAndTheSkyShowsIt) {
    writeRadianceHalves(mDir / "sky.hdr", 64, 32, {0.5f, 0.5f, 0.5f}, {0.25f, 0.125f, 0.0625f});
    // The map lights the surfaces (the background, no sky, stays the clear colour).
    for (const char* args : {"--environment sky.hdr -o e", "-o n", "--environment sky.hdr "
                                                                    "--exposure -1 -o h"}) {
        const CliRun r = run(fmt::format("render --views 2 --size 64x48 {}", args));
        ASSERT_EQ(r.exitCode, 0) << r.err;
    }
    auto e = readPng(mDir / "e/view-0.png"), n = readPng(mDir / "n/view-0.png"),
         h = readPng(mDir / "h/view-0.png");
    ASSERT_TRUE(e && n && h);
    EXPECT_EQ(e->at(0, 0).r, n->at(0, 0).r);
    int lit = 0, halved = 0, unsaturated = 0;
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 64; ++x) {
            const Rgba8 a = e->at(x, y), b = n->at(x, y), c = h->at(x, y);
            lit += std::abs(a.g - b.g) > 8;
            // --exposure −1 halves the lights and the map alike: every unclamped pixel of the
            // lit scene halves (the clear colour aside).
            if (a.g < 250 && a.g != n->at(0, 0).g && a.g > 40) {
                ++unsaturated;
                halved += std::abs(c.g - a.g / 2.0) <= 1.5;
            }
        }
    }
    EXPECT_GT(lit, 64 * 48 / 4);
    EXPECT_GT(unsaturated, 64 * 48 / 4);
    EXPECT_GT(halved, unsaturated * 95 / 100) << halved << " of " << unsaturated;
    // The sky is the map: the top corner looks up into the upper half, radiance 0.5 shown as
    // 0.5 · 255 → 128; --exposure 1 doubles it to full.
    for (const char* args : {"-o s", "--exposure 1 -o x"}) {
        const CliRun r = run(fmt::format(
            "render --environment sky.hdr --sky environment --views 2 --size 64x48 {}", args));
        ASSERT_EQ(r.exitCode, 0) << r.err;
    }
    auto s = readPng(mDir / "s/view-0.png"), x = readPng(mDir / "x/view-0.png");
    ASSERT_TRUE(s && x);
    EXPECT_EQ(s->at(0, 0).r, 128);
    EXPECT_EQ(s->at(0, 0).b, 128);
    EXPECT_EQ(x->at(0, 0).r, 255);
    // The faults: one line naming the option and the file.
    expectError("render --sky environment", 1,
                "--sky environment needs --environment MAP (the map to show)");
    expectError("render --environment nosuch.hdr", 2,
                "--environment 'nosuch.hdr': file not found");
    writeRadianceHalves(mDir / "wide.hdr", 48, 16, glm::vec3(1.0f), glm::vec3(1.0f));
    expectError("render --environment wide.hdr", 1,
                "--environment 'wide.hdr': 48x16 is neither an equirectangular map");
    // Occlusion maps in flat shading cannot darken the map's light: said.
    const auto file = test::writeMapsGltf(mDir);
    const CliRun flat = run(fmt::format(
        "render {} --environment sky.hdr --shading flat --views 2 --size 64x48 -o f",
        file.string()));
    ASSERT_EQ(flat.exitCode, 0) << flat.err;
    EXPECT_NE(flat.err.find("note: in flat shading the scene's occlusion maps do not darken the "
                            "environment's light"),
              std::string::npos)
        << flat.err;
}

/// A glTF of one quad (mesh 0: corners `pos`, normal +Z, in a data URI) after `head`, the JSON
/// members before "meshes" (asset, scenes, nodes, cameras, lights, materials); `material`:
/// whether the quad uses material 0.
std::string quadGltf(const std::array<float, 12>& pos, const std::string& head, bool material) {
    const float nrm[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::uint16_t idx[] = {0, 1, 2, 0, 2, 3};
    std::string bin(reinterpret_cast<const char*>(pos.data()), sizeof(float) * pos.size());
    bin.append(reinterpret_cast<const char*>(nrm), sizeof nrm);
    bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
    glm::vec3 lo(pos[0], pos[1], pos[2]), hi = lo;
    for (std::size_t i = 3; i < pos.size(); i += 3) {
        lo = glm::min(lo, glm::vec3(pos[i], pos[i + 1], pos[i + 2]));
        hi = glm::max(hi, glm::vec3(pos[i], pos[i + 1], pos[i + 2]));
    }
    return head +
           fmt::format(
               R"("meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2{}}}]}}],)"
               R"("accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",)"
               R"("min":[{},{},{}],"max":[{},{},{}]}},)"
               R"({{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"}},)"
               R"({{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}}],)"
               R"("bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},)"
               R"({{"buffer":0,"byteOffset":48,"byteLength":48}},)"
               R"({{"buffer":0,"byteOffset":96,"byteLength":12}}],)"
               R"("buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]}})",
               material ? R"(,"material":0)" : "", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z,
               bin.size(), test::base64(bin));
}

/// A plane z = 0 (8 x 8, albedo 0.8) seen from (0, 0, 6) down -Z (yfov 0.9) and one point light
/// at (0, 0, 1) of `intensity` with `range` (0: not written). As a .gltf with data URIs.
std::string planeWithPointLight(float intensity, float range) {
    return quadGltf(
        {-4, -4, 0, 4, -4, 0, 4, 4, 0, -4, 4, 0},
        fmt::format(
            R"({{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_lights_punctual"],)"
            R"("extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"point","intensity":{}{}}}]}}}},)"
            R"("scene":0,"scenes":[{{"nodes":[0,1,2]}}],)"
            R"("nodes":[{{"mesh":0}},{{"camera":0,"translation":[0,0,6]}},)"
            R"({{"translation":[0,0,1],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}}],)"
            R"("cameras":[{{"type":"perspective","perspective":{{"yfov":0.9,"znear":0.1,"zfar":50}}}}],)"
            R"("materials":[{{"pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.8,0.8,1]}}}}],)",
            intensity, range > 0 ? fmt::format(",\"range\":{}", range) : ""),
        true);
}

// A file camera at (0, 0, 6) (yfov 0.9: the frame's half-height at the plane z = 0 is
// 6 tan 0.45 = 2.90) over the quad x0..x1, y0..y1 of that plane.
std::string quadUnderFileCamera(float x0, float y0, float x1, float y1) {
    return quadGltf(
        {x0, y0, 0, x1, y0, 0, x1, y1, 0, x0, y1, 0},
        R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],)"
        R"("nodes":[{"mesh":0},{"camera":0,"name":"Shot","translation":[0,0,6]}],)"
        R"("cameras":[{"type":"perspective","perspective":{"yfov":0.9,"znear":0.05,"zfar":1000000}}],)",
        false);
}

// A file camera that cuts the scene off on one side says so and names the way out; one whose
// frame the scene fills on every side (a ground plane, a room) does not; --no-file-camera
// frames the whole scene, silently.
TEST_F(Cli, AFileCameraThatCutsTheSceneOffSaysSo) {
    const auto cut = write("cut.gltf", quadUnderFileCamera(-1, -6, 1, 0.5f));
    const CliRun r = run(fmt::format("render '{}' --views 1 --size 64x48 -o cut", cut.string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning: the file's camera 'Shot' cuts the scene off at the bottom ("),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("--no-file-camera frames the whole scene"), std::string::npos) << r.err;
    const CliRun framed = run(
        fmt::format("render '{}' --views 1 --size 64x48 --no-file-camera -o f", cut.string()));
    ASSERT_EQ(framed.exitCode, 0) << framed.err;
    EXPECT_EQ(framed.err.find("warning"), std::string::npos) << framed.err;
    const auto ground = write("ground.gltf", quadUnderFileCamera(-40, -40, 40, 40));
    const CliRun filled =
        run(fmt::format("render '{}' --views 1 --size 64x48 -o g", ground.string()));
    ASSERT_EQ(filled.exitCode, 0) << filled.err;
    EXPECT_EQ(filled.err.find("warning"), std::string::npos) << filled.err;
}

// KHR_lights_punctual's range: a point light at height 1 over the plane with range 2 lights
// the disc of radius sqrt(2² - 1²) around its foot and nothing beyond (computed here). A pixel
// of the plane at radius 2.2 gets what an unlit render (intensity 0) gives it, exactly; at
// radius 1.2 it is lit. Without the range both are lit.
TEST_P(CliGltfBackends, PointLightRangeLeavesWhatLiesBeyondItUnlit) {
    const std::string backend = GetParam();
    if (backend != "soft" && run("info").out.find("backend " + backend) == std::string::npos)
        MVR_SKIP(FeatureNotBuilt) << "no " << backend << " backend in this build";
    const float height = 1.0f, range = 2.0f;
    const float litRadius = std::sqrt(range * range - height * height);  // 1.732
    const int w = 160, h = 120;
    auto render = [&](const std::string& file, float intensity, float r) -> std::optional<Image> {
        const auto model = write(file, planeWithPointLight(intensity, r));
        const CliRun run1 =
            run(fmt::format("render '{}' --backend {} --views 1 --size {}x{} "
                            "--shading pixel -o '{}'",
                            model.string(), backend, w, h, file + ".out"));
        if (run1.exitCode != 0) {
            ADD_FAILURE() << run1.err;
            return std::nullopt;
        }
        auto img = readPng(mDir / (file + ".out") / "view-0.png");
        if (!img) return std::nullopt;
        return std::move(*img);
    };
    // Where a point (x, 0, 0) of the plane lands: the camera at (0, 0, 6), yfov 0.9.
    auto pixel = [&](float x) {
        const float ndc = x / (6.0f * std::tan(0.45f)) / (float(w) / float(h));
        return glm::ivec2(int((ndc * 0.5f + 0.5f) * w), h / 2);
    };
    const glm::ivec2 inside = pixel(1.2f), beyond = pixel(2.2f);
    ASSERT_LT(1.2f, litRadius);
    ASSERT_GT(2.2f, litRadius);
    const auto ranged = render("ranged.gltf", 1.0f, range);
    if (!ranged) return;
    const auto unlit = render("unlit.gltf", 0.0f, range);
    const auto infinite = render("infinite.gltf", 1.0f, 0.0f);
    ASSERT_TRUE(unlit && infinite);
    auto value = [](const Image& img, glm::ivec2 p) {
        const Rgba8 c = img.at(p.x, p.y);
        return int(c.r) + c.g + c.b;
    };
    EXPECT_EQ(value(*ranged, beyond), value(*unlit, beyond)) << backend;
    EXPECT_GT(value(*ranged, inside), value(*unlit, inside) + 15) << backend;
    EXPECT_GT(value(*infinite, beyond), value(*unlit, beyond) + 15) << backend;
}

// --exposure (framing.h's exposeLights): the plane's point light stands 1 unit above the
// scene's centre, so it lights the centre at `intensity` x full colour (1/d², d = 1: computed
// here). A file at 1000 saturates: a warning says so and names the cure; --exposure auto scales
// it to 1 (the render equals the intensity-1 file's within 1/255: 2^-log2(1000) is 1/1000 up
// to float rounding); --exposure -1 of an intensity-2 file is the intensity-1 file exactly.
TEST_P(CliGltfBackends, ExposureScalesTheFilesLights) {
    const std::string backend = GetParam();
    if (backend != "soft" && run("info").out.find("backend " + backend) == std::string::npos)
        MVR_SKIP(FeatureNotBuilt) << "no " << backend << " backend in this build";
    auto render = [&](const std::string& file, float intensity, const std::string& extra,
                      std::string* err) -> std::optional<Image> {
        const auto model = write(file, planeWithPointLight(intensity, 0.0f));
        const CliRun r = run(fmt::format("render '{}' --backend {} --views 1 --size 160x120 "
                                         "--shading pixel {} -o '{}'",
                                         model.string(), backend, extra, file + ".out"));
        if (err) *err = r.err;
        if (backend != "soft" && r.exitCode == 3) return std::nullopt;
        EXPECT_EQ(r.exitCode, 0) << r.err;
        auto img = readPng(mDir / (file + ".out") / "view-0.png");
        if (!img) return std::nullopt;
        return std::move(*img);
    };
    std::string err;
    const auto one = render("one.gltf", 1.0f, "", &err);
    if (!one) MVR_SKIP(MethodUnsupportedByDriver) << err;
    EXPECT_EQ(err.find("warning"), std::string::npos) << err;
    const auto bright = render("bright.gltf", 1000.0f, "", &err);
    ASSERT_TRUE(bright);
    EXPECT_NE(err.find("warning: the lights of "), std::string::npos) << err;
    EXPECT_NE(err.find("at 1e+03x full colour"), std::string::npos) << err;
    // The file's lights chose khr-neutral (--tonemap auto), which compresses but cannot save
    // a scene this bright; the note says what was chosen.
    EXPECT_NE(err.find("surfaces wash out to white"), std::string::npos) << err;
    EXPECT_NE(err.find("note: --tonemap auto chose khr-neutral"), std::string::npos) << err;
    EXPECT_NE(err.find("--exposure auto"), std::string::npos) << err;
    EXPECT_GT(compareImages(*one, *bright, 2).differingPixels, 160 * 120 / 4) << backend;
    const auto autoExposed = render("auto.gltf", 1000.0f, "--exposure auto", &err);
    ASSERT_TRUE(autoExposed);
    EXPECT_NE(err.find("note: --exposure auto chose -9.97 EV"), std::string::npos) << err;
    EXPECT_EQ(compareImages(*one, *autoExposed, 1).differingPixels, 0) << backend;
    const auto halved = render("two.gltf", 2.0f, "--exposure -1", &err);
    ASSERT_TRUE(halved);
    EXPECT_EQ(compareImages(*one, *halved, 0).differingPixels, 0) << backend;
    EXPECT_EQ(one->rgba, halved->rgba) << backend;
    // Nonsense is refused, naming the option.
    const auto model = write("bad.gltf", planeWithPointLight(1.0f, 0.0f));
    const CliRun bad = run(fmt::format("render '{}' --exposure 100 -o bad", model.string()));
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("error: --exposure 100 is out of range"), std::string::npos) << bad.err;
}

INSTANTIATE_TEST_SUITE_P(Backends, CliGltfBackends, ::testing::Values("soft", "gl"),
                         [](const auto& p) { return std::string(p.param); });

// --convergence auto measures the depths the rendered centre camera sees: the file's camera
// (frameScene()'s choice), not a camera framing the bounds. The chosen distance must lie within
// the depths of the fixture's geometry along the file camera's axis (computed here from the
// node transforms); the bounds camera (about 1.9 units nearer) would land before the nearest.
TEST_F(Cli, ConvergenceAutoMeasuresFromTheFileCamera) {
    using test::GltfFixtureTruth;
    const auto model = test::writeGltfFixture(mDir, "scene", test::GltfLayout::External);
    const CliRun r = run(
        fmt::format("render '{}' --backend soft --views 2 --size 120x80 --convergence auto -o o",
                    model.string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto at = r.out.find(", convergence ");
    ASSERT_NE(at, std::string::npos) << r.out;
    const float convergence = std::stof(r.out.substr(at + 14));
    float nearest = 1e9f, farthest = 0.0f;
    const float eyeZ = GltfFixtureTruth::cameraPosition().z;
    for (const glm::mat4& world : {GltfFixtureTruth::parent() * GltfFixtureTruth::childA(),
                                   GltfFixtureTruth::parent() * GltfFixtureTruth::childB()})
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 p((c & 1) ? 0.5f : -0.5f, (c & 2) ? 1.25f : -0.5f,
                              (c & 4) ? 0.5f : -0.5f);
            const float d = eyeZ - (world * glm::vec4(p, 1.0f)).z;  // along the camera's -Z
            nearest = std::min(nearest, d);
            farthest = std::max(farthest, d);
        }
    EXPECT_GE(convergence, nearest) << r.out;
    EXPECT_LE(convergence, farthest) << r.out;
    EXPECT_NE((r.out + r.err).find("--convergence auto chose"), std::string::npos) << r.err;
    // Framing the bounds instead: the distances are measured from that camera.
    const CliRun b =
        run(fmt::format("render '{}' --backend soft --views 2 --size 120x80 --convergence auto "
                        "--no-file-camera -o b",
                        model.string()));
    ASSERT_EQ(b.exitCode, 0) << b.err;
    const auto bt = b.out.find(", convergence ");
    ASSERT_NE(bt, std::string::npos);
    EXPECT_LT(std::stof(b.out.substr(bt + 14)), nearest) << b.out;
}

TEST_F(Cli, GltfSceneWithGridAndStereo) {
    const auto model = test::writeGltfFixture(mDir, "scene", test::GltfLayout::DataUri);
    const CliRun r = run(fmt::format("render '{}' --grid 3 --size 96x64 -o g", model.string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(readPng(mDir / "g/view-1.png"));
}

TEST_F(Cli, ModelsArePlacedFromTheCommandLine) {
    const auto model = write("tri.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    const int w = 160, h = 80;
    // Two copies side by side, the right one half size and turned; --no-file-camera is moot.
    const CliRun r =
        run(fmt::format("render '{0}@-3,0,0' '{0}@3,0,0,0.5,30' --backend soft "
                        "--views 1 --size {1}x{2} -o p",
                        model.string(), w, h));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto img = readPng(mDir / "p/view-0.png");
    ASSERT_TRUE(img);
    const Rgba8 bg = img->at(0, 0);
    long left = 0, right = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (!isBackground(img->at(x, y), bg)) ++(x < w / 2 ? left : right);
    EXPECT_GT(left, 100);
    EXPECT_GT(right, 20);
    EXPECT_LT(right, left);  // half size (and turned): a smaller picture
    // A file whose name contains '@' is read under its whole name.
    const auto at = write("a@1,2,3.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(run(fmt::format("render '{}' --size 32x32 -o a", at.string())).exitCode, 0);
    // Bad placements.
    expectError(fmt::format("render '{}@1,2'", model.string()), 1,
                "placement '1,2' has 2 numbers (expected FILE@X,Y,Z[,SCALE[,YAW]]");
    expectError(fmt::format("render '{}@1,2,x'", model.string()), 1,
                "placement '1,2,x' is not a list of numbers");
    expectError(fmt::format("render '{}@1,2,3,0'", model.string()), 1,
                "placement '1,2,3,0' has SCALE = 0 out of range");
    expectError(fmt::format("render '{}@1,2,3,1,2,3'", model.string()), 1,
                "placement '1,2,3,1,2,3' has 6 numbers");
    expectError(fmt::format("render '{}@1e99,0,0'", model.string()), 1,
                "has X = 1e+99 out of range (|X|, |Y|, |Z| at most 1e+06");
    expectError(fmt::format("render '{}@1,2,3'", (mDir / "missing.obj").string()), 2,
                "missing.obj: file not found");
}

TEST_F(Cli, BadTextureIsOneErrorLineNamingFileAndMaterial) {
    const std::string junk = "not a png";
    const auto model = test::writeGltfFixture(mDir, "bad", test::GltfLayout::External, &junk);
    expectError(fmt::format("render '{}' --size 32x32", model.string()), 2,
                "material 'Checker': texture 'bad.png': not a readable PNG");
}

}  // namespace
}  // namespace mvr
