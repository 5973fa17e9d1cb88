// Issue 42, items 3 and 4, end to end through the built `mvr`:
//  - `--format rgbd`: the Looking Glass RGB-D image (the centre view's colour and its depth side
//    by side, white = near) and its rgbd.json. A scene of two planes at known distances: the
//    depth at pixels on each plane decodes, by the formula written here, to that plane's distance.
//  - `--view-range A:B`: pieces of a render, assembled, equal the whole render byte for byte.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "mvr/io/png.h"

namespace mvr {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::runMvr;
using Json = nlohmann::json;

class CliRgbdViewRange : public ::testing::Test {
protected:
    void SetUp() override {
        MVR_REQUIRE_MVR_BINARY(test::mvrBinary());
        const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        mDir = fs::temp_directory_path() / fmt::format("mvr-rgbd-range-{}-{}", ::getpid(), name);
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }

    /// Three quads facing +Z, all y in [-3, 3], their bounds centred on the origin (a plain
    /// mesh is placed with its bounds' centre at the origin): the near one at z = 1 on the left
    /// (x in [-6, -1.8]), a middle one at z = 0 (x in [-1.5, 1.5]), the far one at z = -1 on
    /// the right (x in [2, 6]).
    fs::path writePlanes() const {
        const fs::path obj = mDir / "planes.obj";
        std::ofstream(obj) << "v -6 -3 1\nv -1.8 -3 1\nv -1.8 3 1\nv -6 3 1\n"
                              "v -1.5 -3 0\nv 1.5 -3 0\nv 1.5 3 0\nv -1.5 3 0\n"
                              "v 2 -3 -1\nv 6 -3 -1\nv 6 3 -1\nv 2 3 -1\n"
                              "f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\nf 9 10 11\nf 9 11 12\n";
        return obj;
    }

    /// The camera 10 units in front of the middle plane, looking down -Z: the planes are 9, 10
    /// and 11 along the view axis.
    static std::string camera() {
        return "--camera-position 0,0,10 --look-at 0,0,0 --fov 45 --size 64x48";
    }

    /// One `error:` line (a value CLI11's checks refuse is followed by the usage hint line,
    /// docs/errors.md), exit 1.
    static void expectOneError(const CliRun& r, const std::string& start) {
        EXPECT_EQ(r.exitCode, 1) << r.err;
        EXPECT_EQ(r.err.rfind("error: " + start, 0), 0u) << r.err;
        std::size_t errors = 0;
        for (std::size_t at = r.err.find("error:"); at != std::string::npos;
             at = r.err.find("error:", at + 1))
            ++errors;
        EXPECT_EQ(errors, 1u) << r.err;
        EXPECT_EQ(r.err.find("warning:"), std::string::npos) << r.err;
    }

