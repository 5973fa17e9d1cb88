// `mvr compose IMAGE --from-rgbd --display NAME` end to end (mvr/session/rgbd_input.h, issue 43
// item 3): a plane at a known depth lands in every view where the view-cone geometry, computed
// here, puts it (mvr's own sidecar and a foreign depth map taken as disparity, --depthiness,
// --focus); an RGB-D render of a model composes to a quilt within a stated PSNR of the quilt
// rendered; the refusals with their messages.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"
#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

// The Portrait preset as docs/displays.md states it: 48 views of 420x560 in an 8x6 quilt
// (view 0 bottom left), picture aspect 0.75, a 40 degree view cone.
constexpr int kViews = 48, kW = 420, kH = 560, kCols = 8, kRows = 6;
constexpr double kAspect = 0.75, kConeDeg = 40.0, kPi = 3.14159265358979323846;

class RgbdComposeCli : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-rgbd-compose-test-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    test::CliRun run(const std::string& args) const { return test::runMvr(mDir, args); }

    void expectError(const std::string& args, int code, const std::string& line) const {
        const test::CliRun r = run(args);
        EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        EXPECT_EQ(r.err, "error: " + line + "\n") << args;
    }

    void write(const std::string& name, const Image& image) const {
        ASSERT_TRUE(writePng(mDir / name, image));
    }
    void writeText(const std::string& name, const std::string& text) const {
        std::ofstream(mDir / name) << text;
    }

    Image quilt(const std::string& dir) const {
        auto q = readPng(mDir / dir / "quilt_qs8x6a0.75.png");
        EXPECT_TRUE(q) << q.status().message();
        return q ? *q : Image();
    }

    std::filesystem::path mDir;
};

/// View v's tile of a Portrait quilt.
Image tile(const Image& quilt, int v) {
    const int x0 = (v % kCols) * kW, y0 = (kRows - 1 - v / kCols) * kH;
    Image out(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) out.set(x, y, quilt.at(x0 + x, y0 + y));
    return out;
}

/// A black picture with a white bar over columns [kBar0, kBar1) and a uniform depth `grey`.
constexpr int kBar0 = 200, kBar1 = 220;
Image barPicture() {
    Image im(kW, kH, {0, 0, 0, 255});
    for (int y = 0; y < kH; ++y)
        for (int x = kBar0; x < kBar1; ++x) im.set(x, y, {255, 255, 255, 255});
    return im;
}
Image greyPicture(int grey) {
    const auto g = static_cast<std::uint8_t>(grey);
    return Image(kW, kH, {g, g, g, 255});
}

/// The bar's centre in a view: the intensity-weighted mean pixel centre of its middle row.
double barCentre(const Image& view) {
    double sum = 0.0, weight = 0.0;
    for (int x = 0; x < kW; ++x) {
        const double v = view.at(x, kH / 2).r;
        sum += v * (x + 0.5);
        weight += v;
    }
    return weight > 0.0 ? sum / weight : -1.0;
}

/// Where the bar lands in view t when every pixel has the parallax factor a = 1 − C / w:
/// view t looks from C · tan θ_t · spread beside the centre (θ_t spread evenly over the cone),
/// the window at the focal plane is 2 · C · aspect · tan(fovY / 2) wide, so a point moves by
/// tan θ_t · spread / (aspect · tan(fovY / 2)) · a · W / 2 pixels.
double expectedCentre(int t, double a, double spread, double fovYDeg) {
    const double theta = (-kConeDeg / 2.0 + kConeDeg * t / (kViews - 1)) * kPi / 180.0;
    const double shear = std::tan(theta) * spread / (kAspect * std::tan(fovYDeg * kPi / 360.0));
    return (kBar0 + kBar1) / 2.0 + shear * a * kW / 2.0;
}

void expectBarAt(const Image& q, double a, double spread, double fovYDeg, const char* what) {
    for (int t = 0; t < kViews; ++t) {
        const double want = expectedCentre(t, a, spread, fovYDeg);
        EXPECT_NEAR(barCentre(tile(q, t)), want, 0.1) << what << ", view " << t;
    }
}

/// rgbd.json as mvr render writes it, with the camera.
std::string sidecar(double near, double far, double convergence, double fovY) {
    return fmt::format(R"({{"type": "rgbd", "uri": "pic.png", "settings": {{"depthiness": 1,
"focus": 0, "depth_loc": 2, "depth_inversion": 0, "chroma_depth": 0}}, "mvr": {{"view": 0,
"near": {}, "far": {}, "convergence": {}, "fov_y_degrees": {}}}}})",
                       near, far, convergence, fovY);
}

