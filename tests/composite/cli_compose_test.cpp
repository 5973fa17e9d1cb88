// `mvr compose` end to end: runs the built binary (${MVR_BINARY_DIR}/tools/cli/mvr).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include <sys/wait.h>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "mvr/composite/jpeg.h"
#include "mvr/io/png.h"
#include "test_views.h"
#include "mvr_test_support.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

using ::mvr::test::CliRun;

class ComposeCli : public ::testing::Test {
protected:
    void SetUp() override {
        mvr = ::mvr::test::mvrBinary();
        if (!std::filesystem::exists(mvr)) FAIL() << mvr << " not built";
        dir = freshDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
        ASSERT_TRUE(writePng(dir / "left.png", taggedView(0, 8, 6)));
        ASSERT_TRUE(writePng(dir / "right.png", taggedView(1, 8, 6)));
    }
    void TearDown() override {
        if (!dir.empty()) std::filesystem::remove_all(dir);
    }
    CliRun run(const std::string& args) const {
        return ::mvr::test::runShell("cd '" + dir.string() + "' && '" + mvr.string() +
                                     "' compose " + args);
    }
    Image readOne(const std::filesystem::path& p) const {
        Result<std::vector<Image>> views = readViewFile(p);
        EXPECT_TRUE(views) << views.status().message();
        return views && !views->empty() ? (*views)[0] : Image();
    }
    std::filesystem::path mvr, dir;
};