    fs::path mDir;
};

// ---- rgbd -------------------------------------------------------------------------------------

TEST_F(CliRgbdViewRange, RgbdDepthDecodesToThePlanesDistances) {
    const fs::path obj = writePlanes();
    for (const char* views : {"1", "3"}) {
        const fs::path out = mDir / fmt::format("out{}", views);
        const CliRun r = runMvr(mDir, fmt::format("render '{}' {} --views {} --format rgbd "
                                                  "--depthiness 1.5 --focus -0.01 "
                                                  "--write-cameras -o '{}'",
                                                  obj.string(), camera(), views, out.string()));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        auto image = readPng(out / "rgbd.png");
        ASSERT_TRUE(image) << image.status().message();
        ASSERT_EQ(image->width, 128);  // colour left, depth right (Bridge's depth_loc 2)
        ASSERT_EQ(image->height, 48);
        const Json side = Json::parse(test::slurp(out / "rgbd.json"));
        EXPECT_EQ(side["type"], "rgbd");
        EXPECT_EQ(side["uri"], "rgbd.png");
        const Json& s = side["settings"];
        EXPECT_EQ(s["depth_loc"], 2);
        EXPECT_EQ(s["depth_inversion"], 0);
        EXPECT_EQ(s["chroma_depth"], 0);
        EXPECT_DOUBLE_EQ(s["depthiness"].get<double>(), 1.5);
        EXPECT_DOUBLE_EQ(s["focus"].get<double>(), -0.01);
        EXPECT_DOUBLE_EQ(s["aspect"].get<double>(), 64.0 / 48.0);
        const int centre = std::stoi(views) / 2;
        EXPECT_EQ(side["mvr"]["view"], centre);
        const double near = side["mvr"]["near"], far = side["mvr"]["far"];
        // Within the centre view's near and far planes, as cameras.json states them.
        const Json cams = Json::parse(test::slurp(out / "cameras.json"));
        EXPECT_GT(near, cams["views"][centre]["near"].get<double>());
        EXPECT_LT(far, cams["views"][centre]["far"].get<double>());
        // The range is the scene's as the view sees it: the nearest and the farthest plane.
        EXPECT_NEAR(near, 9.0, 1e-3);
        EXPECT_NEAR(far, 11.0, 1e-3);
        // White = near: grey g decodes to far - g / 255 (far - near), within half a step.
        auto decode = [&](int x, int y) {
            const Rgba8 p = image->at(64 + x, y);
            EXPECT_EQ(p.r, p.g);
            EXPECT_EQ(p.g, p.b);
            return far - p.r / 255.0 * (far - near);
        };
        const double tolerance = (far - near) / 510.0 + 1e-3;
        // Pixel (x, y) looks along ndc ((x + 0.5) / 32 - 1, 1 - (y + 0.5) / 24): at distance d
        // it sees x_world = ndc_x · d · tan(22.5°) · 4/3. Column 12 sees x = -3.0 on the near
        // plane (d = 9), column 32 x = +0.09 on the middle one (10), column 52 x = +3.9 on the
        // far one (11); row 24 sees y = -0.09. Their neighbours too (3 pixels: under 0.6 units).
        for (int dy : {-4, 0, 4}) {
            for (int dx : {-3, 0, 3}) {
                EXPECT_NEAR(decode(12 + dx, 24 + dy), 9.0, tolerance) << views;
                EXPECT_NEAR(decode(32 + dx, 24 + dy), 10.0, tolerance) << views;
                EXPECT_NEAR(decode(52 + dx, 24 + dy), 11.0, tolerance) << views;
            }
        }
        EXPECT_EQ(image->at(64 + 12, 24).r, 255);  // the nearest: white
        EXPECT_EQ(image->at(64 + 52, 24).r, 0);    // the farthest: black
        // Nothing drawn (above the planes: y > 3 at row 0) is black.
        EXPECT_EQ(image->at(64 + 16, 0).r, 0);
        // The colour half is the centre view, pixel for pixel.
        auto view = readPng(out / fmt::format("view-{}.png", centre));
        ASSERT_TRUE(view) << view.status().message();
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 64; ++x) ASSERT_EQ(image->at(x, y), view->at(x, y)) << x << "," << y;
    }
}

TEST_F(CliRgbdViewRange, RgbdDepthPositions) {
    const fs::path obj = writePlanes();
    for (const auto& [side, loc, w, h, dx, dy] :
         {std::tuple{"left", 3, 128, 48, 0, 0}, std::tuple{"top", 0, 64, 96, 0, 0},
          std::tuple{"bottom", 1, 64, 96, 0, 48}, std::tuple{"right", 2, 128, 48, 64, 0}}) {
        const fs::path out = mDir / side;
        const CliRun r = runMvr(mDir, fmt::format("render '{}' {} --views 1 --format rgbd "
                                                  "--rgbd-depth-position {} -o '{}'",
                                                  obj.string(), camera(), side, out.string()));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        auto image = readPng(out / "rgbd.png");
        ASSERT_TRUE(image);
        EXPECT_EQ(image->width, w) << side;
        EXPECT_EQ(image->height, h) << side;
        EXPECT_EQ(Json::parse(test::slurp(out / "rgbd.json"))["settings"]["depth_loc"], loc);
        // The depth image, wherever it lies: near white, middle grey, far black.
        EXPECT_EQ(image->at(dx + 12, dy + 24).r, 255) << side;
        EXPECT_NEAR(image->at(dx + 32, dy + 24).r, 127.5, 1.0) << side;
        EXPECT_EQ(image->at(dx + 52, dy + 24).r, 0) << side;
    }
}

TEST_F(CliRgbdViewRange, RgbdInEveryFrameOfASequence) {
    const fs::path out = mDir / "seq";
    const CliRun r = runMvr(mDir, "render --views 3 --size 32x24 --format rgbd --frames 2 "
                                  "--orbit 20 -q -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* frame : {"frame-0000", "frame-0001"}) {
        auto image = readPng(out / frame / "rgbd.png");
        ASSERT_TRUE(image) << frame;
        EXPECT_EQ(image->width, 64);
        EXPECT_EQ(Json::parse(test::slurp(out / frame / "rgbd.json"))["mvr"]["view"], 1);
    }
}

