// Unit tests of the viewer's window-free parts: the stereo camera state, the 3D cursor, the HUD
// overlay, the --script parser and the choice of backend and method from the registry.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "input.h"
#include "mvr/backends.h"
#include "overlay.h"
#include "view_state.h"
#include "viewer.h"
#include "viewer_backends.h"
#include "mvr_test_support.h"

namespace mvr::viewer {
namespace {

Rig testRig(float aspect = 4.0f / 3.0f) {
    Camera camera;
    camera.position = {0.3f, 0.2f, 4.0f};
    camera.target = {0.0f, 0.1f, 0.0f};
    camera.aspect = aspect;
    camera.near = 0.5f;
    camera.far = 20.0f;
    RigParams params;
    params.interaxial = 0.12f;
    params.convergence = 4.0f;
    Result<Rig> rig = makeRig(camera, params);
    EXPECT_TRUE(rig) << rig.status().message();
    return *rig;
}

/// Window depth of eye distance w for a perspective near/far (inverse of
/// distanceFromWindowDepth()).
float windowDepth(float w, float near, float far) {
    const float ndcZ = (far + near) / (far - near) - 2.0f * far * near / ((far - near) * w);
    return ndcZ * 0.5f + 0.5f;
}

TEST(StereoCamera, UnmovedCameraGivesTheRigItCameFrom) {
    // Frame 0 of `mvr view` must be `mvr render`'s image: the same rig, bit for bit.
    const Rig rig = testRig();
    Result<Rig> again = StereoCamera::fromRig(rig, 1.0f).rig();
    ASSERT_TRUE(again);
    ASSERT_EQ(again->viewCount(), 2);
    for (int v = 0; v < 2; ++v) {
        EXPECT_EQ(again->views[v].viewFromWorld, rig.views[v].viewFromWorld) << v;
        EXPECT_EQ(again->views[v].clipFromView, rig.views[v].clipFromView) << v;
    }
}

// --rig screen: keys 4 6 8 2 9 3 move the head 20 mm; the rig is then the screen rig of eyes
// at the moved head (makeScreenRig(), whose geometry tests/core/screen_rig_test.cpp checks),
// and an eye cannot go behind the screen.
TEST(StereoCamera, TheHeadKeysMoveTheEyesOfAScreenRig) {
    const Camera framing = testRig(597.9f / 336.3f).camera;
    const ScreenCorners screen = screenOfSize(597.9f, 336.3f);
    auto eyesAt = [&](glm::vec3 head) { return eyesAtHead(screen, head, 63.0f); };
    Result<Rig> start = makeScreenRig(framing, 4.0f, eyesAt({0.0f, 0.0f, 600.0f}));
    ASSERT_TRUE(start) << start.status().message();
    StereoCamera s = StereoCamera::fromRig(*start, 1.0f);
    ASSERT_TRUE(s.screenRig);
    EXPECT_EQ(headStepMm(actionForChar('4')), glm::vec3(-20.0f, 0.0f, 0.0f));
    EXPECT_EQ(headStepMm(actionForChar('9')), glm::vec3(0.0f, 0.0f, -20.0f));
    EXPECT_EQ(headStepMm(Action::Wireframe), glm::vec3(0.0f));
    // A ctrl+left drag: the window's width stands for the screen's (597.9 mm over 300 px), y up.
    const glm::vec3 dragged = headDragMm({30.0f, -60.0f}, 597.9f, 300);
    EXPECT_NEAR(dragged.x, 59.79f, 1e-3f);
    EXPECT_NEAR(dragged.y, 119.58f, 1e-3f);
    EXPECT_EQ(dragged.z, 0.0f);
    EXPECT_NEAR(s.screenWidthMm(), 597.9f, 1e-3f);
    EXPECT_EQ(StereoCamera::fromRig(testRig(1.5f), 1.0f).screenWidthMm(), 0.0f);
    for (char key : {'4', '4', '8', '3'}) EXPECT_TRUE(s.moveHead(headStepMm(actionForChar(key))));
    Result<Rig> moved = s.rig();
    Result<Rig> expected = makeScreenRig(framing, 4.0f, eyesAt({-40.0f, 20.0f, 620.0f}));
    ASSERT_TRUE(moved && expected);
    for (int v = 0; v < 2; ++v) {
        const glm::mat4 a = moved->views[v].clipFromView * moved->views[v].viewFromWorld;
        const glm::mat4 b = expected->views[v].clipFromView * expected->views[v].viewFromWorld;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) EXPECT_NEAR(a[i][j], b[i][j], 1e-4f) << v << i << j;
    }
    // 31 steps nearer put the eyes 0 mm ... behind the screen: the step is refused, unmoved.
    StereoCamera near = StereoCamera::fromRig(*start, 1.0f);
    int steps = 0;
    while (near.moveHead({0.0f, 0.0f, -20.0f})) ++steps;
    EXPECT_EQ(steps, 29);  // 600 - 29·20 = 20 mm in front; 0 mm is refused
    EXPECT_EQ(near.headOffsetMm, glm::vec3(0.0f, 0.0f, -580.0f));
    // Other rigs have no head.
    StereoCamera plain = StereoCamera::fromRig(testRig(), 1.0f);
    EXPECT_FALSE(plain.moveHead({20.0f, 0.0f, 0.0f}));
}

TEST(StereoCamera, ARowOfViewsKeepsItsViewConeAndTheConeKeysChangeIt) {
    // A view-cone row of 9 views: unmoved, the rig is makeRig()'s; each view's eye sits at
    // D·tan(θ_i) along the camera's x axis, θ_i = −cone/2 + cone·i/(N−1), computed here.
    const Camera camera = testRig().camera;
    RigParams params;
    params.columns = 9;
    params.convergence = 4.0f;
    params.viewConeDegrees = 40.0f;
    Result<Rig> rig = makeRig(camera, params);
    ASSERT_TRUE(rig) << rig.status().message();
    StereoCamera s = StereoCamera::fromRig(*rig, 1.0f, 40.0f);
    EXPECT_EQ(s.columns, 9);
    auto eyeOffsets = [&](const Rig& r) {
        const glm::vec3 right = glm::normalize(
            glm::cross(camera.target - camera.position, glm::vec3(0.0f, 1.0f, 0.0f)));
        std::vector<float> out;
        for (const View& v : r.views) {
            const glm::vec3 eye = glm::vec3(glm::inverse(v.viewFromWorld) * glm::vec4(0, 0, 0, 1));
            out.push_back(glm::dot(eye - camera.position, right));
        }
        return out;
    };
    Result<Rig> again = s.rig();
    ASSERT_TRUE(again);
    ASSERT_EQ(again->viewCount(), 9);
    for (int v = 0; v < 9; ++v) {
        EXPECT_EQ(again->views[v].viewFromWorld, rig->views[v].viewFromWorld) << v;
        EXPECT_EQ(again->views[v].clipFromView, rig->views[v].clipFromView) << v;
    }
    for (float cone : {40.0f, 50.0f}) {
        s.setViewCone(cone);
        const std::vector<float> x = eyeOffsets(*s.rig());
        for (int i = 0; i < 9; ++i) {
            const double theta = glm::radians(-cone / 2.0 + cone * i / 8.0);
            EXPECT_NEAR(x[std::size_t(i)], 4.0 * std::tan(theta), 1e-4) << cone << " view " << i;
        }
    }
    s.setViewCone(500.0f);
    EXPECT_EQ(s.viewConeDegrees, StereoCamera::kMaxViewCone);
    s.setViewCone(-5.0f);
    EXPECT_EQ(s.viewConeDegrees, StereoCamera::kMinViewCone);
}

TEST(StereoCamera, SeparationIsKeptWhenConvergenceAspectOrZoomChange) {
    StereoCamera s = StereoCamera::fromRig(testRig(), 1.0f);
    s.setSeparation(0.03f);
    EXPECT_NEAR(s.separation(), 0.03f, 1e-6f);
    s.setConvergence(6.0f);
    EXPECT_FLOAT_EQ(s.convergence, 6.0f);
    EXPECT_NEAR(s.separation(), 0.03f, 1e-6f);
    s.setAspect(2.0f);
    EXPECT_NEAR(s.separation(), 0.03f, 1e-6f);
    const float ratio = s.convergence / s.distance();
    s.zoom(0.5f);
    EXPECT_NEAR(s.separation(), 0.03f, 1e-6f);
    EXPECT_NEAR(s.convergence / s.distance(), ratio, 1e-5f);  // the screen stays in the scene
    EXPECT_GT(s.convergence, s.camera.near);
    s.setSeparation(1.0f);
    EXPECT_NEAR(s.separation(), 0.25f, 1e-6f);  // clamped
}

TEST(StereoCamera, OrbitKeepsDistanceAndClampsPitch) {
    StereoCamera s = StereoCamera::fromRig(testRig(), 1.0f);
    const float d = s.distance();
    s.orbit(0.7f, 0.3f);
    EXPECT_NEAR(s.distance(), d, 1e-4f * d);
    s.orbit(0.0f, 10.0f);  // far past the pole
    const glm::vec3 dir = glm::normalize(s.camera.position - s.camera.target);
    EXPECT_NEAR(std::asin(dir.y), glm::radians(89.0f), 1e-3f);
    EXPECT_TRUE(s.rig());
}

TEST(Cursor, SitsOnAPlaneWithThatPlanesParallax) {
    const Rig rig = testRig();
    const int width = 160, height = 120;
    for (float w : {2.0f, 4.0f, 9.0f}) {
        DepthImage depth(width, height, windowDepth(w, rig.camera.near, rig.camera.far));
        const CursorPlacement c = placeCursor(rig, depth, {70.5f, 40.5f}, width, height);
        ASSERT_TRUE(c.onSurface) << w;
        EXPECT_NEAR(c.distance, w, 1e-3f * w);
        // nvidia-gtc2010: parallax = separation · (1 − convergence / w); zero at convergence.
        EXPECT_NEAR(c.parallax, rig.separation() * (1.0f - rig.convergence / w), 1e-5f) << w;
        EXPECT_NEAR((c.viewPx[1].x - c.viewPx[0].x) / width, c.parallax, 1e-5f);
        EXPECT_NEAR(c.viewPx[0].y, 40.5f, 1e-3f);  // off-axis: no vertical parallax
        EXPECT_NEAR(c.viewPx[1].y, 40.5f, 1e-3f);
        EXPECT_NEAR((c.viewPx[0].x + c.viewPx[1].x) * 0.5f, 70.5f, 1e-3f);  // centred on the mouse
    }
}

TEST(Cursor, FollowsATiltedSurfaceFromTheLeftEye) {
    // Depth that varies across the image: the fixed-point search must land on the distance the
    // left eye sees at the cursor point's own left-eye position.
    const Rig rig = testRig();
    const int width = 200, height = 100;
    DepthImage depth(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float w = 3.0f + 2.0f * float(x) / float(width);
            depth.depth[std::size_t(y) * width + x] =
                windowDepth(w, rig.camera.near, rig.camera.far);
        }
    }
    const CursorPlacement c = placeCursor(rig, depth, {100.5f, 50.5f}, width, height);
    ASSERT_TRUE(c.onSurface);
    const int x0 = int(std::floor(c.viewPx[0].x));
    const float seen = distanceFromWindowDepth(depth.at(x0, 50), rig.camera.near, rig.camera.far);
    EXPECT_NEAR(c.distance, seen, 2.0f / width * 2.0f);  // within a pixel's step of the ramp
}

