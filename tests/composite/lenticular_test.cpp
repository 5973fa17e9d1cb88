#include "mvr/composite/lenticular.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "test_views.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

// A panel whose lenses are (numerically) vertical and 3 pixels = 9 sub-pixels wide: 12 px at
// 12 dpi is 1 inch, 4 lenticules per inch → 4 lenses across. With 9 views every sub-pixel of a
// lens shows another view, and the pixel centre offset (half a pixel = 1.5 sub-pixels) puts
// sub-pixel k = 3·px + i in the middle of view (k + 1) mod 9.
LenticularCalibration verticalPanel() {
    LenticularCalibration cal;
    cal.pitch = 4.0;
    cal.slope = 1e12;
    cal.center = 0.0;
    cal.dpi = 12.0;
    return cal;
}

std::vector<Image> solidViews(int n, int w, int h) {
    std::vector<Image> views;
    for (int v = 0; v < n; ++v)
        views.push_back(
            solid(w, h, {std::uint8_t(10 + v), std::uint8_t(100 + v), std::uint8_t(200 + v), 255}));
    return views;
}

TEST(Lenticular, ShaderParamsFollowLookingGlassFormula) {
    LenticularCalibration cal;  // defaults: a Looking Glass Portrait
    Result<LenticularShaderParams> p = lenticularShaderParams(cal, 1536, 2048);
    ASSERT_TRUE(p) << p.status().message();
    const double screenInches = 1536 / 324.0;
    EXPECT_NEAR(p->pitchU, 52.59267 * screenInches * std::cos(std::atan(1.0 / -7.08354)), 1e-9);
    EXPECT_NEAR(p->tilt, 2048.0 / (1536.0 * -7.08354), 1e-12);
    EXPECT_NEAR(p->subp, 1.0 / (3 * 1536.0), 1e-15);
    EXPECT_EQ(p->ri, 0);
    EXPECT_EQ(p->bi, 2);
    cal.flipX = true;
    cal.bgr = true;
    p = lenticularShaderParams(cal, 1536, 2048);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->tilt, -2048.0 / (1536.0 * -7.08354), 1e-12);
    EXPECT_EQ(p->ri, 2);
    EXPECT_EQ(p->bi, 0);
}

TEST(Lenticular, VerticalLensesGiveOneViewPerSubpixel) {
    const auto views = solidViews(9, 12, 2);
    Result<Image> out = lenticular(views, verticalPanel());
    ASSERT_TRUE(out) << out.status().message();
    ASSERT_EQ(out->width, 12);
    ASSERT_EQ(out->height, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 12; ++x) {
            const int vr = (3 * x + 0 + 1) % 9, vg = (3 * x + 1 + 1) % 9, vb = (3 * x + 2 + 1) % 9;
            EXPECT_EQ(out->at(x, y), (Rgba8{std::uint8_t(10 + vr), std::uint8_t(100 + vg),
                                            std::uint8_t(200 + vb), 255}))
                << x << "," << y;
        }
}

TEST(Lenticular, InvertViewsAndBgrOrder) {
    const auto views = solidViews(9, 12, 1);
    LenticularCalibration cal = verticalPanel();
    cal.invertViews = true;
    Result<Image> inv = lenticular(views, cal);
    ASSERT_TRUE(inv);
    for (int x = 0; x < 12; ++x) {
        const int vr = 8 - (3 * x + 1) % 9;
        EXPECT_EQ(inv->at(x, 0).r, 10 + vr) << x;
    }
    cal.invertViews = false;
    cal.bgr = true;  // red is the right-most sub-pixel: it shows sub-pixel 2's view
    Result<Image> bgr = lenticular(views, cal);
    ASSERT_TRUE(bgr);
    for (int x = 0; x < 12; ++x) {
        EXPECT_EQ(bgr->at(x, 0).r, 10 + (3 * x + 2 + 1) % 9) << x;
        EXPECT_EQ(bgr->at(x, 0).g, 100 + (3 * x + 1 + 1) % 9) << x;
        EXPECT_EQ(bgr->at(x, 0).b, 200 + (3 * x + 0 + 1) % 9) << x;
    }
}