TEST_F(CliRgbdViewRange, RgbdRefusals) {
    const fs::path obj = writePlanes();
    const std::string base = fmt::format("render '{}' {} ", obj.string(), camera());
    const fs::path out = mDir / "out";
    expectOneError(runMvr(mDir, base + "--format rgbd -o " + out.string()),
                   "--format rgbd: the RGB-D image is the rig's centre view, and a row of 2 "
                   "views has none");
    expectOneError(runMvr(mDir, base + "--views 3 --format rgbd --rgbd-depth-position middle"),
                   "--rgbd-depth-position 'middle': expected right, left, top or bottom");
    expectOneError(runMvr(mDir, base + "--views 1 --format rgbd --depthiness 5"),
                   "--depthiness: 5 is out of range");
    expectOneError(runMvr(mDir, base + "--views 1 --format rgbd --focus 0.5"),
                   "--focus: 0.5 is out of range");
    EXPECT_FALSE(fs::exists(out));
    // The options without an RGB-D image are said to be ignored.
    const CliRun r = runMvr(mDir, base + "--views 1 --depthiness 1.2 -o " + out.string());
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning: --depthiness is ignored without an RGB-D image"),
              std::string::npos)
        << r.err;
}

// --depthiness / --focus on the view-cone rig (session/cone_depth.h): the eyes' offsets of a
// 30-degree cone of 5 views, C·tan(θ_i), scaled by the depthiness; depthiness 0 gives identical
// views; the focus moves the focal plane by F of the scene's bounding-box diagonal.
TEST_F(CliRgbdViewRange, DepthinessAndFocusOnTheViewCone) {
    const fs::path obj = writePlanes();
    const std::string base = fmt::format("render '{}' {} --views 5 --view-cone 30 --aa 1 "
                                         "--angular-aa off --write-cameras -q ",
                                         obj.string(), camera());
    for (const char* run : {"-o cone", "--depthiness 0.5 -o half", "--depthiness 0 -o flat",
                            "--focus 0.05 -o focus", "--depthiness 2 --focus -0.05 -o both"}) {
        const CliRun r = runMvr(mDir, base + run);
        ASSERT_EQ(r.exitCode, 0) << run << "\n" << r.err;
    }
    auto cameras = [&](const char* dir) {
        std::ifstream in(mDir / dir / "cameras.json");
        return Json::parse(in);
    };
    auto eyeX = [&](const Json& j, int v) {
        return j["views"][v]["world_from_camera"][0][3].get<double>();
    };
    const double c = 10.0;  // the camera 10 in front of the middle plane: the default focal plane
    const double diagonal = std::sqrt(12.0 * 12.0 + 6.0 * 6.0 + 2.0 * 2.0);  // bounds 12 x 6 x 2
    const Json cone = cameras("cone"), half = cameras("half"), flat = cameras("flat"),
               focus = cameras("focus"), both = cameras("both");
    EXPECT_NEAR(focus["rig"]["convergence"].get<double>(), c - 0.05 * diagonal, 1e-4);
    EXPECT_NEAR(both["rig"]["convergence"].get<double>(), c + 0.05 * diagonal, 1e-4);
    for (int v = 0; v < 5; ++v) {
        const double t = std::tan((-15.0 + 7.5 * v) * M_PI / 180.0);
        EXPECT_NEAR(eyeX(cone, v), c * t, 1e-4) << v;
        EXPECT_NEAR(eyeX(half, v), 0.5 * c * t, 1e-4) << v;
        EXPECT_NEAR(eyeX(flat, v), 0.0, 1e-6) << v;
        EXPECT_NEAR(eyeX(focus, v), (c - 0.05 * diagonal) * t, 1e-4) << v;
        EXPECT_NEAR(eyeX(both, v), 2.0 * (c + 0.05 * diagonal) * t, 1e-4) << v;
        EXPECT_EQ(readPng(mDir / "flat" / fmt::format("view-{}.png", v))->rgba,
                  readPng(mDir / "flat" / "view-2.png")->rgba) << v;
    }
    EXPECT_NE(readPng(mDir / "cone" / "view-0.png")->rgba, readPng(mDir / "cone" / "view-4.png")->rgba);
    // Neither a cone nor an RGB-D image: said to be ignored; a sidecar below Bridge's 0.1: refused.
    const std::string plain = fmt::format("render '{}' {} --views 3 ", obj.string(), camera());
    CliRun r = runMvr(mDir, plain + "--depthiness 0.5 -o plain");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning: --depthiness is ignored without an RGB-D image (--format rgbd) "
                         "or a view cone"), std::string::npos) << r.err;
    expectOneError(runMvr(mDir, plain + "--view-cone 30 --format rgbd --depthiness 0 -o no"),
                   "--depthiness 0: the RGB-D sidecar takes Bridge's 0.1 .. 2");
}

// ---- view ranges ------------------------------------------------------------------------------