TEST_F(ComposeCli, DefaultIsTheDuboisAnaglyphInTheDirectory) {
    const CliRun r = run("left.png right.png -o out -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output, "");
    const std::vector<Image> views = {taggedView(0, 8, 6), taggedView(1, 8, 6)};
    EXPECT_EQ(readOne(dir / "out" / "anaglyph-dubois.png"), *compose("anaglyph-dubois", views));
}

TEST_F(ComposeCli, FilePathOutputAndOptions) {
    CliRun r = run("left.png right.png -f sbs --cross-eyed -o pair.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("pair.png"), std::string::npos) << r.output;
    const Image sbs = readOne(dir / "pair.png");
    ASSERT_EQ(sbs.width, 16);
    EXPECT_EQ(sbs.at(0, 0), tag(1, 0, 0));  // cross-eyed: right view first
    r = run("left.png right.png left.png right.png -f quilt --quilt 2x2 -o q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(std::filesystem::exists(dir / "q" / "quilt_qs2x2a1.3333.png"));
}

TEST_F(ComposeCli, FormatFollowsAnMpoOrJpsFileName) {
    CliRun r = run("left.png right.png -o pair.mpo -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    Result<std::vector<Image>> mpo = readViewFile(dir / "pair.mpo");
    ASSERT_TRUE(mpo) << mpo.status().message();
    EXPECT_EQ(mpo->size(), 2u);
    r = run("left.png right.png -o pair.jps -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readViewFile(dir / "pair.jps")->size(), 2u);
    r = run("left.png right.png -f sbs -o pair2.mpo");  // an explicit format must fit the name
    EXPECT_EQ(r.exitCode, 1) << r.output;
}

TEST_F(ComposeCli, MpoAndJpsInputsAreSplitIntoViews) {
    CliRun r = run("left.png right.png -f mpo -o out --baseline 0.065 --convergence 2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("out/mpo.mpo -f jps -o out");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("out/jps.jps -f columns -o cols.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image cols = readOne(dir / "cols.png");
    ASSERT_EQ(cols.width, 8);
    // Column 0 from the left view, column 1 from the right, after two JPEG generations.
    EXPECT_LE(std::abs(cols.at(0, 2).b - tag(0, 0, 2).b), 12);
    EXPECT_LE(std::abs(cols.at(1, 2).b - tag(1, 1, 2).b), 12);
}

// `mvr compose view-*.png`: the shell gives view-0, view-1, view-10, view-11, view-2, ...; the
// views are taken by their numbers (the quilt equals the one of the numeric order, and a note
// says so); an order that is not the text order (reversed) is the caller's, kept.
TEST_F(ComposeCli, AShellGlobOfNumberedViewsIsTakenInNumericOrder) {
    std::vector<std::string> names;
    for (int v = 0; v < 12; ++v) {
        names.push_back(fmt::format("view-{}.png", v));
        ASSERT_TRUE(writePng(dir / names.back(), taggedView(v, 8, 6)));
    }
    auto joined = [](const std::vector<std::string>& list) {
        std::string s;
        for (const std::string& n : list) s += n + " ";
        return s;
    };
    std::vector<std::string> glob = names;
    std::sort(glob.begin(), glob.end());  // as the shell sorts: view-10.png before view-2.png
    ASSERT_NE(glob, names);
    CliRun numeric = run(joined(names) + "-f quilt --quilt 4x3 -o numeric.png");
    ASSERT_EQ(numeric.exitCode, 0) << numeric.output;
    EXPECT_EQ(numeric.output.find("note:"), std::string::npos) << numeric.output;
    CliRun globbed = run(joined(glob) + "-f quilt --quilt 4x3 -o glob.png");
    ASSERT_EQ(globbed.exitCode, 0) << globbed.output;
    EXPECT_NE(globbed.output.find("note: the views are taken in the order of their numbers "
                                  "(view-0.png before view-1.png)"),
              std::string::npos)
        << globbed.output;
    EXPECT_EQ(readOne(dir / "glob.png").rgba, readOne(dir / "numeric.png").rgba);
    std::vector<std::string> reversed(names.rbegin(), names.rend());
    CliRun kept = run(joined(reversed) + "-f quilt --quilt 4x3 -o reversed.png");
    ASSERT_EQ(kept.exitCode, 0) << kept.output;
    EXPECT_NE(readOne(dir / "reversed.png").rgba, readOne(dir / "numeric.png").rgba);
}

TEST_F(ComposeCli, ViewsOfDifferentSizesAreAnInputError) {
    ASSERT_TRUE(writePng(dir / "small.png", taggedView(1, 4, 6)));
    const CliRun r = run("left.png small.png -o out");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output,
              "error: views differ in size: small.png is 4x6 but left.png is 8x6 (expected all "
              "views of one size)\n");
}

TEST_F(ComposeCli, WrongNumberOfViewsIsAUsageError) {
    const CliRun r = run("left.png right.png left.png -f sbs -o out");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(r.output, "error: --format sbs: 3 views given (expected exactly 2 views)\n");
}

TEST_F(ComposeCli, MissingAndTruncatedInputsAreInputErrors) {
    CliRun r = run("left.png nope.png -o out");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output, "error: nope.png: file not found\n");
    Result<std::vector<std::uint8_t>> png = readFileBytes(dir / "right.png");
    ASSERT_TRUE(png);
    ASSERT_TRUE(writeFileBytes(dir / "cut.png", std::span(png->data(), png->size() / 2)));
    r = run("left.png cut.png -o out");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    Result<std::vector<std::uint8_t>> jpeg = encodeJpeg(taggedView(1, 8, 6), 90);
    ASSERT_TRUE(jpeg);
    ASSERT_TRUE(writeFileBytes(dir / "cut.jpg", std::span(jpeg->data(), jpeg->size() - 20)));
    r = run("left.png cut.jpg -o out");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output.rfind("error: cut.jpg: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
    std::ofstream(dir / "garbage.png") << "garbage";
    r = run("left.png garbage.png -o out");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output, "error: garbage.png: not a PNG or JPEG file (unrecognised signature)\n");
}

TEST_F(ComposeCli, UnknownFormatAndBadOptionsAreUsageErrors) {
    CliRun r = run("left.png right.png -f bogus -o out");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(r.output.rfind("error: --format: bogus not in {", 0), 0u) << r.output;
    r = run("left.png right.png -f quilt --quilt 0x3 -o out");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("expected CxR"), std::string::npos) << r.output;
    r = run("left.png right.png -f hdmi-frame-packing -o out");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("expected 1280x720 or 1920x1080"), std::string::npos) << r.output;
    r = run("left.png right.png -f mpo -o out.png");
    EXPECT_EQ(r.exitCode, 1) << r.output;
}

TEST_F(ComposeCli, UnwritableOutputIsAnOutputError) {
    std::ofstream(dir / "file") << "x";
    CliRun r = run("left.png right.png -o file/sub");
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_EQ(r.output.rfind("error: cannot create output directory 'file/sub'", 0), 0u)
        << r.output;
}

TEST_F(ComposeCli, LenticularCalibrationFileAndOverrides) {
    std::ofstream(dir / "visual.json")
        << R"({"pitch": {"value": 4}, "slope": {"value": 1e12}, "center": {"value": 0},)"
        << R"( "DPI": {"value": 12}, "screenW": {"value": 12}, "screenH": {"value": 2}})";
    std::vector<std::string> names;
    for (int v = 0; v < 9; ++v) {
        names.push_back(fmt::format("v{}.png", v));
        ASSERT_TRUE(writePng(dir / names.back(), solid(12, 2,
                                                       {std::uint8_t(10 + v), std::uint8_t(100 + v),
                                                        std::uint8_t(200 + v), 255})));
    }
    std::string list;
    for (const std::string& n : names) list += n + " ";
    CliRun r = run(list + "-f lenticular --lenticular-calibration visual.json -o lent.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image out = readOne(dir / "lent.png");
    ASSERT_EQ(out.width, 12);
    for (int x = 0; x < 12; ++x) EXPECT_EQ(out.at(x, 0).r, 10 + (3 * x + 1) % 9) << x;
    // A single value given with the file overrides it, whatever the order on the command line.
    r = run("--lenticular-invert-views " + list +
            "-f lenticular --lenticular-calibration visual.json -o inv.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Image inv = readOne(dir / "inv.png");
    for (int x = 0; x < 12; ++x) EXPECT_EQ(inv.at(x, 0).r, 10 + 8 - (3 * x + 1) % 9) << x;
    r = run(list + "-f lenticular --lenticular-calibration missing.json -o x.png");
    EXPECT_EQ(r.exitCode, 2) << r.output;  // the file's fault (docs/errors.md)
    EXPECT_NE(r.output.find("missing.json: file not found"), std::string::npos) << r.output;
}

TEST_F(ComposeCli, HelpListsTheFormats) {
    const CliRun r = run("--help");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    for (const std::string& f : formatNames()) EXPECT_NE(r.output.find(f), std::string::npos) << f;
}

}  // namespace
}  // namespace mvr::composite