TEST(Cursor, BackgroundOrNoDepthIsAtScreenDepth) {
    const Rig rig = testRig();
    for (const DepthImage& depth : {DepthImage(), DepthImage(64, 48, 1.0f)}) {
        const CursorPlacement c = placeCursor(rig, depth, {10.0f, 20.0f}, 64, 48);
        EXPECT_FALSE(c.onSurface);
        EXPECT_FLOAT_EQ(c.distance, rig.convergence);
        EXPECT_NEAR(c.parallax, 0.0f, 1e-6f);
        EXPECT_NEAR(c.viewPx[0].x, 10.0f, 1e-3f);
        EXPECT_NEAR(c.viewPx[1].x, 10.0f, 1e-3f);
    }
}

TEST(ParallaxRange, FromDepthImage) {
    const Rig rig = testRig();
    DepthImage depth(4, 1, 1.0f);
    EXPECT_FALSE(frameParallaxRange(rig, depth));
    depth.depth[1] = windowDepth(2.5f, rig.camera.near, rig.camera.far);
    depth.depth[2] = windowDepth(8.0f, rig.camera.near, rig.camera.far);
    const auto r = frameParallaxRange(rig, depth);
    ASSERT_TRUE(r);
    EXPECT_NEAR(r->minParallax, rig.separation() * (1.0f - 4.0f / 2.5f), 1e-5f);
    EXPECT_NEAR(r->maxParallax, rig.separation() * (1.0f - 4.0f / 8.0f), 1e-5f);
    EXPECT_TRUE(r->comfortable);
}

