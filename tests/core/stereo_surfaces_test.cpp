// Sky at infinity, floating window, letterbox and 2D at depth (mvr/core/stereo_surfaces.h),
// checked against numbers computed here from the camera parameters, not through rig.h's
// separation(): separation = interaxial / (2 · convergence · aspect · tan(fovY / 2)).
#include "mvr/core/stereo_surfaces.h"

#include <cmath>
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "mvr/io/png.h"
#include "mvr/io/scene_io.h"
#include "test_files.h"

namespace mvr {
namespace {

constexpr int kW = 240, kH = 160;

struct StereoPair {
    Camera camera;
    RigParams params;
    Rig rig;
    float separation = 0;  ///< computed independently
};

StereoPair pair(float interaxial = 0.4f, float convergence = 5.0f) {
    StereoPair s;
    s.camera.aspect = float(kW) / float(kH);
    s.camera.near = 0.5f;
    s.camera.far = 50.0f;
    s.params.columns = 2;
    s.params.interaxial = interaxial;
    s.params.convergence = convergence;
    s.rig = *makeRig(s.camera, s.params);
    const float tanHalf = std::tan(glm::radians(s.camera.fovYDegrees) * 0.5f);
    s.separation = interaxial / (2.0f * convergence * s.camera.aspect * tanHalf);
    return s;
}

/// Window depth of eye distance w for glFrustum's z row (written out, not through the library).
float depthOf(const Camera& c, float w) {
    const float n = c.near, f = c.far;
    const float ndc = (f + n) / (f - n) - 2.0f * f * n / ((f - n) * w);
    return ndc * 0.5f + 0.5f;
}

/// Centroid x of the red channel above the background's 10.
double brightCentroidX(const Image& im) {
    double sum = 0, wsum = 0;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const int r = im.at(x, y).r - 10;
            if (r > 0) sum += (x + 0.5) * r, wsum += r;
        }
    return wsum > 0 ? sum / wsum : -1.0;
}

int leftmostLit(const Image& im) {
    for (int x = 0; x < im.width; ++x)
        for (int y = 0; y < im.height; ++y)
            if (im.at(x, y).r > 128) return x;
    return -1;
}

TEST(Sky, EquirectDotHasTheSeparationAsParallax) {
    for (float interaxial : {0.2f, 0.5f}) {
        StereoPair s = pair(interaxial);
        Sky sky;
        sky.kind = Sky::Kind::Equirect;
        sky.image = Image(512, 256, {10, 20, 40, 255});
        // A bright dot straight ahead (−Z): column 256, row 128 (texel centres ±1).
        for (int y = 126; y < 130; ++y)
            for (int x = 254; x < 258; ++x) sky.image.set(x, y, {255, 255, 255, 255});
        std::vector<Image> color(2, Image(kW, kH));
        std::vector<DepthImage> depth(2, DepthImage(kW, kH, 1.0f));
        ASSERT_TRUE(drawSky(sky, s.rig, color, depth));
        const double x0 = brightCentroidX(color[0]), x1 = brightCentroidX(color[1]);
        ASSERT_GT(x0, 0);
        ASSERT_GT(x1, 0);
        EXPECT_NEAR(x1 - x0, s.separation * kW, 0.05) << "interaxial " << interaxial;
        EXPECT_NEAR(float(x1 - x0) / kW, s.rig.separation(), 1e-3);
        // The dot straddles the centre of the mono view: the two views are symmetric about it.
        EXPECT_NEAR((x0 + x1) * 0.5, kW * 0.5, 0.05);
    }
}

TEST(Sky, OnlyBackgroundPixelsAndDepthStaysFar) {
    StereoPair s = pair();
    Sky sky;  // gradient
    std::vector<Image> color(2, Image(kW, kH, {1, 2, 3, 255}));
    std::vector<DepthImage> depth(2, DepthImage(kW, kH, 1.0f));
    depth[0].depth[0] = 0.5f;  // (0, 0) covered by the scene
    ASSERT_TRUE(drawSky(sky, s.rig, color, depth));
    EXPECT_EQ(color[0].at(0, 0), (Rgba8{1, 2, 3, 255}));
    EXPECT_NE(color[0].at(1, 0), (Rgba8{1, 2, 3, 255}));
    EXPECT_EQ(depth[1].depth[5], 1.0f);
    // Up is bluer than the horizon: the top row is darker in red than the middle row.
    EXPECT_LT(color[1].at(kW / 2, 0).r, color[1].at(kW / 2, kH / 2).r);
}

TEST(Sky, CubeCrossFacesAndFiles) {
    test::TempDir dir("mvr-sky-test");
    const int f = 8;
    Image cross(4 * f, 3 * f, {0, 0, 0, 255});
    // Each face a distinct red value: (col, row) → 40·col + 100·row + 10.
    for (auto [c, r] : {std::pair{1, 0}, {0, 1}, {1, 1}, {2, 1}, {3, 1}, {1, 2}})
        for (int y = 0; y < f; ++y)
            for (int x = 0; x < f; ++x)
                cross.set(c * f + x, r * f + y, {std::uint8_t(40 * c + 100 * r + 10), 0, 0, 255});
    const auto path = dir.path() / "cross.png";
    ASSERT_TRUE(writePng(path, cross));
    auto sky = loadSky(path.string());
    ASSERT_TRUE(sky) << sky.status().message();
    EXPECT_EQ(sky->kind, Sky::Kind::CubeCross);
    auto red = [&](glm::vec3 d) { return int(std::lround(skyColor(*sky, d).x * 255)); };
    EXPECT_EQ(red({0, 0, -1}), 40 + 100 + 10);  // −Z: centre
    EXPECT_EQ(red({1, 0, 0}), 80 + 100 + 10);   // +X: right of it
    EXPECT_EQ(red({-1, 0, 0}), 0 + 100 + 10);   // −X: left
    EXPECT_EQ(red({0, 0, 1}), 120 + 100 + 10);  // +Z: far right
    EXPECT_EQ(red({0, 1, 0}), 40 + 0 + 10);     // +Y: above
    EXPECT_EQ(red({0, -1, 0}), 40 + 200 + 10);  // −Y: below

    ASSERT_TRUE(writePng(dir.path() / "eq.png", Image(64, 32)));
    auto eq = loadSky((dir.path() / "eq.png").string());
    ASSERT_TRUE(eq);
    EXPECT_EQ(eq->kind, Sky::Kind::Equirect);
    ASSERT_TRUE(writePng(dir.path() / "odd.png", Image(50, 32)));
    auto odd = loadSky((dir.path() / "odd.png").string());
    ASSERT_FALSE(odd);
    EXPECT_EQ(odd.status().code(), ErrorCode::Usage);
    auto missing = loadSky((dir.path() / "none.png").string());
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.status().code(), ErrorCode::Input);
    EXPECT_NE(missing.status().message().find("none.png"), std::string::npos);
}

