// Display presets, parallax per rig kind, the screen's budget and the auto rules
// (include/mvr/core/displays.h, issue 13). Expected values are computed here from the rigs'
// matrices (mvr::parallax()) or by hand, not from the code under test.
#include <cmath>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "mvr/core/displays.h"
#include "mvr/core/rig.h"

namespace mvr {
namespace {

TEST(Displays, PresetsCarryTheMakersFigures) {
    auto portrait = findDisplay("portrait");
    ASSERT_TRUE(portrait);
    EXPECT_EQ(portrait->views, 48);
    EXPECT_EQ(portrait->quiltColumns * portrait->quiltRows, 48);
    EXPECT_EQ(portrait->viewWidth, 420);
    EXPECT_EQ(portrait->viewHeight, 560);
    EXPECT_EQ(portrait->quiltColumns * portrait->viewWidth, 3360);
    EXPECT_FLOAT_EQ(portrait->aspect, 0.75f);
    EXPECT_EQ(portrait->viewConeDegrees, 40.0f);
    EXPECT_EQ(aspectText(portrait->aspect), "0.75");
    for (const DisplayPreset& d : displayPresets()) {
        EXPECT_GE(d.views, 2) << d.name;
        EXPECT_LE(d.views, kMaxViews) << d.name;
        EXPECT_GT(d.viewWidth, 0) << d.name;
        EXPECT_GT(d.aspect, 0.0f) << d.name;
        if (d.quiltColumns > 0) {
            EXPECT_EQ(d.quiltColumns * d.quiltRows, d.views) << d.name;
            EXPECT_LE(d.quiltColumns * d.viewWidth, d.quiltWidth) << d.name;
            EXPECT_GT(d.viewConeDegrees, 0.0f) << d.name;
        }
    }
    const auto bad = findDisplay("nosuch");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().code(), ErrorCode::Usage);
    EXPECT_NE(bad.status().message().find("portrait"), std::string::npos);
    EXPECT_NE(bad.status().message().find("3dtv"), std::string::npos);
}

Rig rigOf(RigKind kind, int columns, float interaxial, float convergence) {
    Camera camera;
    camera.position = {0.0f, 0.0f, 10.0f};
    camera.target = {0.0f, 0.0f, 0.0f};
    camera.near = 0.5f;
    camera.far = 200.0f;
    RigParams p;
    p.kind = kind;
    p.columns = columns;
    p.interaxial = interaxial;
    p.convergence = convergence;
    auto rig = makeRig(camera, p);
    EXPECT_TRUE(rig);
    return *rig;
}

// parallaxRange() of each rig equals the parallax the rig's matrices give a point on the axis.
TEST(Displays, EachRigHasItsOwnParallax) {
    for (RigKind kind : {RigKind::OffAxis, RigKind::Parallel, RigKind::ToeIn}) {
        for (int columns : {2, 5}) {
            const Rig rig = rigOf(kind, columns, 0.3f, 8.0f);
            for (float w : {4.5f, 8.0f, 30.0f}) {
                const glm::vec3 point(0.0f, 0.0f, 10.0f - w);
                const float expected = parallax(rig, point, 0, columns - 1);
                const ParallaxRange r = parallaxRange(rig, w, w);
                EXPECT_NEAR(r.minParallax, expected, 1e-4f)
                    << rigKindName(kind) << " columns " << columns << " w " << w;
            }
        }
    }
    // The parallel rig: negative everywhere (nothing behind the screen), no convergence rule.
    const Rig par = rigOf(RigKind::Parallel, 2, 0.3f, 8.0f);
    const ParallaxRange r = parallaxRange(par, 2.0f, 1000.0f);
    EXPECT_LT(r.maxParallax, 0.0f);
    EXPECT_TRUE(r.comfortable) << r.why;
}

TEST(Displays, TheBudgetIsTheEyeSeparation) {
    ScreenGeometry tv{100.0f, 300.0f};
    const ParallaxBudget b = parallaxBudget(tv);
    EXPECT_FLOAT_EQ(b.eyeSeparation, 0.065f);
    EXPECT_FLOAT_EQ(b.fraction, 0.065f);
    EXPECT_FALSE(b.desktop);
    ScreenGeometry desk{50.0f, 60.0f};
    const ParallaxBudget d = parallaxBudget(desk);
    EXPECT_TRUE(d.desktop);
    EXPECT_FLOAT_EQ(d.fraction, 0.5f * 6.5f / 50.0f);
    EXPECT_FALSE(parallaxBudget({50.0f, 0.0f}).desktop);  // distance unknown: the full budget
}

// Allowed and each broken rule, the parallax computed by hand: off-axis stereo,
// s = interaxial / W, parallax = s (1 - C / w), W = 2 C aspect tan(fov / 2).
TEST(Displays, ScreenComfortFlagsEachBrokenRuleAndNothingElse) {
    const float c = 8.0f;
    const float screenWorld = 2.0f * c * (4.0f / 3.0f) * std::tan(glm::radians(22.5f));
    auto rigWithSeparation = [&](float s) {
        return rigOf(RigKind::OffAxis, 2, s * screenWorld, c);
    };
    auto byHand = [&](float s, float w) { return s * (1.0f - c / w); };
    const ScreenGeometry screen{50.0f, 200.0f};  // living room: budget 6.5 cm = 13 %

    // Allowed: s = 5 %, w in [6, 20]: -1.67 % .. +3 % = -0.83 .. +1.5 cm.
    {
        const Rig rig = rigWithSeparation(0.05f);
        const ParallaxRange r = parallaxRange(rig, 6.0f, 20.0f);
        EXPECT_TRUE(r.comfortable) << r.why;
        const ScreenComfort sc = screenComfort(rig, r, 1, screen);
        EXPECT_TRUE(sc.comfortable) << sc.why;
        EXPECT_NEAR(sc.minParallaxCm, 50.0f * byHand(0.05f, 6.0f), 1e-3f);
        EXPECT_NEAR(sc.maxParallaxCm, 50.0f * byHand(0.05f, 20.0f), 1e-3f);
        const float vergence =
            glm::degrees(2.0f * std::atan((6.5f - 50.0f * byHand(0.05f, 6.0f)) / (2.0f * 200.0f)));
        EXPECT_NEAR(sc.nearestVergenceDeg, vergence, 1e-4f);
        EXPECT_NEAR(sc.screenVergenceDeg, glm::degrees(2.0f * std::atan(6.5f / 400.0f)), 1e-4f);
    }
    // Behind the screen beyond the budget (not yet diverging): s = 18 %, w = 50:
    // 0.18 (1 - 8/50) = 15.1 % = 7.56 cm > 6.5 cm → the eyes diverge.
    {
        const Rig rig = rigWithSeparation(0.18f);
        const ParallaxRange r = parallaxRange(rig, 7.0f, 50.0f);
        const ScreenComfort sc = screenComfort(rig, r, 1, screen);
        EXPECT_FALSE(sc.comfortable);
        EXPECT_NE(sc.why.find("they diverge"), std::string::npos) << sc.why;
        // On a desktop (60 cm) the budget halves: 3.25 cm; s = 8 %, w = 50 → 3.36 cm.
        const Rig desk = rigWithSeparation(0.08f);
        const ScreenComfort d =
            screenComfort(desk, parallaxRange(desk, 7.0f, 50.0f), 1, {50.0f, 60.0f});
        EXPECT_NEAR(d.maxParallaxCm, 50.0f * byHand(0.08f, 50.0f), 1e-3f);
        EXPECT_FALSE(d.comfortable);
        EXPECT_NE(d.why.find("parallax behind the screen"), std::string::npos) << d.why;
        EXPECT_NE(d.why.find("half the eye separation"), std::string::npos) << d.why;
        // The same rig on the living-room screen is fine.
        EXPECT_TRUE(screenComfort(desk, parallaxRange(desk, 7.0f, 50.0f), 1, screen).comfortable);
    }
    // Out of the screen beyond the budget: s = 10 %, w = 4.1 (> C/2): 0.1 (1 - 8/4.1) = -9.5 %
    // = -4.76 cm, beyond the desktop budget 3.25 cm.
    {
        const Rig rig = rigWithSeparation(0.10f);
        const ParallaxRange r = parallaxRange(rig, 4.1f, 9.0f);
        EXPECT_TRUE(r.comfortable) << r.why;
        const ScreenComfort sc = screenComfort(rig, r, 1, {50.0f, 60.0f});
        EXPECT_FALSE(sc.comfortable);
        EXPECT_NE(sc.why.find("out of the screen"), std::string::npos) << sc.why;
    }
    // The depth rules still apply: nearer than C/2, farther than 100 C.
    {
        const Rig rig = rigWithSeparation(0.01f);
        EXPECT_EQ(parallaxRange(rig, 3.9f, 9.0f).why, "scene reaches closer than convergence/2");
        EXPECT_EQ(parallaxRange(rig, 5.0f, 801.0f).why, "scene reaches beyond 100 x convergence");
    }
}

// A light-field row is judged by the views the eyes see together (adjacent), not its outer pair.
TEST(Displays, ARowOfViewsIsJudgedByAdjacentViews) {
    const float c = 8.0f;
    const float screenWorld = 2.0f * c * (4.0f / 3.0f) * std::tan(glm::radians(22.5f));
    // 48 views, adjacent separation 5 %: the outer views 47 × 5 % = 235 % apart in separation;
    // at w = 6: outer parallax 2.35 (1 - 8/6) = -78 %, at w = 30: +172 %; adjacent +3.7 %.
    const Rig row = rigOf(RigKind::OffAxis, 48, 0.05f * screenWorld, c);
    const ParallaxRange r = parallaxRange(row, 6.0f, 30.0f);
    EXPECT_GT(r.maxParallax, 1.0f);
    EXPECT_TRUE(r.comfortable) << r.why;
    // Adjacent views a screen width and more apart: flagged.
    const Rig absurd = rigOf(RigKind::OffAxis, 48, 2.0f * screenWorld, c);
    const ParallaxRange a = parallaxRange(absurd, 6.0f, 30.0f);
    EXPECT_FALSE(a.comfortable);
    EXPECT_NE(a.why.find("between adjacent views"), std::string::npos) << a.why;
}

// A row of N views: the eyes see views k apart, k = the eyes' angle over the views' spacing.
TEST(Displays, TheEyesSeeViewsOfTheConeApart) {
    const Rig rig = rigOf(RigKind::OffAxis, 48, 0.1f, 8.0f);
    // 6.5 cm at 40 cm: 2 atan(3.25 / 40) = 9.29 deg; 40 deg / 47 = 0.851 deg per view → 11.
    EXPECT_EQ(eyePairViews(rig, 40.0f, {12.0f, 40.0f}), 11);
    EXPECT_EQ(eyePairViews(rig, 40.0f, {12.0f, 0.0f}), 1);   // distance unknown: adjacent
    EXPECT_EQ(eyePairViews(rig, 0.0f, {12.0f, 40.0f}), 1);   // no cone
    EXPECT_EQ(eyePairViews(rig, 40.0f, {12.0f, 1.0f}), 47);  // clamped
    const ParallaxRange outer = parallaxRange(rig, 6.0f, 12.0f);
    const ScreenComfort sc = screenComfort(rig, outer, 11, {12.0f, 40.0f});
    EXPECT_NEAR(sc.minParallax, outer.minParallax * 11.0f / 47.0f, 1e-6f);
}

// Issue 42 item 0: --separation auto keeps the parallax the eyes meet within the screen's
// budget for the whole scene — at infinity (the separation itself, nvidia-gtc2010 "Separation
// should be Comfortable") and at the scene's nearest and farthest points. The budget and the
// off-axis parallax s (1 - C / w) are written here, not taken from the code under test.
TEST(Displays, AutoSeparationKeepsTheWholeSceneWithinTheBudget) {
    const float c = 8.0f;
    const float screenWorld = 2.0f * c * (4.0f / 3.0f) * std::tan(glm::radians(22.5f));
    const Rig trial = rigOf(RigKind::OffAxis, 2, 0.01f * screenWorld, c);
    auto budgetByHand = [](float widthCm, float distanceCm) {
        const float eyeSeparation = 6.5f / widthCm;
        return distanceCm > 0.0f && distanceCm < 100.0f ? 0.5f * eyeSeparation : eyeSeparation;
    };
    auto byHand = [&](float s, float w) { return s * (1.0f - c / w); };
    // The engine-like case: a wide object framed close, 0.86 .. 1.2 x the convergence.
    const float nearest = 6.9f, farthest = 9.6f;
    for (const ScreenGeometry screen : {ScreenGeometry{50.0f, 0.0f}, ScreenGeometry{50.0f, 60.0f},
                                        ScreenGeometry{120.0f, 300.0f}}) {
        const float budget = budgetByHand(screen.widthCm, screen.viewingDistanceCm);
        for (float percent : {100.0f, 50.0f, 10.0f}) {
            const float s = autoSeparation(trial, nearest, farthest, parallaxBudget(screen), percent);
            const float target = percent / 100.0f * budget;
            const float worst = std::max({std::abs(byHand(s, nearest)),
                                          std::abs(byHand(s, farthest)), s /* at infinity */});
            EXPECT_NEAR(worst, target, 1e-4f * target) << screen.widthCm << " " << percent;
            EXPECT_LE(worst, budget * (1.0f + 1e-4f));
            // The rig's own matrices agree: a point far behind the scene stays within it.
            const Rig rig = rigOf(RigKind::OffAxis, 2, s * screenWorld, c);
            for (float w : {nearest, farthest, 1e4f}) {
                const float p = parallax(rig, glm::vec3(0.0f, 0.0f, 10.0f - w), 0, 1);
                EXPECT_LE(std::abs(p), budget * 1.001f) << "w " << w;
            }
            const ScreenComfort sc =
                screenComfort(rig, parallaxRange(rig, nearest, farthest), 1, screen);
            EXPECT_TRUE(sc.comfortable) << sc.why;
            EXPECT_NEAR(sc.infinityParallaxCm, s * screen.widthCm, 1e-3f);
        }
    }
    // The separation the bug report got (scene parallax filled, 36 % on a 50 cm desktop
    // screen): the scene alone stays within 3.25 cm, but at infinity the parallax is 18 cm —
    // the report never calls that comfortable.
    {
        const ScreenGeometry desk{50.0f, 60.0f};
        const float budgetCm = budgetByHand(50.0f, 60.0f) * 50.0f;  // 3.25 cm
        const Rig rig = rigOf(RigKind::OffAxis, 2, 0.36f * screenWorld, c);
        EXPECT_LE(std::abs(50.0f * byHand(0.36f, nearest)), budgetCm);
        EXPECT_LE(std::abs(50.0f * byHand(0.36f, farthest)), budgetCm);
        const ScreenComfort sc = screenComfort(rig, parallaxRange(rig, nearest, farthest), 1, desk);
        EXPECT_FALSE(sc.comfortable);
        EXPECT_NE(sc.why.find("separation 18.00 cm (the parallax at infinity) exceeds"),
                  std::string::npos)
            << sc.why;
        EXPECT_NE(sc.why.find("the eyes diverge"), std::string::npos) << sc.why;
        // A light-field row spread over a view cone is judged by its scene's parallax only.
        const ScreenComfort cone =
            screenComfort(rig, parallaxRange(rig, nearest, farthest), 1, desk, 40.0f);
        EXPECT_FALSE(cone.separationRule);
        EXPECT_TRUE(cone.comfortable) << cone.why;
    }
    // A scene nearer than convergence / 2: there the parallax out of the screen is larger than
    // the separation, so the nearest point sets it: s (C / n - 1) = budget.
    {
        const ScreenGeometry tv{100.0f, 300.0f};
        const float budget = budgetByHand(100.0f, 300.0f);
        const float s = autoSeparation(trial, 3.0f, 20.0f, parallaxBudget(tv));
        EXPECT_NEAR(s, budget / (c / 3.0f - 1.0f), 1e-4f * budget);
        EXPECT_NEAR(byHand(s, 3.0f), -budget, 1e-4f * budget);
    }
    // A parallel rig has no parallax at infinity: its nearest point sets it, s C / n = budget.
    {
        const Rig par = rigOf(RigKind::Parallel, 2, 0.01f * screenWorld, c);
        const float budget = budgetByHand(50.0f, 0.0f);
        const float s = autoSeparation(par, nearest, farthest, parallaxBudget({50.0f, 0.0f}));
        EXPECT_NEAR(s * c / nearest, budget, 1e-4f * budget);
        EXPECT_EQ(parallaxAtInfinity(par), 0.0f);
    }
}

TEST(Displays, BalancedConvergenceEqualsTheParallaxInAndOut) {
    for (auto [n, f] : {std::pair{2.0f, 6.0f}, std::pair{1.0f, 150.0f}, std::pair{5.0f, 5.5f}}) {
        const float c = balancedConvergence(n, f);
        EXPECT_GE(c, n);
        EXPECT_LE(c, f);
        EXPECT_LE(c, 2.0f * n);                             // the convergence/2 rule holds
        EXPECT_NEAR(-(1.0f - c / n), 1.0f - c / f, 1e-5f);  // equal magnitudes
    }
}

TEST(Displays, DepthPercentilesIgnoreTheBackground) {
    const float near = 1.0f, far = 11.0f;
    auto windowDepth = [&](float w) {  // the inverse of distanceFromWindowDepth
        const float z = ((far + near) - 2.0f * near * far / w) / (far - near);
        return 0.5f * z + 0.5f;
    };
    std::vector<float> depth(1000, 1.0f);  // background
    for (int i = 0; i < 500; ++i) depth[i] = windowDepth(2.0f + 4.0f * float(i) / 499.0f);
    auto p = depthPercentiles(depth, near, far, 0.0f, 100.0f);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->pixels, 500);
    EXPECT_NEAR(p->minimum, 2.0f, 1e-3f);
    EXPECT_NEAR(p->maximum, 6.0f, 1e-3f);
    EXPECT_NEAR(p->nearest, 2.0f, 0.05f);
    EXPECT_NEAR(p->farthest, 6.0f, 0.05f);
    EXPECT_FALSE(depthPercentiles(std::vector<float>(10, 1.0f), near, far));
}

}  // namespace
}  // namespace mvr