TEST(Overlay, HudTextIsTheSameInBothEyes) {
    // Zero parallax: drawn at the same pixels over two different eyes' images.
    Image left(120, 40, {10, 20, 30, 255}), right(120, 40, {200, 100, 50, 255});
    const Rgba8 ink{240, 240, 240, 255};
    for (Image* eye : {&left, &right}) drawText(*eye, 3, 4, "fps 12.5\nsep 2%", ink, 1);
    int inked = 0;
    for (int y = 0; y < 40; ++y) {
        for (int x = 0; x < 120; ++x) {
            EXPECT_EQ(left.at(x, y) == ink, right.at(x, y) == ink) << x << "," << y;
            inked += left.at(x, y) == ink;
        }
    }
    EXPECT_GT(inked, 40);
    const glm::ivec2 size = textSize("fps 12.5\nsep 2%", 2);
    EXPECT_GT(size.x, 0);
    EXPECT_GT(size.y, 12);
    // Clipped at the borders, never outside the image.
    drawText(left, 115, 35, "clipped", ink, 3);
    drawText(left, -20, -5, "clipped", ink, 3);
}

TEST(Overlay, CrosshairCentredOnItsPixel) {
    Image image(40, 40);
    drawCrosshair(image, {20.5f, 10.5f}, 8, {255, 255, 255, 255});
    EXPECT_EQ(image.at(20, 10), (Rgba8{255, 255, 255, 255}));      // centre dot
    EXPECT_EQ(image.at(20, 10 - 7), (Rgba8{255, 255, 255, 255}));  // upper arm
    EXPECT_EQ(image.at(20 + 7, 10), (Rgba8{255, 255, 255, 255}));  // right arm
    EXPECT_EQ(image.at(30, 30), (Rgba8{0, 0, 0, 255}));
    drawCrosshair(image, {-3.0f, 45.0f}, 8, {255, 255, 255, 255});  // off the image: clipped
}