/// Colour and depth side by side, depth right.
Image sideBySide(const Image& colour, const Image& depth) {
    Image out(2 * kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            out.set(x, y, colour.at(x, y));
            out.set(kW + x, y, depth.at(x, y));
        }
    return out;
}

TEST_F(RgbdComposeCli, AKnownDepthLandsWhereTheViewConePutsIt) {
    // mvr's own RGB-D: grey 255 is `near` (3), grey 128 is 6 − 128/255 · 3; focal plane at 4.
    write("pic.png", sideBySide(barPicture(), greyPicture(255)));
    writeText("pic.json", sidecar(3.0, 6.0, 4.0, 45.0));
    test::CliRun r = run("compose pic.png --from-rgbd --display portrait -o near");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("composed 48 views of 420x560 for portrait from pic.png (depth in world "
                         "units from "),
              std::string::npos)
        << r.out;
    expectBarAt(quilt("near"), 1.0 - 4.0 / 3.0, 1.0, 45.0, "mvr sidecar, grey 255");

    write("pic.png", sideBySide(barPicture(), greyPicture(128)));
    writeText("pic.json", sidecar(3.0, 6.0, 4.0, 30.0));
    ASSERT_EQ(run("compose pic.png --from-rgbd --display portrait -q -o mid").exitCode, 0);
    expectBarAt(quilt("mid"), 1.0 - 4.0 / (6.0 - 128.0 / 255.0 * 3.0), 1.0, 30.0,
                "mvr sidecar, grey 128, 30 degrees");

    // --depthiness scales every parallax.
    ASSERT_EQ(run("compose pic.png --from-rgbd --display portrait --depthiness 0.5 -q -o half")
                  .exitCode,
              0);
    expectBarAt(quilt("half"), 1.0 - 4.0 / (6.0 - 128.0 / 255.0 * 3.0), 0.5, 30.0,
                "--depthiness 0.5");
}

TEST_F(RgbdComposeCli, AForeignDepthMapIsDisparity) {
    // No sidecar, two files: grey g is disparity, a = 0.5 + focus − g, mvr's 45 degrees.
    write("colour.png", barPicture());
    write("depth.png", greyPicture(255));
    ASSERT_EQ(run("compose colour.png depth.png --from-rgbd --display portrait -q -o white")
                  .exitCode,
              0);
    expectBarAt(quilt("white"), -0.5, 1.0, 45.0, "grey 255");
    ASSERT_EQ(run("compose colour.png depth.png --from-rgbd --display portrait --focus 0.05 -q "
                  "-o focus")
                  .exitCode,
              0);
    expectBarAt(quilt("focus"), -0.45, 1.0, 45.0, "grey 255, --focus 0.05");
    // Grey 0 behind the focal plane: the bar moves the other way.
    write("depth.png", greyPicture(0));
    ASSERT_EQ(run("compose colour.png depth.png --from-rgbd --display portrait -q -o black")
                  .exitCode,
              0);
    expectBarAt(quilt("black"), 0.5, 1.0, 45.0, "grey 0");
    // The depth on the left of one picture (--rgbd-depth-position) is the same input.
    Image left(2 * kW, kH);
    const Image bar = barPicture();
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            left.set(x, y, {0, 0, 0, 255});
            left.set(kW + x, y, bar.at(x, y));
        }
    write("left.png", left);
    ASSERT_EQ(run("compose left.png --from-rgbd --rgbd-depth-position left --display portrait -q "
                  "-o left")
                  .exitCode,
              0);
    EXPECT_TRUE(quilt("left") == quilt("black"));
}

TEST_F(RgbdComposeCli, APictureOfAnotherSizeIsCroppedAndResampled) {
    // The bar picture and its depth at twice the view size: area-averaged 2x2 to the same
    // pixels, hence the same quilt; and inside a wider picture: cropped about the centre.
    const Image bar = barPicture();
    Image big(2 * kW, 2 * kH), wide(kW + 300, kH, {90, 20, 200, 255});
    for (int y = 0; y < 2 * kH; ++y)
        for (int x = 0; x < 2 * kW; ++x) big.set(x, y, bar.at(x / 2, y / 2));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) wide.set(150 + x, y, bar.at(x, y));
    write("colour.png", bar);
    write("big.png", big);
    write("wide.png", wide);
    write("depth.png", greyPicture(230));
    write("bigdepth.png", Image(2 * kW, 2 * kH, {230, 230, 230, 255}));
    write("widedepth.png", Image(kW + 300, kH, {230, 230, 230, 255}));
    for (const char* args : {"colour.png depth.png -o plain", "big.png bigdepth.png -o big",
                             "wide.png widedepth.png -o wide"})
        ASSERT_EQ(run(fmt::format("compose {} --from-rgbd --display portrait -q", args)).exitCode,
                  0)
            << args;
    EXPECT_TRUE(quilt("big") == quilt("plain"));
    EXPECT_TRUE(quilt("wide") == quilt("plain"));
    // A depth map smaller than its colour (as phones write them), over the same frame.
    write("halfdepth.png", Image(kW / 2, kH / 2, {230, 230, 230, 255}));
    ASSERT_EQ(run("compose colour.png halfdepth.png --from-rgbd --display portrait -q -o half")
                  .exitCode,
              0);
    EXPECT_TRUE(quilt("half") == quilt("plain"));
    expectBarAt(quilt("plain"), 0.5 - 230.0 / 255.0, 1.0, 45.0, "grey 230");
}

