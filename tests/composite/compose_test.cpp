#include "mvr/composite/compose.h"

#include <fstream>

#include <gtest/gtest.h>

#include "mvr/composite/jpeg.h"
#include "test_views.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

constexpr int kJpegTolerance = 8;

TEST(Compose, FormatList) {
    const std::vector<std::string> names = formatNames();
    for (const char* f : {"anaglyph-color", "anaglyph-half-color", "anaglyph-gray", "anaglyph-true",
                          "anaglyph-dubois", "anaglyph-dubois-gm", "anaglyph-dubois-ab", "sbs",
                          "sbs-half", "tb", "tb-half", "rows", "columns", "checkerboard",
                          "hdmi-frame-packing", "quilt", "lenticular", "mpo", "jps"})
        EXPECT_NE(std::find(names.begin(), names.end(), f), names.end()) << f;
    EXPECT_EQ(names.size(), formats().size());
    EXPECT_EQ(names.front(), kDefaultAnaglyph);
    EXPECT_NE(formatHelp().find("hdmi-frame-packing"), std::string::npos);
}

TEST(Compose, UnknownFormatIsAUsageError) {
    Result<Image> out = compose("anaglyph-purple", taggedViews(2, 2, 2));
    ASSERT_FALSE(out);
    EXPECT_EQ(out.status().code(), ErrorCode::Usage);
    EXPECT_EQ(
        out.status().message().rfind("unknown output format 'anaglyph-purple' (expected one of: "
                                     "anaglyph-dubois, ",
                                     0),
        0u)
        << out.status().message();
}

TEST(Compose, EveryImageFormatComposesItsTestViews) {
    for (const FormatInfo& f : formats()) {
        if (f.fileOnly) continue;
        const int n = f.name == "quilt" ? 5 : f.name == "hdmi-frame-packing" ? 2 : f.minViews;
        const auto views =
            f.name == "hdmi-frame-packing" ? taggedViews(2, 1280, 720) : taggedViews(n, 8, 6);
        Result<Image> out = compose(f.name, views);
        EXPECT_TRUE(out) << f.name << ": " << out.status().message();
    }
    Result<Image> mpo = compose("mpo", taggedViews(2, 4, 4));
    ASSERT_FALSE(mpo);
    EXPECT_EQ(mpo.status().code(), ErrorCode::Unsupported);
}

TEST(Compose, FileNames) {
    const auto two = taggedViews(2, 4, 3);
    EXPECT_EQ(*compositeFileName("anaglyph-dubois", two), "anaglyph-dubois.png");
    EXPECT_EQ(*compositeFileName("sbs-half", two), "sbs-half.png");
    EXPECT_EQ(*compositeFileName("jps", two), "jps.jps");
    EXPECT_EQ(*compositeFileName("mpo", two), "mpo.mpo");
    EXPECT_EQ(*compositeFileName("quilt", taggedViews(48, 3, 4)), "quilt_qs8x6a0.75.png");
    EXPECT_FALSE(compositeFileName("sbs", taggedViews(3, 4, 3)));
}

TEST(Compose, WriteCompositeWritesEveryFormatIntoTheDirectory) {
    const auto dir = freshDir("write_all");
    for (const FormatInfo& f : formats()) {
        const auto views = f.name == "hdmi-frame-packing"
                               ? taggedViews(2, 1280, 720)
                               : taggedViews(f.minViews == 1 ? 3 : f.minViews, 8, 6);
        Result<std::filesystem::path> path = writeComposite(f.name, views, {}, dir);
        ASSERT_TRUE(path) << f.name << ": " << path.status().message();
        EXPECT_EQ(path->parent_path(), dir);
        EXPECT_TRUE(std::filesystem::is_regular_file(*path)) << *path;
        Result<std::vector<Image>> back = readViewFile(*path);
        ASSERT_TRUE(back) << back.status().message();
        if (f.name == "mpo" || f.name == "jps") {
            ASSERT_EQ(back->size(), 2u) << f.name;
            continue;
        }
        ASSERT_EQ(back->size(), 1u);
        Result<Image> expected = compose(f.name, views);
        ASSERT_TRUE(expected);
        EXPECT_EQ((*back)[0].width, expected->width);
        EXPECT_EQ(maxRgbDelta((*back)[0], *expected), 0) << f.name;  // PNG: lossless
    }
    std::filesystem::remove_all(dir);
}

