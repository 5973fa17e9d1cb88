// View synthesis (mvr/core/synthesize.h, `--synthesize K`): which views are exact, the rigs it
// refuses, and the warp itself against exact renders — a fronto-parallel plane whose parallax
// between adjacent views is a whole number of pixels (computed here from the eye geometry, not
// from the rig's matrices) lands exactly where an exact render puts it; the exact views are the
// plain render's, bit for bit; and a scene with occlusions stays close to its exact render.
#include <cmath>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/core/synthesize.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

TEST(Synthesize, ExactColumnsAreEveryKthAndTheLast) {
    EXPECT_EQ(exactColumns(9, 4), (std::vector<int>{0, 4, 8}));
    EXPECT_EQ(exactColumns(10, 4), (std::vector<int>{0, 4, 8, 9}));
    EXPECT_EQ(exactColumns(45, 4), (std::vector<int>{0, 4, 8, 12, 16, 20, 24, 28, 32, 36, 40, 44}));
    EXPECT_EQ(exactColumns(5, 1), (std::vector<int>{0, 1, 2, 3, 4}));
    EXPECT_EQ(exactColumns(3, 64), (std::vector<int>{0, 2}));
    EXPECT_EQ(exactColumns(1, 4), (std::vector<int>{0}));
}

// The scene: vertical bars of different colours in the plane z = 0, seen from z = 10 (w = 10),
// over the clear colour; unlit-looking (no specular) so a bar's colour is the same in every view.
constexpr int kW = 160, kH = 120;
constexpr float kC = 5.0f;       // convergence
constexpr float kDist = 10.0f;   // the camera's distance to the bars' plane
constexpr float kFovY = 45.0f;
constexpr int kViews = 9;

struct Bar {
    float x0, x1;
    glm::vec3 color;
};
const std::vector<Bar> kBars = {{-3.1f, -2.05f, {0.9f, 0.2f, 0.1f}},
                                {-1.37f, -0.42f, {0.1f, 0.8f, 0.2f}},
                                {0.31f, 1.23f, {0.2f, 0.3f, 0.9f}},
                                {1.9f, 3.3f, {0.9f, 0.8f, 0.1f}}};

Scene barScene(float backdropZ = 0.0f) {
    Scene s;
    s.lights = defaultLights();
    s.ambient = glm::vec3(1.0f);
    auto quad = [&](float x0, float x1, float y0, float y1, float z, glm::vec3 color) {
        Mesh m;
        m.name = "bar";
        m.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
        m.normals.assign(4, {0, 0, 1});
        m.indices = {0, 1, 2, 0, 2, 3};
        s.meshes.push_back(std::move(m));
        Instance inst;
        inst.mesh = int(s.meshes.size()) - 1;
        inst.material = Material(color, 0.0f);
        s.instances.push_back(inst);
    };
    for (const Bar& b : kBars) quad(b.x0, b.x1, -1.5f, 1.5f, 0.0f, b.color);
    if (backdropZ < 0.0f) {  // a checkered wall behind the bars: what they uncover differs
        for (int i = -12; i < 12; ++i)
            for (int j = -6; j < 6; ++j)
                quad(float(i), float(i + 1), float(j), float(j + 1), backdropZ,
                     (i + j) % 2 ? glm::vec3(0.7f, 0.7f, 0.75f) : glm::vec3(0.3f, 0.25f, 0.2f));
    }
    return s;
}

/// Half the window's width at the convergence plane (rig.h: a = C · aspect · tan(fovY / 2)).
float halfWindow() {
    return kC * (float(kW) / float(kH)) * std::tan(glm::radians(kFovY) / 2.0f);
}

/// The eye spacing that gives a point at distance `w` a parallax of `pixels` between adjacent
/// views: by similar triangles a point at w seen from eyes d apart is d · (w − C) / w apart on
/// the screen plane at C, whose 2a world units are kW pixels.
float spacingFor(float pixels, float w) {
    return pixels * 2.0f * halfWindow() * w / (float(kW) * (w - kC));
}