std::uint32_t crc32(const std::string& bytes) {  // PNG's CRC (ISO 3309), bit by bit
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
}

std::string pngChunk(const std::string& type, const std::string& data) {
    auto be32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

// A sky file whose header claims more pixels than its bytes can hold is refused before
// decoding (a 57-byte PNG claiming 16000x8000 RGBA), naming the file; a folder is not "not
// found"; a text file is not an image. And the JPEG that made stb_image 2.27 write past its
// Huffman table (tests/fuzz/regressions/sky/) is refused with the decoder's reason.
TEST(Sky, BadFilesAreRefusedNamingTheFile) {
    test::TempDir dir;
    const std::string png = "\x89PNG\r\n\x1a\n" +
                            pngChunk("IHDR", std::string("\0\0\x3e\x80\0\0\x1f\x40\x08\x06\0\0\0", 13)) +
                            pngChunk("IDAT", "") + pngChunk("IEND", "");
    const auto path = dir.write("huge.png", png);
    auto sky = loadSky(path.string());
    ASSERT_FALSE(sky);
    EXPECT_EQ(sky.status().code(), ErrorCode::Input);
    EXPECT_NE(sky.status().message().find("--sky '" + path.string() +
                                          "': PNG header claims 16000x8000 pixels but its " +
                                          std::to_string(png.size()) + " bytes cannot hold them"),
              std::string::npos)
        << sky.status().message();
    auto folder = loadSky(dir.path().string());
    ASSERT_FALSE(folder);
    EXPECT_NE(folder.status().message().find("not a regular file"), std::string::npos)
        << folder.status().message();
    const auto text = dir.write("sky.png", "not an image");
    auto notImage = loadSky(text.string());
    ASSERT_FALSE(notImage);
    EXPECT_EQ(notImage.status().message(),
              "--sky '" + text.string() + "': not a PNG, JPEG, Radiance or OpenEXR image");
    const std::filesystem::path stbCrash = std::filesystem::path(MVR_TEST_SOURCE_ROOT) /
                                           "tests/fuzz/regressions/sky/stb-dht-counts-over-256.jpg";
    ASSERT_TRUE(std::filesystem::exists(stbCrash)) << stbCrash;
    auto bad = loadSky(stbCrash.string());
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().code(), ErrorCode::Input);
    EXPECT_EQ(bad.status().message().rfind("--sky '" + stbCrash.string() + "': ", 0), 0u)
        << bad.status().message();
}