TEST(Lenticular, SlantShiftsOneSubpixelPerRowAtSlope3) {
    // tilt = H / (W · slope): at slope 3 going one row down moves the lens phase back by one
    // sub-pixel, so sub-pixel i of the next row shows what sub-pixel i−1 showed (the van Berkel
    // slant of one sub-pixel per row, tan α = 1/3).
    LenticularCalibration cal;
    cal.slope = 3.0;
    cal.pitch = 7.31;
    cal.center = 0.123;
    cal.dpi = 100.0;
    Result<LenticularShaderParams> p = lenticularShaderParams(cal, 40, 30);
    ASSERT_TRUE(p);
    int same = 0, total = 0;
    for (int py = 0; py + 1 < 30; ++py)
        for (int px = 0; px < 40; ++px)
            for (int i = 1; i < 3; ++i) {
                ++total;
                same += lenticularView(*p, 45, 40, 30, px, py + 1, i) ==
                        lenticularView(*p, 45, 40, 30, px, py, i - 1);
            }
    // Equal except where float rounding lands exactly on a view boundary.
    EXPECT_GE(same, total - 2) << same << " of " << total;
}

TEST(Lenticular, EveryChannelComesFromItsViewAtThatPixel) {
    // Tagged views: the channel value names the source pixel, the view is checked by the formula.
    const int n = 5, w = 20, h = 10;
    std::vector<Image> views;
    for (int v = 0; v < n; ++v) {
        Image img(w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                img.set(x, y,
                        {std::uint8_t(v * 50 + x), std::uint8_t(v * 50 + y),
                         std::uint8_t(v * 50 + 1), 255});
        views.push_back(std::move(img));
    }
    LenticularCalibration cal;
    cal.pitch = 11.0;
    cal.slope = -5.5;
    cal.center = 0.3;
    cal.dpi = 50.0;
    Result<Image> out = lenticular(views, cal);
    ASSERT_TRUE(out);
    Result<LenticularShaderParams> p = lenticularShaderParams(cal, w, h);
    ASSERT_TRUE(p);
    std::set<int> seen;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int vr = lenticularView(*p, n, w, h, x, y, 0);
            const int vg = lenticularView(*p, n, w, h, x, y, 1);
            const int vb = lenticularView(*p, n, w, h, x, y, 2);
            seen.insert(vr);
            EXPECT_EQ(out->at(x, y), (Rgba8{std::uint8_t(vr * 50 + x), std::uint8_t(vg * 50 + y),
                                            std::uint8_t(vb * 50 + 1), 255}));
        }
    EXPECT_EQ(seen.size(), std::size_t(n));  // every view shows somewhere
}

TEST(Lenticular, ScreenSizeResamplesAndFlipsMirrorTheLookup) {
    const auto views = taggedViews(2, 4, 2);
    LenticularCalibration cal = verticalPanel();
    cal.screenWidth = 8;
    cal.screenHeight = 4;
    Result<Image> out = lenticular(views, cal);
    ASSERT_TRUE(out);
    ASSERT_EQ(out->width, 8);
    ASSERT_EQ(out->height, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            EXPECT_EQ(out->at(x, y).r, x / 2);  // nearest view pixel: r = view x
            EXPECT_EQ(out->at(x, y).g, y / 2);
        }
    cal.flipX = true;
    cal.flipY = true;
    Result<Image> flipped = lenticular(views, cal);
    ASSERT_TRUE(flipped);
    EXPECT_EQ(flipped->at(0, 0).r, 3);
    EXPECT_EQ(flipped->at(0, 0).g, 1);
}