Rig barRig(float spacing, RigKind kind = RigKind::OffAxis, int views = kViews) {
    Camera cam;
    cam.position = {0.0f, 0.0f, kDist};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDegrees = kFovY;
    cam.aspect = float(kW) / float(kH);
    cam.near = 1.0f;
    cam.far = 40.0f;
    RigParams params;
    params.kind = kind;
    params.columns = views;
    params.interaxial = spacing;
    params.convergence = kC;
    auto rig = makeRig(cam, params);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

/// The output column (pixel edge, 0..kW) where world x = `x` on the plane z = 0 appears in
/// view `v`: the eye at offset o = (v − (n − 1) / 2) · d looks through the window [−a, a] at
/// distance C, so the point is seen at o + (x − o) · C / w on it.
float columnOf(float x, int v, float spacing) {
    const float o = (float(v) - float(kViews - 1) / 2.0f) * spacing;
    const float onScreen = o + (x - o) * kC / kDist;
    return (onScreen / halfWindow() + 1.0f) * 0.5f * float(kW);
}

RenderSettings settings() {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.clearColor = glm::vec3(0.05f, 0.05f, 0.05f);
    return s;
}

/// Every view of `rig` rendered exactly (soft:multipass) and with --synthesize 4.
void renderBoth(const Scene& scene, const Rig& rig, RenderOutput& exact, RenderOutput& warped) {
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft) << soft.status().message();
    auto e = (*soft)->render(scene, rig, settings(), "multipass");
    ASSERT_TRUE(e) << e.status().message();
    auto w = renderSynthesized(**soft, scene, rig, settings(), "multipass", 4);
    ASSERT_TRUE(w) << w.status().message();
    exact = std::move(*e);
    warped = std::move(*w);
}

TEST(Synthesize, APlaneWithWholePixelParallaxLandsWhereTheEyesPutIt) {
    const float d = spacingFor(2.0f, kDist);  // 2 pixels a view
    const Scene scene = barScene();
    const Rig rig = barRig(d);
    RenderOutput exact, warped;
    ASSERT_NO_FATAL_FAILURE(renderBoth(scene, rig, exact, warped));
    ASSERT_EQ(warped.color.size(), std::size_t(kViews));
    ASSERT_EQ(warped.depth.size(), std::size_t(kViews));
    const int y = kH / 2;
    for (int v = 0; v < kViews; ++v) {
        const Image& w = warped.color[std::size_t(v)];
        const Image& e = exact.color[std::size_t(v)];
        if (v % 4 == 0) {  // exact views: the plain render's, bit for bit
            EXPECT_TRUE(w == e) << "exact view " << v;
            continue;
        }
        // Where the eyes put every bar: its colour well inside, the background just outside,
        // in the exact view (the formula is right) and in the warped one (the warp is).
        const Rgba8 background = e.at(0, 0);
        for (const Bar& b : kBars) {
            const float c0 = columnOf(b.x0, v, d), c1 = columnOf(b.x1, v, d);
            const int inside = int(std::floor((c0 + c1) / 2.0f));
            const int before = int(std::floor(c0)) - 1, after = int(std::ceil(c1));
            if (inside >= 0 && inside < kW) {
                EXPECT_NE(e.at(inside, y), background)
                    << "exact view " << v << ": the bar at x " << b.x0 << " is not at column "
                    << inside;
                EXPECT_EQ(w.at(inside, y), e.at(inside, y))
                    << "warped view " << v << ": the bar at x " << b.x0 << " at column " << inside;
            }
            for (const Image* im : {&e, &w}) {
                const char* which = im == &e ? "exact" : "warped";
                if (before >= 0 && before < kW) {
                    EXPECT_EQ(im->at(before, y), background)
                        << which << " view " << v << ": column " << before
                        << " left of the bar at x " << b.x0 << " is not background";
                }
                if (after >= 0 && after < kW) {
                    EXPECT_EQ(im->at(after, y), background)
                        << which << " view " << v << ": column " << after
                        << " right of the bar at x " << b.x1 << " is not background";
                }
            }
        }
        // Shifted by whole pixels, every pixel but those at a bar's edge is the exact one.
        long off = 0;
        for (int yy = 0; yy < kH; ++yy)
            for (int x = 0; x < kW; ++x) {
                bool nearEdge = false;
                for (const Bar& b : kBars)
                    for (float edge : {columnOf(b.x0, v, d), columnOf(b.x1, v, d)})
                        nearEdge = nearEdge || std::abs(float(x) + 0.5f - edge) < 1.5f;
                const bool same = w.at(x, yy) == e.at(x, yy);
                if (!same && !nearEdge) ++off;
            }
        EXPECT_EQ(off, 0) << "view " << v << ": pixels off the exact render away from the edges";
    }
}

