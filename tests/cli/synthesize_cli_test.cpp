// `mvr render --synthesize K` end to end (mvr/core/synthesize.h, issue 43 item 2): the
// refusals with their messages, the files written (every view; the exact ones the plain
// render's), and --check's report of each warped view against its exact render.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"
#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

class SynthesizeCli : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-synthesize-test-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    test::CliRun run(const std::string& args) const { return test::runMvr(mDir, args); }

    void expectError(const std::string& args, const std::string& line) const {
        const test::CliRun r = run(args);
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;
        EXPECT_EQ(r.err, "error: " + line + "\n") << args;
    }

    Image view(const std::string& dir, int v) const {
        auto im = readPng(mDir / dir / fmt::format("view-{}.png", v));
        EXPECT_TRUE(im) << im.status().message();
        return im ? *im : Image();
    }

    std::filesystem::path mDir;
};

TEST_F(SynthesizeCli, Refusals) {
    expectError("render --views 9 --synthesize 0 -o out",
                "--synthesize 0 is out of range (expected 1..64; 1: every view exact)");
    expectError("render --views 9 --synthesize 65 -o out",
                "--synthesize 65 is out of range (expected 1..64; 1: every view exact)");
    expectError("render --views 2 --synthesize 4 -o out",
                "--synthesize 4: needs rows of at least 3 views (the rig has 2 views in 1 row)");
    expectError("render --views 9 --rig toein --synthesize 4 -o out",
                "--synthesize 4: needs an off-axis rig (the warp is the horizontal shear between "
                "its views; --rig toein has none)");
    expectError("render --views 9 --rig parallel --synthesize 2 -o out",
                "--synthesize 2: needs an off-axis rig (the warp is the horizontal shear between "
                "its views; --rig parallel has none)");
    EXPECT_FALSE(std::filesystem::exists(mDir / "out"));
}

constexpr const char* kRender = "render --views 9 --size 160x120 -q";

TEST_F(SynthesizeCli, EveryViewIsWrittenAndTheExactOnesAreThePlainRenders) {
    ASSERT_EQ(run(std::string(kRender) + " -o plain").exitCode, 0);
    const test::CliRun r = run("render --views 9 --size 160x120 --synthesize 4 -o warped");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("soft:unified (--synthesize 4: 3 exact, 6 warped) in "), std::string::npos)
        << r.out;
    for (int v = 0; v < 9; ++v) {
        ASSERT_TRUE(std::filesystem::exists(mDir / "warped" / fmt::format("view-{}.png", v)));
        if (v % 4 == 0) {
            EXPECT_TRUE(view("warped", v) == view("plain", v)) << "exact view " << v;
        }
    }
    // A warped view is not a copy of its neighbour: the default scene has parallax.
    EXPECT_FALSE(view("warped", 1) == view("warped", 0));
    EXPECT_FALSE(std::filesystem::exists(mDir / "warped/depth-1.png"))
        << "the depth the warp needs is internal";
}

// A sequence synthesizes every frame's views: frame 1 of an orbit differs from frame 0, and its
// exact views are the plain sequence's.
TEST_F(SynthesizeCli, ASequenceSynthesizesEveryFrame) {
    const std::string seq = std::string(kRender) + " --frames 2 --orbit 20";
    ASSERT_EQ(run(seq + " -o plain").exitCode, 0);
    const test::CliRun r = run(seq + " --synthesize 4 -o warped");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (int v = 0; v < 9; ++v) {
        const Image w = view("warped/frame-0001", v), p = view("plain/frame-0001", v);
        if (v % 4 == 0) {
            EXPECT_TRUE(w == p) << "exact view " << v;
        } else {
            EXPECT_EQ(w.width, 160);
            EXPECT_FALSE(w == view("warped/frame-0000", v)) << "view " << v << " did not move";
        }
    }
}

TEST_F(SynthesizeCli, CheckReportsEveryWarpedViewAgainstItsExactRender) {
    const test::CliRun r = run(std::string(kRender) + " --synthesize 4 --check -o out");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    int lines = 0;
    for (int v : {1, 2, 3, 5, 6, 7}) {
        const std::regex line(fmt::format(
            R"(check: view {} \(warped\): PSNR ([0-9.]+) dB against the exact view; ([0-9.]+) % of the pixels differ by more than 2/255 \([0-9]+ of 19200\))",
            v));
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.out, m, line)) << "view " << v << "\n" << r.out;
        EXPECT_GT(std::stod(m[1]), 20.0) << "view " << v;
        EXPECT_LT(std::stod(m[2]), 20.0) << "view " << v;
        ++lines;
    }
    EXPECT_EQ(lines, 6);
    for (int v : {0, 4, 8})
        EXPECT_EQ(r.out.find(fmt::format("check: view {} ", v)), std::string::npos)
            << "exact view " << v << " reported";
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        r.out, m,
        std::regex(R"(check: --synthesize 4: 6 of 9 views warped; lowest PSNR ([0-9.]+) dB, at most ([0-9.]+) % of a view's pixels more than 2/255 off)")))
        << r.out;
}

}  // namespace
}  // namespace mvr