TEST(Script, ParsesKeysNamesAndMouseSteps) {
    auto steps = parseScript("m,m,+, left ,,at:12:34.5,drag:-5:3,wheel:2,q");
    ASSERT_TRUE(steps) << steps.status().message();
    ASSERT_EQ(steps->size(), 9u);
    EXPECT_EQ((*steps)[0].action, Action::NextMethod);
    EXPECT_EQ((*steps)[2].action, Action::SeparationUp);
    EXPECT_EQ((*steps)[3].action, Action::OrbitLeft);
    EXPECT_EQ((*steps)[4].action, Action::None);
    EXPECT_EQ((*steps)[5].kind, ScriptStep::Kind::MouseAt);
    EXPECT_FLOAT_EQ((*steps)[5].y, 34.5f);
    EXPECT_EQ((*steps)[6].kind, ScriptStep::Kind::Drag);
    EXPECT_FLOAT_EQ((*steps)[6].x, -5.0f);
    EXPECT_EQ((*steps)[7].kind, ScriptStep::Kind::Wheel);
    EXPECT_EQ((*steps)[8].action, Action::Quit);
    EXPECT_TRUE(parseScript("")->empty());
    EXPECT_EQ(parseScript("-,[,]")->at(0).action, Action::SeparationDown);
}

TEST(Script, ViewKeys) {
    // ',' separates steps, so scripts step back with '<'; the window takes ',' and '.' too.
    auto steps = parseScript(">,<,.,v");
    ASSERT_TRUE(steps);
    ASSERT_EQ(steps->size(), 4u);
    EXPECT_EQ(steps->at(0).action, Action::NextView);
    EXPECT_EQ(steps->at(1).action, Action::PrevView);
    EXPECT_EQ(steps->at(2).action, Action::NextView);
    EXPECT_EQ(steps->at(3).action, Action::ToggleView);
    EXPECT_EQ(actionForChar(','), Action::PrevView);
}

