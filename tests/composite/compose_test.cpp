#include "mvr/composite/compose.h"

#include <fstream>

#include <gtest/gtest.h>

#include "mvr/composite/jpeg.h"
#include "mvr/io/png.h"
#include "test_views.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

constexpr int kJpegTolerance = 8;
const ComposeOptions kNoOptions;

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

// The size rules of the formats table against what compose() makes: for every format, view
// count and size (odd, even, HDMI, tiny), outputSize() gives compose()'s size, or refuses with
// compose()'s code and the text after its caller's name.
TEST(Compose, OutputSizeIsComposesSize) {
    ComposeOptions grid, badGrid, panel, badPanel;
    grid.quiltColumns = 3;
    grid.quiltRows = 2;
    badGrid.quiltColumns = 3;
    panel.lenticular.screenWidth = 23;
    panel.lenticular.screenHeight = 19;
    badPanel.lenticular.slope = 0;
    const std::vector<std::pair<int, int>> sizes = {{1, 1}, {7, 5}, {8, 6}, {1280, 720}};
    int compared = 0;
    for (const FormatInfo& f : formats()) {
        if (f.fileOnly) continue;
        for (int n : {1, 2, 3, 7}) {
            for (const auto& [w, h] : sizes) {
                // 1280x720 (an HDMI size) only where it is the rule, to stay quick.
                if (w == 1280 && (f.size.rule != SizeRule::FramePacked || n != 2)) continue;
                const std::vector<Image> views = taggedViews(n, w, h);
                for (const ComposeOptions* o : std::initializer_list<const ComposeOptions*>{
                         &kNoOptions, &grid, &badGrid, &panel, &badPanel}) {
                    Result<Image> image = compose(f.name, views, *o);
                    Result<Size> size = outputSize(f.name, n, w, h, *o);
                    ++compared;
                    ASSERT_EQ(bool(image), bool(size))
                        << f.name << " " << n << "x" << w << "x" << h << ": "
                        << (image ? size.status().message() : image.status().message());
                    if (image) {
                        EXPECT_EQ(*size, (Size{image->width, image->height})) << f.name;
                        continue;
                    }
                    EXPECT_EQ(size.status().code(), image.status().code()) << f.name;
                    std::string tail = image.status().message();
                    tail = tail.substr(tail.find("): ") + 3);
                    if (tail.rfind(std::string(f.name) + ": ", 0) == 0)
                        tail = tail.substr(f.name.size() + 2);
                    EXPECT_NE(size.status().message().find(tail), std::string::npos)
                        << "outputSize: " << size.status().message()
                        << "\ncompose: " << image.status().message();
                }
            }
        }
    }
    EXPECT_GT(compared, 300);
    Result<Size> mpo = outputSize("mpo", 3, 4, 5);
    ASSERT_TRUE(mpo) << mpo.status().message();
    EXPECT_EQ(*mpo, (Size{4, 5}));
    EXPECT_FALSE(outputSize("anaglyph-purple", 2, 4, 4));
    Result<Size> zero = outputSize("sbs", 2, 0, 4);
    ASSERT_FALSE(zero);
    EXPECT_EQ(zero.status().message(),
              "mvr::composite::outputSize(): sbs: view size 0x4 (expected at least 1x1)");
}

// largestViewSize(): the largest views whose output fits the frame (and one pixel more across
// or down does not fit, for the tiled formats).
TEST(Compose, LargestViewSizeFitsTheFrame) {
    const auto view = [](std::string_view f, int n, int w, int h, const ComposeOptions& o = {}) {
        Result<Size> s = largestViewSize(f, n, w, h, o);
        EXPECT_TRUE(s) << f << ": " << s.status().message();
        return s ? *s : Size{};
    };
    EXPECT_EQ(view("anaglyph-dubois", 2, 961, 541), (Size{961, 541}));
    EXPECT_EQ(view("sbs", 2, 961, 541), (Size{480, 541}));
    EXPECT_EQ(view("sbs-half", 2, 961, 541), (Size{960, 541}));
    EXPECT_EQ(view("tb", 2, 961, 541), (Size{961, 270}));
    EXPECT_EQ(view("tb-half", 2, 961, 541), (Size{961, 540}));
    EXPECT_EQ(view("rows", 5, 31, 17), (Size{31, 17}));
    EXPECT_EQ(view("jps", 2, 31, 17), (Size{15, 17}));
    EXPECT_EQ(view("hdmi-frame-packing", 2, 1920, 2205), (Size{1920, 1080}));
    EXPECT_EQ(view("hdmi-frame-packing", 2, 1919, 2205), (Size{1280, 720}));
    ComposeOptions grid;
    grid.quiltColumns = 4;
    grid.quiltRows = 2;
    EXPECT_EQ(view("quilt", 8, 400, 301, grid), (Size{100, 150}));
    ComposeOptions panel;
    panel.lenticular.screenWidth = 30;
    panel.lenticular.screenHeight = 20;
    EXPECT_EQ(view("lenticular", 3, 64, 48, panel), (Size{30, 20}));
    EXPECT_EQ(view("lenticular", 3, 64, 48), (Size{64, 48}));
    for (const FormatInfo& f : formats()) {
        if (f.size.rule != SizeRule::Tiled) continue;
        for (const auto& [fw, fh] : {std::pair{2, 2}, std::pair{7, 9}, std::pair{960, 541}}) {
            const Size v = view(f.name, 2, fw, fh);
            Result<Size> out = outputSize(f.name, 2, v.width, v.height);
            ASSERT_TRUE(out) << f.name << ": " << out.status().message();
            EXPECT_LE(out->width, fw) << f.name;
            EXPECT_LE(out->height, fh) << f.name;
            Result<Size> wider = outputSize(f.name, 2, v.width + f.size.squeezeX, v.height);
            EXPECT_TRUE(!wider || wider->width > fw) << f.name;
            Result<Size> taller = outputSize(f.name, 2, v.width, v.height + f.size.squeezeY);
            EXPECT_TRUE(!taller || taller->height > fh) << f.name;
        }
    }
    // The automatic quilt grid: the views' own grid, i.e. compose() of them fits the frame.
    for (int n : {2, 5, 8, 45}) {
        const Size v = view("quilt", n, 1000, 700);
        const auto [c, r] = chooseQuiltLayout(n, v.width, v.height);
        EXPECT_LE(c * v.width, 1000) << n;
        EXPECT_LE(r * v.height, 700) << n;
    }
    Result<Size> small = largestViewSize("sbs", 2, 1, 100);
    ASSERT_FALSE(small);
    EXPECT_EQ(small.status().code(), ErrorCode::Usage);
    EXPECT_NE(small.status().message().find("a frame of 1x100 is too small"), std::string::npos)
        << small.status().message();
    EXPECT_FALSE(largestViewSize("hdmi-frame-packing", 2, 1280, 1469));
    EXPECT_FALSE(largestViewSize("sbs", 3, 100, 100));
}

}  // namespace
}  // namespace mvr::composite
