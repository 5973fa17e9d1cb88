// `mvr render --aa N` end to end (the resolve itself: tests/raster/antialias_test.cpp): the
// light-field presets take 4 samples unless told, plain renders 1, and nonsense is one line.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"
#include "mvr/core/image.h"
#include "mvr/io/png.h"

namespace mvr {
namespace {

class AntialiasCli : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-aa-cli-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(mDir);
        std::ofstream(mDir / "pyramid.obj")
            << "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv 0 1.5 0\n"
               "f 1 2 3\nf 1 3 4\nf 1 5 2\nf 2 5 3\nf 3 5 4\nf 4 5 1\n";
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }
    test::CliRun run(const std::string& args) const { return test::runMvr(mDir, args); }
    Image png(const std::string& path) const {
        auto image = readPng(mDir / path);
        EXPECT_TRUE(image) << path;
        return image ? *image : Image{};
    }
    std::filesystem::path mDir;
};

/// Pixels whose value is neither the background's nor the pyramid's most common ones: the
/// blended edge pixels.
int between(const Image& img) {
    const Rgba8 corner = img.at(0, 0);
    int n = 0;
    for (int y = 1; y + 1 < img.height; ++y) {
        for (int x = 1; x + 1 < img.width; ++x) {
            const Rgba8 p = img.at(x, y);
            n += p != corner && (img.at(x - 1, y) == corner || img.at(x + 1, y) == corner ||
                                 img.at(x, y - 1) == corner || img.at(x, y + 1) == corner);
        }
    }
    return n;
}

TEST_F(AntialiasCli, PresetsSampleFourTimesPlainRendersOnce) {
    const std::string common = "render pyramid.obj --shading flat -q ";
    ASSERT_EQ(run(common + "--size 64x48 --views 2 -o one").exitCode, 0);
    ASSERT_EQ(run(common + "--size 64x48 --views 2 --aa 4 -o four").exitCode, 0);
    const Image one = png("one/view-0.png"), four = png("four/view-0.png");
    EXPECT_NE(one, four);
    EXPECT_EQ(one.width, 64);
    EXPECT_GT(between(four), between(one));  // edges blend into the background
    // The Portrait preset: 4 unless --aa says otherwise.
    const std::string portrait = common + "--display portrait --size 42x56 --write views ";
    ASSERT_EQ(run(portrait + "-o preset").exitCode, 0);
    ASSERT_EQ(run(portrait + "--aa 4 -o p4").exitCode, 0);
    ASSERT_EQ(run(portrait + "--aa 1 -o p1").exitCode, 0);
    EXPECT_EQ(png("preset/view-20.png"), png("p4/view-20.png"));
    EXPECT_NE(png("preset/view-20.png"), png("p1/view-20.png"));
}

TEST_F(AntialiasCli, NonsenseIsOneErrorLine) {
    for (const auto& [args, needle] :
         {std::pair{"--aa 3", "error: --aa 3: expected 1, 2, 4 or 8 samples a pixel"},
          std::pair{"--aa 0", "error: --aa 0: expected 1, 2, 4 or 8 samples a pixel"}}) {
        const test::CliRun r = run(std::string("render pyramid.obj --size 32x24 -q -o out ") + args);
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;
        EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(mDir / "out")) << args;
    }
}

}  // namespace
}  // namespace mvr
