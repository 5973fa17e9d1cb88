#include "mvr/composite/layout.h"

#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "test_views.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

constexpr Rgba8 kBlack{0, 0, 0, 255};

Image composeOk(const char* format, const std::vector<Image>& views, const ComposeOptions& o = {}) {
    Result<Image> out = compose(format, views, o);
    EXPECT_TRUE(out) << format << ": " << out.status().message();
    return out ? std::move(*out) : Image();
}

// Squeezed pixel of view v at output column x (2:1 average, rounding half up).
Rgba8 squeezedX(int v, int x, int y) {
    const Rgba8 a = tag(v, 2 * x, y), b = tag(v, 2 * x + 1, y);
    return {std::uint8_t((a.r + b.r + 1) / 2), std::uint8_t((a.g + b.g + 1) / 2),
            std::uint8_t((a.b + b.b + 1) / 2), std::uint8_t((a.a + b.a + 1) / 2)};
}
Rgba8 squeezedY(int v, int x, int y) {
    const Rgba8 a = tag(v, x, 2 * y), b = tag(v, x, 2 * y + 1);
    return {std::uint8_t((a.r + b.r + 1) / 2), std::uint8_t((a.g + b.g + 1) / 2),
            std::uint8_t((a.b + b.b + 1) / 2), std::uint8_t((a.a + b.a + 1) / 2)};
}

TEST(Layout, SideBySideFull) {
    const auto views = taggedViews(2, 5, 3);
    const Image out = composeOk("sbs", views);
    ASSERT_EQ(out.width, 10);
    ASSERT_EQ(out.height, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 10; ++x)
            EXPECT_EQ(out.at(x, y), tag(x < 5 ? 0 : 1, x % 5, y)) << x << "," << y;
}

TEST(Layout, SideBySideCrossEyedAndSwapEyes) {
    const auto views = taggedViews(2, 4, 2);
    ComposeOptions cross;
    cross.crossEyed = true;
    const Image out = composeOk("sbs", views, cross);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_EQ(out.at(x, y), tag(x < 4 ? 1 : 0, x % 4, y));
    ComposeOptions swap;
    swap.swapEyes = true;
    EXPECT_EQ(composeOk("sbs", views, swap), out);
    ComposeOptions both = cross;
    both.swapEyes = true;  // the two cancel
    EXPECT_EQ(composeOk("sbs", views, both), composeOk("sbs", views));
}

TEST(Layout, SideBySideHalf) {
    const auto views = taggedViews(2, 6, 3);
    const Image out = composeOk("sbs-half", views);
    ASSERT_EQ(out.width, 6);
    ASSERT_EQ(out.height, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 6; ++x)
            EXPECT_EQ(out.at(x, y), squeezedX(x < 3 ? 0 : 1, x % 3, y)) << x;
    ComposeOptions cross;
    cross.crossEyed = true;
    const Image crossed = composeOk("sbs-half", views, cross);
    for (int x = 0; x < 6; ++x) EXPECT_EQ(crossed.at(x, 1), squeezedX(x < 3 ? 1 : 0, x % 3, 1));
}

TEST(Layout, SideBySideHalfRejectsOddWidth) {
    Result<Image> out = compose("sbs-half", taggedViews(2, 5, 2));
    ASSERT_FALSE(out);
    EXPECT_EQ(out.status().code(), ErrorCode::Usage);
    EXPECT_NE(out.status().message().find("view width 5 is odd"), std::string::npos)
        << out.status().message();
}

TEST(Layout, TopBottomFullAndHalf) {
    const auto views = taggedViews(2, 3, 4);
    const Image full = composeOk("tb", views);
    ASSERT_EQ(full.width, 3);
    ASSERT_EQ(full.height, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 3; ++x) EXPECT_EQ(full.at(x, y), tag(y < 4 ? 0 : 1, x, y % 4));
    const Image half = composeOk("tb-half", views);
    ASSERT_EQ(half.width, 3);
    ASSERT_EQ(half.height, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 3; ++x) EXPECT_EQ(half.at(x, y), squeezedY(y < 2 ? 0 : 1, x, y % 2));
    ComposeOptions swap;
    swap.swapEyes = true;
    EXPECT_EQ(composeOk("tb", views, swap).at(0, 0), tag(1, 0, 0));
    EXPECT_FALSE(compose("tb-half", taggedViews(2, 3, 3)));
}

