// The screen rig (mvr/core/screen_rig.h): every number below is computed here from the framing
// camera, the screen's size and the eyes, not read from the code under test.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "mvr/core/animation.h"
#include "mvr/core/screen_rig.h"

namespace mvr {
namespace {

constexpr float kW = 600.0f, kH = 340.0f;  // mm
constexpr float kConv = 10.0f;             // world units from the camera to its window

/// A camera at (0, 0, 10) looking at the origin, 45 degrees high, the screen's aspect.
Camera framing() {
    Camera c;
    c.position = {0.0f, 0.0f, kConv};
    c.target = {0.0f, 0.0f, 0.0f};
    c.fovYDegrees = 45.0f;
    c.aspect = kW / kH;
    c.near = 1.0f;
    c.far = 30.0f;
    return c;
}
/// The window at the convergence plane: half extents in world units, and world units per mm.
float halfHeight() { return kConv * std::tan(glm::radians(22.5f)); }
float halfWidth() { return halfHeight() * kW / kH; }
float scale() { return 2.0f * halfWidth() / kW; }

glm::vec3 ndc(const View& v, const glm::vec3& p) {
    const glm::vec4 c = v.clipFromWorld() * glm::vec4(p, 1.0f);
    return glm::vec3(c) / c.w;
}

Rig rigOf(const ScreenEyes& eyes) {
    auto rig = makeScreenRig(framing(), kConv, eyes);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

TEST(ScreenRig, TheScreensCornersAreTheImageCornersInEachEye) {
    // Eyes off centre and at different distances (a head turned and leaning): still exact.
    ScreenEyes eyes;
    eyes.screen = screenOfSize(kW, kH);
    eyes.leftEye = {-60.0f, 80.0f, 550.0f};
    eyes.rightEye = {5.0f, 90.0f, 600.0f};
    const Rig rig = rigOf(eyes);
    ASSERT_EQ(rig.viewCount(), 2);
    const float hx = halfWidth(), hy = halfHeight();
    const glm::vec3 corners[4] = {{-hx, -hy, 0}, {hx, -hy, 0}, {hx, hy, 0}, {-hx, hy, 0}};
    const glm::vec2 expected[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const View& v : rig.views) {
        for (int i = 0; i < 4; ++i) {
            const glm::vec3 p = ndc(v, corners[i]);
            EXPECT_NEAR(p.x, expected[i].x, 1e-4f) << i;
            EXPECT_NEAR(p.y, expected[i].y, 1e-4f) << i;
        }
    }
    // The eyes sit where the screen-space positions put them: (x, y, z) mm · scale from the
    // window's centre (the origin), z toward the camera.
    EXPECT_NEAR(glm::length(rig.views[0].eyeWorld - glm::vec3(-60, 80, 550) * scale()), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(rig.views[1].eyeWorld - glm::vec3(5, 90, 600) * scale()), 0.0f, 1e-4f);
}

TEST(ScreenRig, ParallaxIsZeroOnTheScreenAndSimilarTrianglesBehindIt) {
    const float ipd = 64.0f, distance = 650.0f;  // mm
    const ScreenEyes eyes = eyesAtHead(screenOfSize(kW, kH), {0.0f, 0.0f, distance}, ipd);
    const Rig rig = rigOf(eyes);
    // On the screen: the same image position in both eyes.
    for (const glm::vec3 p : {glm::vec3(0.3f, 0.2f, 0.0f), glm::vec3(-2.0f, 1.0f, 0.0f)}) {
        EXPECT_NEAR(ndc(rig.views[0], p).x, ndc(rig.views[1], p).x, 1e-5f);
        EXPECT_NEAR(ndc(rig.views[0], p).y, ndc(rig.views[1], p).y, 1e-5f);
    }
    // d mm behind the screen: parallax e·d / (D + d) mm, right eye's image to the right.
    for (const float d : {100.0f, 650.0f, 3000.0f}) {
        const glm::vec3 p(0.5f, -0.3f, -d * scale());
        const float dxNdc = ndc(rig.views[1], p).x - ndc(rig.views[0], p).x;
        const float parallaxMm = dxNdc * 0.5f * kW;
        EXPECT_NEAR(parallaxMm, ipd * d / (distance + d), 0.01f) << d;
    }
    // In front of it (d < 0): crossed, negative.
    const glm::vec3 front(0.0f, 0.0f, 200.0f * scale());
    const float crossed = (ndc(rig.views[1], front).x - ndc(rig.views[0], front).x) * 0.5f * kW;
    EXPECT_NEAR(crossed, ipd * -200.0f / (distance - 200.0f), 0.01f);
    // The rig's figures: the eyes' distance to the screen and to each other, in world units.
    EXPECT_NEAR(rig.convergence, distance * scale(), 1e-4f);
    EXPECT_NEAR(rig.interaxial, ipd * scale(), 1e-5f);
}

TEST(ScreenRig, ATiltedScreenKeepsTheSceneUprightInTheRoom) {
    // A 300 x 200 mm panel leaning back 45 degrees (as Sony's Spatial Reality Display), its
    // lower edge on the desk; eyes above and in front of it.
    const float c = std::cos(glm::radians(45.0f)), s = std::sin(glm::radians(45.0f));
    const ScreenCorners tilted{{-150, 0, 0}, {150, 0, 0}, {-150, 200 * c, -200 * s}};
    ScreenEyes eyes;
    eyes.screen = tilted;
    eyes.leftEye = {-32.0f, 350.0f, 350.0f};
    eyes.rightEye = {32.0f, 350.0f, 350.0f};
    Camera f = framing();
    f.aspect = 1.5f;
    auto made = makeScreenRig(f, kConv, eyes);
    ASSERT_TRUE(made) << made.status().message();
    // The room's axes are the camera's (x right, y up, z toward it), the panel's centre
    // (0, 100c, −100s) mm on the convergence point (the origin), 300 mm the window's width.
    const float hx = halfHeight() * 1.5f, sc = 2.0f * hx / 300.0f;
    const glm::vec3 centreMm(0.0f, 100.0f * c, -100.0f * s);
    auto world = [&](glm::vec3 mm) { return sc * (mm - centreMm); };
    const glm::vec3 upperRight = tilted.lowerRight + (tilted.upperLeft - tilted.lowerLeft);
    const glm::vec3 corners[4] = {tilted.lowerLeft, tilted.lowerRight, upperRight, tilted.upperLeft};
    const glm::vec2 expected[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const View& v : made->views) {
        for (int i = 0; i < 4; ++i) {
            EXPECT_NEAR(ndc(v, world(corners[i])).x, expected[i].x, 1e-4f) << i;
            EXPECT_NEAR(ndc(v, world(corners[i])).y, expected[i].y, 1e-4f) << i;
        }
    }
    // The eyes where the room puts them: above the scene, looking down at it.
    EXPECT_NEAR(glm::length(made->views[0].eyeWorld - world(eyes.leftEye)), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(made->views[1].eyeWorld - world(eyes.rightEye)), 0.0f, 1e-4f);
    EXPECT_GT(made->views[0].eyeWorld.y, 0.0f);
    // A point on the panel has zero parallax; one 100 mm behind it along its normal (0, s, c)
    // has e·d / (D + d), D the eyes' distance to the panel's plane.
    const glm::vec3 onPanel = world({40.0f, 60.0f * c, -60.0f * s});
    EXPECT_NEAR(ndc(made->views[0], onPanel).x, ndc(made->views[1], onPanel).x, 1e-5f);
    const float dMm = 350.0f * s + 350.0f * c;
    const glm::vec3 behind = world(glm::vec3(40.0f, 60.0f * c, -60.0f * s) - 100.0f * glm::vec3(0, s, c));
    const float parallaxMm =
        (ndc(made->views[1], behind).x - ndc(made->views[0], behind).x) * 0.5f * 300.0f;
    EXPECT_NEAR(parallaxMm, 64.0f * 100.0f / (dMm + 100.0f), 0.01f);
    // screenOfSize's tilt gives the same panel about its centre.
    const ScreenCorners bySize = screenOfSize(300.0f, 200.0f, 45.0f);
    EXPECT_NEAR(glm::length(bySize.lowerLeft - (tilted.lowerLeft - centreMm)), 0.0f, 1e-3f);
    EXPECT_NEAR(glm::length(bySize.upperLeft - (tilted.upperLeft - centreMm)), 0.0f, 1e-3f);
}

TEST(ScreenRig, RigAtMovesTheScreenWithTheCamera) {
    const ScreenEyes eyes = eyesAtHead(screenOfSize(kW, kH), {0.0f, 0.0f, 600.0f}, 63.0f);
    const Rig rig = rigOf(eyes);
    // A quarter orbit of the centre eye about the origin: the screen turns with it.
    Camera moved = rig.camera;
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 1, 0));
    moved.position = glm::vec3(turn * glm::vec4(moved.position, 1.0f));
    moved.target = glm::vec3(turn * glm::vec4(moved.target, 1.0f));
    auto again = rigAt(rig, moved);
    ASSERT_TRUE(again) << again.status().message();
    ASSERT_EQ(again->viewCount(), 2);
    // The window now lies in the plane x = 0, seen from +X: its right is −Z, so the
    // upper-right corner is (0, hy, −hx) and the lower-left (0, −hy, hx).
    const float hx = halfWidth(), hy = halfHeight();
    for (const View& v : again->views) {
        EXPECT_NEAR(ndc(v, {0.0f, hy, -hx}).x, 1.0f, 1e-4f);
        EXPECT_NEAR(ndc(v, {0.0f, hy, -hx}).y, 1.0f, 1e-4f);
        EXPECT_NEAR(ndc(v, {0.0f, -hy, hx}).x, -1.0f, 1e-4f);
        EXPECT_NEAR(ndc(v, {0.0f, -hy, hx}).y, -1.0f, 1e-4f);
    }
}

TEST(ScreenRig, BadScreensAndEyesAreRefusedByName) {
    ScreenEyes behind = eyesAtHead(screenOfSize(kW, kH), {0.0f, 0.0f, -100.0f}, 63.0f);
    Status s = validateScreenEyes(behind, "--head 0,0,-100");
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("--head 0,0,-100: the left eye at (-31.5, 0, -100) mm is -100 mm "
                               "from the screen's plane"),
              std::string::npos)
        << s.message();
    ScreenCorners skew{{0, 0, 0}, {100, 0, 0}, {50, 100, 0}};
    s = validateScreen(skew, "--screen-corners X");
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("angle of 63.43 degrees"), std::string::npos) << s.message();
    s = validateScreen(screenOfSize(0.5f, 100.0f), "--screen-mm 0.5x100");
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("a screen of 0.5 x 100 mm"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace mvr