TEST(Script, UnknownTokenIsAUsageError) {
    auto steps = parseScript("m,zz,+");
    ASSERT_FALSE(steps);
    EXPECT_EQ(steps.status().code(), ErrorCode::Usage);
    EXPECT_NE(steps.status().message().find("token 2 'zz'"), std::string::npos)
        << steps.status().message();
    EXPECT_FALSE(parseScript("at:1"));
    EXPECT_FALSE(parseScript("wheel:x"));
    EXPECT_FALSE(parseScript("size:0:10"));
    auto resize = parseScript("size:300:100");
    ASSERT_TRUE(resize);
    EXPECT_EQ(resize->at(0).kind, ScriptStep::Kind::Resize);
}

// The registry decides: the default backend is the first GPU row, the fallback the first other
// row, `m` cycles GPU backends' methods first. Making a backend touches no GPU.
TEST(ViewerBackends, ComeFromTheRegistry) {
    std::string firstGpu, firstOther;
    for (const BackendEntry& e : backends()) {
        std::string& first = e.gpu ? firstGpu : firstOther;
        if (first.empty()) first = e.name;
    }
    if (firstGpu.empty()) MVR_SKIP(FeatureNotBuilt) << "no GPU backend in this build";
    EXPECT_EQ(defaultViewerBackend(), firstGpu);
    EXPECT_EQ(fallbackViewerBackend(), firstOther);
    ViewerBackends made;
    ASSERT_TRUE(made.make());
    ASSERT_FALSE(made.methods().empty());
    EXPECT_EQ(made.methods().front().backend, firstGpu);
    bool other = false;
    for (const MethodRef& m : made.methods()) {
        const bool gpu = (*findBackend(m.backend))->gpu;
        EXPECT_FALSE(gpu && other) << m.label() << " after a non-GPU backend's method";
        other = other || !gpu;
    }
}

// The initial method: the backend's start method (interactiveMethod, else defaultMethod()); the
// fallback when the default backend does not run, keeping --method where the fallback has it.
TEST(ViewerBackends, InitialMethodAndFallback) {
    ViewerBackends made;
    ASSERT_TRUE(made.make());
    const std::string gpu = defaultViewerBackend(), cpu = fallbackViewerBackend();
    if (gpu == cpu || cpu.empty()) MVR_SKIP(FeatureNotBuilt) << "no fallback in this build";
    const auto start = [&](const std::string& name) {
        return startMethod(name, made.backend(name).defaultMethod());
    };
    const auto everything = [](const MethodRef&) { return Status::ok(); };
    const auto noGpu = [&](const MethodRef& m) {
        return m.backend == gpu ? unsupportedError("no EGL display: test") : Status::ok();
    };
    ViewerOptions options;
    Result<std::size_t> chosen = chooseInitialMethod(made, options, everything);
    ASSERT_TRUE(chosen) << chosen.status().message();
    EXPECT_EQ(made.methods()[*chosen].label(), gpu + ":" + start(gpu));
    const std::string interactive = (*findBackend(gpu))->interactiveMethod;
    if (!interactive.empty()) {
        EXPECT_EQ(made.methods()[*chosen].method, interactive);
    }

    chosen = chooseInitialMethod(made, options, noGpu);
    ASSERT_TRUE(chosen) << chosen.status().message();
    EXPECT_EQ(made.methods()[*chosen].label(), cpu + ":" + start(cpu));

    options.method = made.backend(cpu).methods().front();  // also a method of gpu?
    if (made.find(gpu, options.method)) {
        chosen = chooseInitialMethod(made, options, noGpu);
        ASSERT_TRUE(chosen) << chosen.status().message();
        EXPECT_EQ(made.methods()[*chosen].label(), cpu + ":" + options.method);
    }

    options.method.clear();
    options.backendGiven = true;
    chosen = chooseInitialMethod(made, options, noGpu);
    ASSERT_FALSE(chosen);
    EXPECT_EQ(chosen.status().code(), ErrorCode::Unsupported);

    options.backendGiven = false;
    options.method = "no-such-method";
    chosen = chooseInitialMethod(made, options, everything);
    ASSERT_FALSE(chosen);
    EXPECT_EQ(chosen.status().code(), ErrorCode::Usage);
    EXPECT_NE(chosen.status().message().find("--method 'no-such-method'"), std::string::npos);
}

}  // namespace
}  // namespace mvr::viewer