TEST(StereoSurfaces, DepthlessOutputIsRefusedNamingTheMethod) {
    StereoPair s = pair();
    RenderOutput out;
    out.method = "gs-mrt";
    out.color.assign(2, Image(kW, kH));
    StereoSurfaces surfaces;
    surfaces.sky = Sky{};
    auto r = applyStereoSurfaces(surfaces, s.rig, out);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Unsupported);
    EXPECT_NE(r.status().message().find("--sky"), std::string::npos);
    EXPECT_NE(r.status().message().find("gs-mrt"), std::string::npos);
    // Labels alone are fine without depth (drawn without a depth test).
    StereoSurfaces labels;
    labels.labels.push_back(*parseLabel("X@0.5,0.5", false));
    EXPECT_TRUE(applyStereoSurfaces(labels, s.rig, out));
}

TEST(FloatingWindow, MasksExactlyTheStripsComputedFromTheRig) {
    for (float w : {2.0f, 3.0f, 4.5f}) {
        StereoPair s = pair(0.5f, 5.0f);
        const float c = s.params.convergence;
        const int expected = int(std::ceil(kW * s.separation * (c / w - 1.0f) - 0.5f));
        ASSERT_GT(expected, 0);
        std::vector<DepthImage> depth(2, DepthImage(kW, kH, 1.0f));
        // A near object at distance w touching the left edge in view 0 and the right edge in
        // view 1, 30 columns wide; a far object (behind the screen) at the other edges.
        for (int y = 60; y < 100; ++y)
            for (int x = 0; x < 30; ++x) {
                depth[0].depth[y * kW + x] = depthOf(s.camera, w);
                depth[1].depth[y * kW + (kW - 1 - x)] = depthOf(s.camera, w);
                depth[0].depth[y * kW + (kW - 1 - x)] = depthOf(s.camera, 2 * c);
                depth[1].depth[y * kW + x] = depthOf(s.camera, 2 * c);
            }
        std::vector<Image> color(2, Image(kW, kH, {200, 200, 200, 255}));
        auto strips = applyFloatingWindow(s.rig, color, depth);
        ASSERT_TRUE(strips) << strips.status().message();
        EXPECT_EQ((*strips)[0].left, expected) << "w " << w;
        EXPECT_EQ((*strips)[0].right, 0);
        EXPECT_EQ((*strips)[1].right, expected);
        EXPECT_EQ((*strips)[1].left, 0);
        EXPECT_NEAR((*strips)[0].nearestLeft, w, 1e-3f * w);
        for (int y : {0, 80, kH - 1}) {
            EXPECT_EQ(color[0].at(expected - 1, y), (Rgba8{0, 0, 0, 255}));
            EXPECT_EQ(color[0].at(expected, y), (Rgba8{200, 200, 200, 255}));
            EXPECT_EQ(color[1].at(kW - expected, y), (Rgba8{0, 0, 0, 255}));
            EXPECT_EQ(color[1].at(kW - expected - 1, y), (Rgba8{200, 200, 200, 255}));
            EXPECT_EQ(color[0].at(kW - 1, y), (Rgba8{200, 200, 200, 255}));
        }
    }
}

TEST(FloatingWindow, NearObjectAwayFromTheEdgesMasksNothing) {
    StereoPair s = pair(0.5f, 5.0f);
    std::vector<DepthImage> depth(2, DepthImage(kW, kH, 1.0f));
    for (int x = 100; x < 140; ++x) depth[0].depth[80 * kW + x] = depthOf(s.camera, 2.0f);
    auto strips = floatingWindowStrips(s.rig, depth);
    ASSERT_TRUE(strips);
    EXPECT_EQ((*strips)[0].left, 0);
    EXPECT_EQ((*strips)[1].right, 0);
    RigParams toeIn = s.params;
    toeIn.kind = RigKind::ToeIn;
    auto refused = floatingWindowStrips(*makeRig(s.camera, toeIn), depth);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.status().code(), ErrorCode::Unsupported);
}

TEST(Letterbox, BandsAtConvergenceDepthOverdrawnByOutOfScreenObjects) {
    StereoPair s = pair(0.5f, 5.0f);
    const float pct = 10.0f;
    const int rows = int(std::lround(pct / 100.0f * kH));  // 16
    std::vector<DepthImage> depth(2, DepthImage(kW, kH, 1.0f));
    depth[0].depth[2 * kW + 50] = depthOf(s.camera, 3.0f);  // in front of the screen
    depth[0].depth[3 * kW + 50] = depthOf(s.camera, 8.0f);  // behind it
    std::vector<Image> color(2, Image(kW, kH, {200, 200, 200, 255}));
    ASSERT_TRUE(drawLetterbox(s.rig, color, depth, pct));
    const float band = depthOf(s.camera, 5.0f);
    for (int v = 0; v < 2; ++v) {
        EXPECT_EQ(color[v].at(10, 0), (Rgba8{0, 0, 0, 255}));
        EXPECT_EQ(color[v].at(10, rows - 1), (Rgba8{0, 0, 0, 255}));
        EXPECT_EQ(color[v].at(10, rows), (Rgba8{200, 200, 200, 255}));
        EXPECT_EQ(color[v].at(10, kH - rows), (Rgba8{0, 0, 0, 255}));
        EXPECT_EQ(color[v].at(10, kH - rows - 1), (Rgba8{200, 200, 200, 255}));
        EXPECT_NEAR(depth[v].at(10, 0), band, 1e-6f);
    }
    EXPECT_EQ(color[0].at(50, 2), (Rgba8{200, 200, 200, 255}));  // overdraws the band
    EXPECT_EQ(color[0].at(50, 3), (Rgba8{0, 0, 0, 255}));
    EXPECT_FALSE(drawLetterbox(s.rig, color, depth, 50.0f));
    EXPECT_FALSE(drawLetterbox(s.rig, color, depth, 0.0f));
}