TEST(Lenticular, ParsesLookingGlassVisualJson) {
    const std::string json = R"({
        "configVersion": "3.0", "serial": "LKG-P0000", "pitch": {"value": 52.59267044067383},
        "slope": {"value": -7.083540916442871}, "center": {"value": 0.8167931437492371},
        "viewCone": {"value": 40.0}, "invView": {"value": 1.0}, "verticalAngle": {"value": 0.0},
        "DPI": {"value": 324.0}, "screenW": {"value": 1536.0}, "screenH": {"value": 2048.0},
        "flipImageX": {"value": 0.0}, "flipImageY": {"value": 0.0}, "flipSubp": {"value": 0.0}
    })";
    Result<LenticularCalibration> cal = parseLookingGlassCalibration(json, "visual.json");
    ASSERT_TRUE(cal) << cal.status().message();
    EXPECT_DOUBLE_EQ(cal->pitch, 52.59267044067383);
    EXPECT_DOUBLE_EQ(cal->slope, -7.083540916442871);
    EXPECT_DOUBLE_EQ(cal->center, 0.8167931437492371);
    EXPECT_DOUBLE_EQ(cal->dpi, 324.0);
    EXPECT_EQ(cal->screenWidth, 1536);
    EXPECT_EQ(cal->screenHeight, 2048);
    EXPECT_TRUE(cal->invertViews);
    EXPECT_FALSE(cal->flipX);
    EXPECT_FALSE(cal->bgr);
    EXPECT_DOUBLE_EQ(cal->viewCone, 40.0);
    // Plain numbers work too; optional keys may be missing.
    Result<LenticularCalibration> plain = parseLookingGlassCalibration(
        R"({"pitch": 40, "slope": 5.5, "center": 0.1, "DPI": 300, "flipSubp": true})", "x");
    ASSERT_TRUE(plain) << plain.status().message();
    EXPECT_EQ(plain->screenWidth, 0);
    EXPECT_TRUE(plain->bgr);
    EXPECT_EQ(plain->viewCone, 0.0);  // absent
    // A viewCone outside (0, 180) degrees is an input error naming it.
    Result<LenticularCalibration> wide = parseLookingGlassCalibration(
        R"({"pitch": 40, "slope": 5.5, "center": 0.1, "DPI": 300, "viewCone": 200})", "w.json");
    ASSERT_FALSE(wide);
    EXPECT_EQ(wide.status().code(), ErrorCode::Input);
    EXPECT_NE(wide.status().message().find("w.json: calibration viewCone = 200"), std::string::npos)
        << wide.status().message();
}

TEST(Lenticular, CalibrationErrorsNameTheKey) {
    Result<LenticularCalibration> missing = parseLookingGlassCalibration(
        R"({"pitch": {"value": 40}, "slope": 5, "DPI": 300})", "v.json");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.status().code(), ErrorCode::Input);
    EXPECT_EQ(missing.status().message(),
              "v.json: calibration key \"center\" missing (expected a Looking Glass visual.json "
              "with pitch, slope, center and DPI)");
    Result<LenticularCalibration> notNumber = parseLookingGlassCalibration(
        R"({"pitch": {"value": "wide"}, "slope": 5, "center": 0, "DPI": 300})", "v.json");
    ASSERT_FALSE(notNumber);
    EXPECT_EQ(notNumber.status().message(), "v.json: calibration key \"pitch\" is not a number");
    EXPECT_FALSE(
        parseLookingGlassCalibration(R"({"pitch": 1, "slope": 0, "center": 0, "DPI": 300})", "v"));
    EXPECT_FALSE(parseLookingGlassCalibration(
        R"({"pitch": 1, "slope": 2, "center": 0, "DPI": 3, "screenW": 10.5})", "v"));
    const std::string valid =
        R"({"pitch": {"value": 40}, "slope": {"value": 5}, "center": {"value": 0.1}, "DPI": {"value": 300}})";
    for (std::size_t n = 0; n < valid.size(); ++n)  // every prefix: an error, no crash
        EXPECT_FALSE(parseLookingGlassCalibration(valid.substr(0, n), "cut")) << n;
    EXPECT_EQ(readLookingGlassCalibration("/nonexistent/visual.json").status().code(),
              ErrorCode::Input);
}