TEST(Synthesize, WhatABarUncoversComesFromTheOtherExactView) {
    // The bars 10 from the eyes (4 pixels a view), a checkered wall 10 behind them: at w = 20
    // its parallax is (1 − C / 20) / (1 − C / 10) = 1.5 times the bars', 6 pixels a view. A
    // warped view 1 or 2 views from the nearer exact view sees 2 or 4 columns of wall beside
    // each bar that that view has behind the bar; the other exact view sees them. Whole-pixel
    // shifts: every pixel is the exact render's, those uncovered included.
    const float d = spacingFor(4.0f, kDist);
    const Scene scene = barScene(-10.0f);
    const Rig rig = barRig(d);
    RenderOutput exact, warped;
    ASSERT_NO_FATAL_FAILURE(renderBoth(scene, rig, exact, warped));
    for (int v = 0; v < kViews; ++v) {
        if (v % 4 == 0) continue;
        const Image& w = warped.color[std::size_t(v)];
        const Image& e = exact.color[std::size_t(v)];
        long off = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) off += w.at(x, y) == e.at(x, y) ? 0 : 1;
        EXPECT_EQ(off, 0) << "view " << v << ": pixels off the exact render";
    }
}

TEST(Synthesize, CompareImagesGivesThePsnrAndTheShareOfPixelsOffByMoreThanTheThreshold) {
    const Image a(4, 1, Rgba8{100, 100, 100, 255});
    Image b = a;
    EXPECT_TRUE(std::isinf(compareImages(a, b).psnr));
    b.set(1, 0, Rgba8{103, 100, 100, 255});  // off by 3 (more than 2/255): 1 pixel of 4
    b.set(2, 0, Rgba8{100, 102, 100, 255});  // off by 2: not counted
    const ImageDiff e = compareImages(b, a, 2);
    EXPECT_EQ(e.differingPixels, 1);
    EXPECT_EQ(e.pixels, 4);
    EXPECT_DOUBLE_EQ(e.percentDiffering(), 25.0);
    // The mean squared error over the 12 channel values: (9 + 4) / 12.
    EXPECT_NEAR(e.psnr, 10.0 * std::log10(255.0 * 255.0 / (13.0 / 12.0)), 1e-9);
}

TEST(Synthesize, RigsWithoutAShearOrWithTooFewViewsAreRefused) {
    const float d = spacingFor(2.0f, kDist);
    const Status toein = checkSynthesisRig(barRig(d, RigKind::ToeIn), "--synthesize 4");
    EXPECT_EQ(toein.code(), ErrorCode::Usage);
    EXPECT_EQ(toein.message(),
              "--synthesize 4: needs an off-axis rig (the warp is the horizontal shear between "
              "its views; --rig toein has none)");
    const Status two = checkSynthesisRig(barRig(d, RigKind::OffAxis, 2), "--synthesize 2");
    EXPECT_EQ(two.code(), ErrorCode::Usage);
    EXPECT_EQ(two.message(),
              "--synthesize 2: needs rows of at least 3 views (the rig has 2 views in 1 row)");
    EXPECT_TRUE(checkSynthesisRig(barRig(d), "--synthesize 4"));
    // k = 1 is the plain render.
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    auto one = renderSynthesized(**soft, barScene(), barRig(d, RigKind::ToeIn), settings(),
                                 "multipass", 1);
    EXPECT_TRUE(one) << one.status().message();
}

}  // namespace
}  // namespace mvr