TEST(Layout, RowInterleave) {
    const Image out = composeOk("rows", taggedViews(2, 4, 5));
    ASSERT_EQ(out.width, 4);
    ASSERT_EQ(out.height, 5);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_EQ(out.at(x, y), tag(y % 2, x, y));  // top row: left
    const Image three = composeOk("rows", taggedViews(3, 2, 7));
    for (int y = 0; y < 7; ++y) EXPECT_EQ(three.at(1, y), tag(y % 3, 1, y));
}

TEST(Layout, ColumnInterleaveIsKalaiahTwoViewBarrier) {
    // kalaiah2007 §5: odd columns (1-based) from the left image, even columns from the right.
    const Image out = composeOk("columns", taggedViews(2, 6, 3));
    ASSERT_EQ(out.width, 6);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 6; ++x) {
            const int column1Based = x + 1;
            EXPECT_EQ(out.at(x, y), tag(column1Based % 2 == 1 ? 0 : 1, x, y));
        }
    const Image four = composeOk("columns", taggedViews(4, 9, 2));
    for (int x = 0; x < 9; ++x) EXPECT_EQ(four.at(x, 1), tag(x % 4, x, 1));
    ComposeOptions swap;
    swap.swapEyes = true;  // N views: order reversed
    const Image reversed = composeOk("columns", taggedViews(4, 9, 2), swap);
    for (int x = 0; x < 9; ++x) EXPECT_EQ(reversed.at(x, 1), tag(3 - x % 4, x, 1));
}

TEST(Layout, Checkerboard) {
    const Image out = composeOk("checkerboard", taggedViews(2, 5, 4));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) EXPECT_EQ(out.at(x, y), tag((x + y) % 2, x, y));
}

void checkHdmi(int w, int h, int gap) {
    std::vector<Image> views = {solid(w, h, {255, 0, 0, 255}), solid(w, h, {0, 0, 255, 255})};
    views[0].set(7, 0, {1, 2, 3, 255});  // markers at known places
    views[1].set(w - 1, h - 1, {4, 5, 6, 255});
    const Image out = composeOk("hdmi-frame-packing", views);
    ASSERT_EQ(out.width, w);
    ASSERT_EQ(out.height, 2 * h + gap);
    for (int y = 0; y < out.height; ++y) {
        const Rgba8 want = y < h         ? Rgba8{255, 0, 0, 255}
                           : y < h + gap ? kBlack
                                         : Rgba8{0, 0, 255, 255};
        for (int x = 0; x < w; x += 97) ASSERT_EQ(out.at(x, y), want) << x << "," << y;
        ASSERT_EQ(out.at(w - 2, y), want) << y;
    }
    EXPECT_EQ(out.at(7, 0), (Rgba8{1, 2, 3, 255}));
    EXPECT_EQ(out.at(w - 1, out.height - 1), (Rgba8{4, 5, 6, 255}));
}

TEST(Layout, HdmiFramePacking720p) { checkHdmi(1280, 720, 30); }
TEST(Layout, HdmiFramePacking1080p) { checkHdmi(1920, 1080, 45); }

TEST(Layout, HdmiFramePackingRejectsOtherSizes) {
    Result<Image> out = compose("hdmi-frame-packing", taggedViews(2, 64, 48));
    ASSERT_FALSE(out);
    EXPECT_EQ(out.status().code(), ErrorCode::Usage);
    EXPECT_EQ(out.status().message(),
              "mvr::composite::hdmiFramePacking(): view size 64x48 has no HDMI 1.4a frame packing "
              "(expected 1280x720 or 1920x1080)");
    EXPECT_EQ(hdmiActiveSpaceLines(1280, 720), 30);
    EXPECT_EQ(hdmiActiveSpaceLines(1920, 1080), 45);
    EXPECT_EQ(hdmiActiveSpaceLines(1920, 720), -1);
}

// Every pixel of a quilt: view i in tile (i mod C, row ⌊i/C⌋ from the bottom), black beyond N.
void checkQuilt(const Image& q, int n, int columns, int rows, int w, int h) {
    ASSERT_EQ(q.width, columns * w);
    ASSERT_EQ(q.height, rows * h);
    for (int y = 0; y < q.height; ++y)
        for (int x = 0; x < q.width; ++x) {
            const int tileX = x / w, tileRowFromTop = y / h;
            const int view = (rows - 1 - tileRowFromTop) * columns + tileX;
            const Rgba8 want = view < n ? tag(view, x % w, y % h) : kBlack;
            ASSERT_EQ(q.at(x, y), want) << "pixel " << x << "," << y << " view " << view;
        }
}