TEST(Lenticular, RejectsBadCalibration) {
    LenticularCalibration cal;
    cal.dpi = 0;
    Result<Image> out = lenticular(taggedViews(2, 4, 4), cal);
    ASSERT_FALSE(out);
    EXPECT_EQ(out.status().code(), ErrorCode::Usage);
    EXPECT_EQ(out.status().message(), "mvr::composite::lenticular(): dpi 0 (must be > 0 and at most 10000)");
    cal = {};
    cal.slope = 0;
    EXPECT_FALSE(lenticular(taggedViews(2, 4, 4), cal));
    cal = {};
    cal.pitch = std::nan("");
    EXPECT_FALSE(lenticular(taggedViews(2, 4, 4), cal));
    EXPECT_FALSE(lenticular(taggedViews(1, 4, 4), LenticularCalibration{}));
}

}  // namespace
}  // namespace mvr::composite

namespace mvr::composite {
namespace {

// lenticularView() takes its floors without libm below 2^52: the views of every sub-pixel of
// three panels — a Portrait's lenses, a phase that makes z negative, and lenses so fine and
// slanted that z passes 2^52 (std::floor's own path) — against lenticular.h's formula written
// out here with std::floor.
TEST(Lenticular, ViewsFollowTheFormulaWithStdFloor) {
    LenticularCalibration portrait;
    portrait.pitch = 52.59267044067383, portrait.slope = -7.083540916442871;
    portrait.center = 0.8167931437492371, portrait.dpi = 324.0, portrait.invertViews = true;
    LenticularCalibration negative = portrait;
    negative.center = 917.25, negative.invertViews = false;
    LenticularCalibration huge = portrait;
    huge.pitch = 9000.0, huge.dpi = 1.0e-12, huge.slope = 1.0e-6;  // z ~ 5e17
    for (const LenticularCalibration& cal : {portrait, negative, huge}) {
        const int sw = 97, sh = 61, n = 45;
        auto p = lenticularShaderParams(cal, sw, sh);
        ASSERT_TRUE(p) << p.status().message();
        std::set<int> seen;
        for (int py = 0; py < sh; ++py) {
            for (int px = 0; px < sw; ++px) {
                for (int i = 0; i < 3; ++i) {
                    const double u = (px + 0.5) / sw, v = 1.0 - (py + 0.5) / sh;
                    double z = (u + i * p->subp + v * p->tilt) * p->pitchU - p->center;
                    z -= std::floor(z);
                    if (p->invertViews) z = 1.0 - z;
                    const int want = std::clamp(int(std::floor(z * n)), 0, n - 1);
                    ASSERT_EQ(lenticularView(*p, n, sw, sh, px, py, i), want)
                        << "pitch " << cal.pitch << " at " << px << "," << py << " sub-pixel " << i;
                    seen.insert(want);
                }
            }
        }
        // lenticular() (lenticularRow(): the vectorized floors below 2^50, else these) takes
        // every sub-pixel from that view: views of one colour each, (v, 2v, 3v).
        std::vector<Image> views;
        for (int v = 0; v < n; ++v)
            views.push_back(solid(5, 3, {std::uint8_t(v), std::uint8_t(2 * v),
                                         std::uint8_t(3 * v), 255}));
        LenticularCalibration sized = cal;
        sized.screenWidth = sw, sized.screenHeight = sh;
        auto panel = lenticular(views, sized);
        ASSERT_TRUE(panel) << panel.status().message();
        for (int py = 0; py < sh; ++py) {
            for (int px = 0; px < sw; ++px) {
                const Rgba8 c = panel->at(px, py);
                ASSERT_EQ(c.r, lenticularView(*p, n, sw, sh, px, py, 0)) << px << "," << py;
                ASSERT_EQ(c.g, 2 * lenticularView(*p, n, sw, sh, px, py, 1)) << px << "," << py;
                ASSERT_EQ(c.b, 3 * lenticularView(*p, n, sw, sh, px, py, 2)) << px << "," << py;
            }
        }
        // The panel shows most views, not one; past 2^52 no fraction is left (one view).
        if (cal.pitch != huge.pitch) EXPECT_GT(seen.size(), 20u);
    }
}

}  // namespace
}  // namespace mvr::composite