TEST(Compose, WriteCompositeFileFollowsTheExtension) {
    const auto dir = freshDir("extension");
    const std::vector<Image> views = {smoothView(16, 8, 0), smoothView(16, 8, 3)};
    ASSERT_TRUE(writeCompositeFile("sbs", views, {}, dir / "pair.jpg"));
    Result<std::vector<Image>> jpg = readViewFile(dir / "pair.jpg");
    ASSERT_TRUE(jpg);
    EXPECT_LE(maxRgbDelta((*jpg)[0], *compose("sbs", views)), kJpegTolerance);
    Status wrong = writeCompositeFile("mpo", views, {}, dir / "pair.png");
    ASSERT_FALSE(wrong);
    EXPECT_EQ(wrong.code(), ErrorCode::Usage);
    EXPECT_FALSE(writeCompositeFile("sbs", views, {}, dir / "pair.tiff"));
    Status unwritable = writeCompositeFile("sbs", views, {}, dir / "missing" / "pair.png");
    ASSERT_FALSE(unwritable);
    EXPECT_EQ(unwritable.code(), ErrorCode::Output);
    std::filesystem::remove_all(dir);
}

TEST(Compose, ReadViewFileSplitsMpoAndJps) {
    const auto dir = freshDir("read_views");
    const std::vector<Image> views = {smoothView(16, 8, 0), smoothView(16, 8, 3)};
    ASSERT_TRUE(writeComposite("mpo", views, {}, dir));
    ASSERT_TRUE(writeComposite("jps", views, {}, dir));
    for (const char* file : {"mpo.mpo", "jps.jps"}) {
        Result<std::vector<Image>> back = readViewFile(dir / file);
        ASSERT_TRUE(back) << back.status().message();
        ASSERT_EQ(back->size(), 2u);
        EXPECT_LE(maxRgbDelta((*back)[0], views[0]), kJpegTolerance) << file;  // left first
        EXPECT_LE(maxRgbDelta((*back)[1], views[1]), kJpegTolerance) << file;
    }
    ASSERT_TRUE(writePng(dir / "a.png", views[0]));
    Result<std::vector<Image>> png = readViewFile(dir / "a.png");
    ASSERT_TRUE(png);
    EXPECT_EQ((*png)[0], views[0]);
    std::filesystem::remove_all(dir);
}

TEST(Compose, ReadViewFileErrors) {
    const auto dir = freshDir("read_errors");
    Result<std::vector<Image>> missing = readViewFile(dir / "nope.png");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.status().code(), ErrorCode::Input);
    EXPECT_EQ(missing.status().message(), (dir / "nope.png").string() + ": file not found");
    std::ofstream(dir / "text.png") << "not an image";
    Result<std::vector<Image>> text = readViewFile(dir / "text.png");
    ASSERT_FALSE(text);
    EXPECT_EQ(text.status().code(), ErrorCode::Input);
    EXPECT_EQ(text.status().message(),
              (dir / "text.png").string() + ": not a PNG or JPEG file (unrecognised signature)");
    std::ofstream(dir / "empty.jpg");
    EXPECT_EQ(readViewFile(dir / "empty.jpg").status().code(), ErrorCode::Input);
    // A truncated JPEG is an error, never a gray-filled picture.
    Result<std::vector<std::uint8_t>> jpeg = encodeJpeg(smoothView(16, 16, 0), 90);
    ASSERT_TRUE(jpeg);
    ASSERT_TRUE(writeFileBytes(dir / "cut.jpg", std::span(jpeg->data(), jpeg->size() - 10)));
    Result<std::vector<Image>> cut = readViewFile(dir / "cut.jpg");
    ASSERT_FALSE(cut);
    EXPECT_EQ(cut.status().code(), ErrorCode::Input);
    EXPECT_NE(cut.status().message().find("truncated"), std::string::npos)
        << cut.status().message();
    std::filesystem::remove_all(dir);
}

TEST(Compose, QuiltGridParsingAndConvergenceAngle) {
    EXPECT_EQ(*parseQuiltGrid("8x6"), (std::pair{8, 6}));
    EXPECT_EQ(*parseQuiltGrid("5X9"), (std::pair{5, 9}));
    for (const char* bad : {"", "8", "8x", "x6", "0x6", "8x-1", "8x6x2", "8x6 ", "axb", "300x2"})
        EXPECT_FALSE(parseQuiltGrid(bad)) << bad;
    EXPECT_NEAR(convergenceAngleDegrees(0.065, 2.0), 1.8619, 1e-4);
    EXPECT_EQ(convergenceAngleDegrees(0.065, 0.0), 0.0);
    ComposeOptions half;
    half.quiltColumns = 3;  // rows missing
    EXPECT_FALSE(compose("quilt", taggedViews(3, 2, 2), half));
}

}  // namespace
}  // namespace mvr::composite