TEST(Layout, QuiltOf45ViewsLookingGlassDefault5x9) {
    // 45 views of 1.8:1 → the Looking Glass 5x9 quilt, view 0 bottom left, view 44 top right.
    const auto views = taggedViews(45, 9, 5);
    EXPECT_EQ(chooseQuiltLayout(45, 9, 5), (std::pair{5, 9}));
    const Image q = composeOk("quilt", views);
    checkQuilt(q, 45, 5, 9, 9, 5);
    EXPECT_EQ(q.at(0, q.height - 1), tag(0, 0, 4));  // bottom left: view 0
    EXPECT_EQ(q.at(q.width - 1, 0), tag(44, 8, 0));  // top right: view 44
    Result<std::string> name = compositeFileName("quilt", views);
    ASSERT_TRUE(name);
    EXPECT_EQ(*name, "quilt_qs5x9a1.8.png");
}

TEST(Layout, QuiltOf45ViewsOnAnExplicit8x6Grid) {
    const auto views = taggedViews(45, 3, 4);
    ComposeOptions o;
    o.quiltColumns = 8;
    o.quiltRows = 6;
    const Image q = composeOk("quilt", views, o);
    checkQuilt(q, 45, 8, 6, 3, 4);  // 3 black tiles at the top right
    Result<std::string> name = compositeFileName("quilt", views, o);
    ASSERT_TRUE(name);
    EXPECT_EQ(*name, "quilt_qs8x6a0.75.png");
}

TEST(Layout, QuiltSwapEyesReversesViews) {
    ComposeOptions o;
    o.quiltColumns = 2;
    o.quiltRows = 2;
    o.swapEyes = true;
    const Image q = composeOk("quilt", taggedViews(4, 2, 2), o);
    EXPECT_EQ(q.at(0, 2), tag(3, 0, 0));  // bottom left now shows the last view
}

TEST(Layout, QuiltRejectsTooSmallGrid) {
    ComposeOptions o;
    o.quiltColumns = 4;
    o.quiltRows = 2;
    Result<Image> out = compose("quilt", taggedViews(9, 2, 2), o);
    ASSERT_FALSE(out);
    EXPECT_EQ(out.status().message(),
              "mvr::composite::quilt(): grid 4x2 has 8 tiles for 9 views (expected at least one "
              "tile per view)");
    o.quiltRows = 0;
    EXPECT_FALSE(compose("quilt", taggedViews(4, 2, 2), o));
}

TEST(Layout, QuiltLayoutChoice) {
    EXPECT_EQ(chooseQuiltLayout(48, 3, 4), (std::pair{8, 6}));  // Looking Glass Portrait
    EXPECT_EQ(chooseQuiltLayout(45, 16, 9), (std::pair{5, 9}));
    EXPECT_EQ(chooseQuiltLayout(1, 10, 10), (std::pair{1, 1}));
    EXPECT_EQ(chooseQuiltLayout(4, 10, 10), (std::pair{2, 2}));
    EXPECT_EQ(chooseQuiltLayout(2, 10, 10), (std::pair{2, 1}));  // tie → fewer blank tiles
    EXPECT_EQ(formatAspect(3, 4), "0.75");
    EXPECT_EQ(formatAspect(4, 4), "1");
    EXPECT_EQ(formatAspect(16, 9), "1.7778");
    EXPECT_EQ(formatAspect(9, 5), "1.8");
}

TEST(Layout, ViewCountAndSizeErrors) {
    Result<Image> three = compose("sbs", taggedViews(3, 2, 2));
    ASSERT_FALSE(three);
    EXPECT_EQ(three.status().code(), ErrorCode::Usage);
    EXPECT_EQ(three.status().message(), "mvr::composite::compose(): sbs: needs 2 views (got 3)");
    Result<Image> one = compose("columns", taggedViews(1, 2, 2));
    ASSERT_FALSE(one);
    EXPECT_EQ(one.status().message(),
              "mvr::composite::compose(): columns: needs at least 2 views (got 1)");
    std::vector<Image> mixed = taggedViews(3, 4, 4);
    mixed[2] = taggedView(2, 4, 5);
    Result<Image> sizes = compose("rows", mixed);
    ASSERT_FALSE(sizes);
    EXPECT_EQ(sizes.status().message(),
              "mvr::composite::compose(): rows: views differ in size: view 0 is 4x4, view 2 is 4x5 "
              "(expected one size)");
    std::vector<Image> empty(2);
    EXPECT_FALSE(compose("checkerboard", empty));
}

}  // namespace
}  // namespace mvr::composite