TEST(Labels, ParallaxIsSeparationTimesOneMinusConvergenceOverDepth) {
    StereoPair s = pair(0.5f, 5.0f);
    const float c = s.params.convergence;
    for (float d : {2.5f, 4.0f, 5.0f, 10.0f, 40.0f}) {
        std::vector<Image> color(2, Image(kW, kH));
        Label label = *parseLabel(fmt::format("I@0.5,0.5,{}", d), false);
        ASSERT_TRUE(drawLabels(s.rig, {label}, color, {}));
        const int x0 = leftmostLit(color[0]), x1 = leftmostLit(color[1]);
        ASSERT_GE(x0, 0);
        ASSERT_GE(x1, 0);
        // Each view's position is rounded to whole pixels: within one pixel of the exact value.
        EXPECT_NEAR(x1 - x0, s.separation * (1.0f - c / d) * kW, 1.0) << "d " << d;
        // The library's continuous positions are exact.
        const glm::vec3 p = labelPoint(s.rig, label);
        const float exact = projectToPixel(s.rig.views[1], p, kW, kH)->x -
                            projectToPixel(s.rig.views[0], p, kW, kH)->x;
        EXPECT_NEAR(exact, s.separation * (1.0f - c / d) * kW, 1e-3f * kW);
        // Its eye-space distance from the mono camera is d.
        EXPECT_NEAR(
            glm::dot(p - s.camera.position, glm::normalize(s.camera.target - s.camera.position)), d,
            1e-4f * d);
    }
}

TEST(Labels, AnchorAndDepthTest) {
    StereoPair s = pair(0.5f, 5.0f);
    // An anchor 2.5 in front of the mono camera on its axis: parallax of distance 2.5.
    const glm::vec3 anchor =
        s.camera.position + 2.5f * glm::normalize(s.camera.target - s.camera.position);
    Label label = *parseLabel(fmt::format("I@{},{},{}", anchor.x, anchor.y, anchor.z), true);
    std::vector<Image> color(2, Image(kW, kH));
    ASSERT_TRUE(drawLabels(s.rig, {label}, color, {}));
    EXPECT_NEAR(leftmostLit(color[1]) - leftmostLit(color[0]),
                s.separation * (1 - 5.0f / 2.5f) * kW, 1.0);
    // A scene point nearer than the label hides it; a farther one does not.
    std::vector<Image> hidden(2, Image(kW, kH));
    std::vector<DepthImage> nearer(2, DepthImage(kW, kH, depthOf(s.camera, 2.0f)));
    ASSERT_TRUE(drawLabels(s.rig, {label}, hidden, nearer));
    EXPECT_EQ(leftmostLit(hidden[0]), -1);
    std::vector<DepthImage> farther(2, DepthImage(kW, kH, depthOf(s.camera, 3.0f)));
    ASSERT_TRUE(drawLabels(s.rig, {label}, hidden, farther));
    EXPECT_EQ(leftmostLit(hidden[0]), leftmostLit(color[0]));
}

TEST(Labels, ParseErrorsQuoteTheText) {
    for (const char* bad : {"noat", "@0.5,0.5", "T@x,y", "T@0.5", "T@0.5,0.5,-1", "T@1,2,3,4"}) {
        auto l = parseLabel(bad, false);
        ASSERT_FALSE(l) << bad;
        EXPECT_EQ(l.status().code(), ErrorCode::Usage);
        EXPECT_NE(l.status().message().find(bad), std::string::npos);
    }
    EXPECT_FALSE(parseLabel("T@1,2", true));
    auto ok = parseLabel("a@b@0.25,0.75", false);
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->text, "a@b");
    EXPECT_FLOAT_EQ(ok->screen.y, 0.75f);
    EXPECT_EQ(ok->distance, 0.0f);
}

}  // namespace
}  // namespace mvr