TEST_F(RgbdComposeCli, ARenderedModelComposesCloseToItsRenderedQuilt) {
    const std::filesystem::path spot = test::sharedModels() / "spot.obj";
    if (!std::filesystem::exists(spot))
        MVR_SKIP(ModelsMissing) << "no spot.obj in " << test::sharedModels();
    const std::string model = fmt::format("'{}'", spot.string());
    // The centre camera's RGB-D and the display's 48 views, one sample a pixel.
    ASSERT_EQ(run(fmt::format("render {} --display portrait --views 1 --aa 1 --format rgbd -q -o "
                              "rgbd",
                              model))
                  .exitCode,
              0);
    ASSERT_EQ(run(fmt::format("render {} --display portrait --aa 1 -q -o exact", model)).exitCode,
              0);
    const test::CliRun r = run("compose rgbd/rgbd.png --from-rgbd --display portrait -o warped");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Image warped = quilt("warped"), exact = quilt("exact");
    ASSERT_EQ(warped.width, exact.width);
    // Measured: 31.8 dB over the quilt, 27.6 dB at the outermost views (what the centre camera
    // does not see of the cow's flanks); the central views 47 dB.
    EXPECT_GE(compareImages(warped, exact).psnr, 30.0);
    for (int t : {0, kViews - 1}) EXPECT_GE(compareImages(tile(warped, t), tile(exact, t)).psnr, 26.0);
    for (int t : {23, 24}) EXPECT_GE(compareImages(tile(warped, t), tile(exact, t)).psnr, 40.0);
}

TEST_F(RgbdComposeCli, Refusals) {
    write("pic.png", sideBySide(barPicture(), greyPicture(200)));
    write("odd.png", Image(kW + 1, kH));
    expectError("compose pic.png --from-rgbd -o out",
                1, "--from-rgbd needs --display NAME, the light-field display whose views to "
                "make (`mvr info --displays` lists them)");
    expectError("compose pic.png --from-rgbd --display 3dtv -o out", 1,
                "--display 3dtv: --from-rgbd needs a light-field display (a view cone; `mvr info "
                "--displays` lists them)");
    expectError("compose pic.png pic.png --display portrait -o out", 1,
                "--display portrait: mvr compose takes a display only with --from-rgbd (to "
                "compose rendered views for a display, give its --format and --quilt)");
    expectError("compose pic.png pic.png pic.png --from-rgbd --display portrait -o out", 1,
                "--from-rgbd: 3 files given (expected one RGB-D picture, colour and depth side "
                "by side, or two: colour then depth)");
    expectError("compose odd.png --from-rgbd --display portrait -o out", 2,
                "odd.png: 421x560 cannot hold colour and depth side by side with the depth right "
                "(expected an even width; --rgbd-depth-position says where the depth lies)");
    write("small.png", Image(10, 10));
    expectError("compose pic.png small.png --from-rgbd --display portrait -o out", 2,
                "small.png is 10x10 but the colour pic.png is 840x560 (expected a depth map of "
                "the colour's frame: the same aspect, any size)");
    writeText("pic.json", "{\"settings\": {\"depth_loc\": 2");
    const test::CliRun r = run("compose pic.png --from-rgbd --display portrait -o out");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err.rfind("error: pic.json: not JSON (", 0), 0u) << r.err;
    writeText("pic.json", R"({"settings": {"depth_loc": 7}})");
    expectError("compose pic.png --from-rgbd --display portrait -o out", 2,
                "pic.json: \"settings\".\"depth_loc\" is 7 (expected 0 top, 1 bottom, 2 right "
                "or 3 left)");
    writeText("pic.json", R"({"mvr": {"near": 5, "far": 2, "convergence": 3, "fov_y_degrees": 45}})");
    expectError("compose pic.png --from-rgbd --display portrait -o out", 2,
                "pic.json: \"mvr\" near 5 and far 2 (expected 0 < near < far)");
    expectError("compose missing.png --from-rgbd --display portrait -o out", 2,
                "missing.png: file not found");
    EXPECT_FALSE(std::filesystem::exists(mDir / "out"));
}

}  // namespace
}  // namespace mvr
