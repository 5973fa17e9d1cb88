// Direct lenticular rendering (mvr/session/direct.h, `mvr render --direct`): the panel image
// composed from soft:unified's bands equals composing the views of the reference method
// (soft:multipass, rendered whole) with composite::lenticular(), bit for bit, for a Portrait-like
// calibration (a 0.75 panel, mirrored vertically, B,G,R, views inverted) and a Go-like one (a
// 0.5625 panel, mirrored horizontally, another slope), one and four samples a pixel; and the
// requests it cannot serve are refused with a message naming the culprit.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/composite/lenticular.h"
#include "mvr/raster/soft_backend.h"
#include "mvr/session/direct.h"

namespace mvr {
namespace {

struct Panel {
    const char* name;
    composite::LenticularCalibration cal;
    int views, viewWidth, viewHeight;
};

composite::LenticularCalibration portraitLike() {
    composite::LenticularCalibration c;  // a Portrait's visual.json, on a 96x128 panel
    c.pitch = 52.59267044067383, c.slope = -7.083540916442871, c.center = 0.8167931437492371;
    c.dpi = 324.0 / 16.0;  // the panel's size in inches kept at 16x fewer pixels
    c.screenWidth = 96, c.screenHeight = 128;
    c.invertViews = true, c.flipY = true, c.bgr = true;
    return c;
}

composite::LenticularCalibration goLike() {
    composite::LenticularCalibration c;  // a 0.5625 (9:16) panel, lenses the other way
    c.pitch = 80.7, c.slope = 6.2, c.center = -0.31, c.dpi = 491.0 / 16.0;
    c.screenWidth = 90, c.screenHeight = 160;
    c.flipX = true;
    return c;
}

Rig rowRig(int views, int w, int h) {
    Camera cam;
    cam.position = {0.4f, 1.2f, 7.0f};
    cam.target = {0.0f, 0.3f, 0.0f};
    cam.fovYDegrees = 40.0f;
    cam.aspect = float(w) / float(h);
    cam.near = 0.5f;
    cam.far = 40.0f;
    RigParams params;
    params.columns = views;
    params.interaxial = 0.12f;
    params.convergence = 7.0f;
    auto rig = makeRig(cam, params);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

class Direct : public ::testing::TestWithParam<int> {};

TEST_P(Direct, EqualsComposingTheReferenceViews) {
    const int samples = GetParam();
    const Scene scene = makeDefaultScene();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft) << soft.status().message();
    for (const Panel& panel : {Panel{"portrait-like", portraitLike(), 12, 60, 80},
                               Panel{"go-like", goLike(), 7, 36, 64}}) {
        SCOPED_TRACE(panel.name);
        const Rig rig = rowRig(panel.views, panel.viewWidth, panel.viewHeight);
        RenderSettings settings;
        settings.width = panel.viewWidth, settings.height = panel.viewHeight;
        settings.samples = samples;
        auto views = (*soft)->render(scene, rig, settings, "multipass");
        ASSERT_TRUE(views) << views.status().message();
        auto composed = composite::lenticular(views->color, panel.cal);
        ASSERT_TRUE(composed) << composed.status().message();
        auto direct =
            session::renderDirectLenticular(**soft, scene, rig, settings, "unified", panel.cal);
        ASSERT_TRUE(direct) << direct.status().message();
        ASSERT_EQ(direct->width, panel.cal.screenWidth);
        ASSERT_EQ(direct->height, panel.cal.screenHeight);
        EXPECT_TRUE(direct->rgba == composed->rgba);
        // Not a blank panel: the scene covers a good part of it, and the views differ (the
        // panel is not one view's picture).
        const std::uint32_t clear = 0xff000000u;
        std::size_t drawn = 0;
        for (std::size_t i = 0; i < direct->rgba.size(); i += 4) {
            std::uint32_t px = 0xff000000u | direct->rgba[i] | direct->rgba[i + 1] << 8 |
                               direct->rgba[i + 2] << 16;
            drawn += px != clear;
        }
        EXPECT_GT(drawn, direct->rgba.size() / 4 / 5);
        EXPECT_FALSE(views->color.front().rgba == views->color.back().rgba);
    }
}

INSTANTIATE_TEST_SUITE_P(Samples, Direct, ::testing::Values(1, 4));

TEST(DirectRefusals, NameTheMethodAndTheBackend) {
    const Scene scene = makeDefaultScene();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    RenderSettings settings;
    settings.width = 36, settings.height = 64;
    const Rig rig = rowRig(4, 36, 64);
    auto multipass =
        session::renderDirectLenticular(**soft, scene, rig, settings, "multipass", goLike());
    ASSERT_FALSE(multipass);
    EXPECT_EQ(multipass.status().code(), ErrorCode::Unsupported);
    EXPECT_NE(multipass.status().message().find("only soft:unified with 2 or more views"),
              std::string::npos)
        << multipass.status().message();
    const Rig one = rowRig(1, 36, 64);
    auto single = session::renderDirectLenticular(**soft, scene, one, settings, "unified", goLike());
    ASSERT_FALSE(single);
    EXPECT_NE(single.status().message().find("soft:unified with 1 view:"), std::string::npos)
        << single.status().message();
    composite::LenticularCalibration bad = goLike();
    bad.dpi = -1.0;
    auto calibration = session::renderDirectLenticular(**soft, scene, rig, settings, "unified", bad);
    ASSERT_FALSE(calibration);
    EXPECT_NE(calibration.status().message().find("dpi -1"), std::string::npos)
        << calibration.status().message();
}

}  // namespace
}  // namespace mvr