TEST_F(CliRgbdViewRange, RangesAssembleIntoTheWholeRenderByteForByte) {
    for (const std::string rig : {"--views 8", "--views 8 --view-cone 35"}) {
        const fs::path whole = mDir / "whole", parts = mDir / "parts", apart = mDir / "apart";
        fs::remove_all(whole);
        fs::remove_all(parts);
        fs::remove_all(apart);
        const std::string base = "render " + rig + " --size 64x48 --depth --write-cameras ";
        ASSERT_EQ(runMvr(mDir, base + "-o " + whole.string()).exitCode, 0);
        // Two ranges into one folder; and three into another, one of a single view.
        for (const char* range : {"0:3", "4:7"}) {
            const CliRun r = runMvr(mDir, base + "--view-range " + range + " -o " + parts.string());
            ASSERT_EQ(r.exitCode, 0) << r.err;
        }
        for (const char* range : {"0:0", "1:5", "6:7"}) {
            const fs::path dir = apart / range;
            ASSERT_EQ(runMvr(mDir, base + "--view-range " + range + " -o '" + dir.string() + "'")
                          .exitCode,
                      0);
        }
        for (int v = 0; v < 8; ++v) {
            for (const std::string& name :
                 {fmt::format("view-{}.png", v), fmt::format("depth-{}.png", v)}) {
                const std::string bytes = test::slurp(whole / name);
                ASSERT_FALSE(bytes.empty()) << name;
                EXPECT_EQ(test::slurp(parts / name), bytes) << rig << ": " << name;
                const char* range = v == 0 ? "0:0" : v <= 5 ? "1:5" : "6:7";
                EXPECT_EQ(test::slurp(apart / range / name), bytes) << rig << ": " << name;
            }
        }
        // Nothing else: no composite (the anaglyph of a pair, a quilt) in a range's folder.
        int files = 0;
        for (const auto& e : fs::directory_iterator(parts)) files += e.is_regular_file();
        EXPECT_EQ(files, 8 * 2 + 1);  // views, depths and the last range's cameras.json
        // cameras.json of a range: the whole rig's cameras of those views, numbered as in it.
        const Json all = Json::parse(test::slurp(whole / "cameras.json"));
        const Json part = Json::parse(test::slurp(parts / "cameras.json"));
        EXPECT_EQ(part["rig"]["view_range"], Json::array({4, 7}));
        ASSERT_EQ(part["views"].size(), 4u);
        for (int i = 0; i < 4; ++i) EXPECT_EQ(part["views"][i], all["views"][4 + i]) << i;
    }
    // The comfort report covers the range and says which.
    const fs::path report = mDir / "report.json";
    ASSERT_EQ(runMvr(mDir, "render --views 8 --size 32x24 --view-range 2:5 -q --report-json " +
                               report.string() + " -o " + (mDir / "r").string())
                  .exitCode,
              0);
    const Json j = Json::parse(test::slurp(report));
    EXPECT_EQ(j["rig"]["views"], 4);
    EXPECT_EQ(j["rig"]["view_range"], Json::array({2, 5}));
}

TEST_F(CliRgbdViewRange, RangeOfADisplayPresetWritesItsViews) {
    const fs::path out = mDir / "out";
    const CliRun r =
        runMvr(mDir, "render --display portrait --size 48x64 --view-range 20:23 -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("note: --view-range 20:23 writes views 20..23, not --display portrait's "
                         "quilt"),
              std::string::npos)
        << r.err;
    int files = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        ++files;
        const std::string name = e.path().filename().string();
        EXPECT_TRUE(name == "view-20.png" || name == "view-21.png" || name == "view-22.png" ||
                    name == "view-23.png")
            << name;
    }
    EXPECT_EQ(files, 4);
}

TEST_F(CliRgbdViewRange, BadRangesAreOneErrorLine) {
    const fs::path out = mDir / "out";
    const std::string base = "render --views 48 --size 16x12 -o " + out.string() + " ";
    expectOneError(runMvr(mDir, base + "--view-range 5:2"),
                   "--view-range '5:2' is out of range (expected 0 <= A <= B <= 47: views A..B "
                   "of the rig's 48)");
    expectOneError(runMvr(mDir, base + "--view-range 0:99"),
                   "--view-range '0:99' is out of range");
    expectOneError(runMvr(mDir, base + "--view-range a:b"),
                   "--view-range 'a:b' is not of the form A:B");
    expectOneError(runMvr(mDir, base + "--view-range 3"), "--view-range '3' is not of the form A:B");
    expectOneError(runMvr(mDir, base + "--view-range ''"), "--view-range '': expected a value");
    expectOneError(runMvr(mDir, base + "--view-range 0:3 --format quilt"),
                   "--view-range 0:3: not with --format quilt (a composite needs every view");
    expectOneError(runMvr(mDir, base + "--view-range 0:3 --write views,composites"),
                   "--view-range 0:3: not with --write views,composites");
    expectOneError(runMvr(mDir, "render --view-grid 3x2 --view-range 0:3 -o " + out.string()),
                   "--view-range 0:3: needs a row of views");
    expectOneError(runMvr(mDir, base + "--view-range 0:3 --frames 2"),
                   "--view-range 0:3: renders a still");
    EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace mvr
