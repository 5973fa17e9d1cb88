// `mvr render --backend gl --format …` end to end: every image composite it writes (composed
// on the GPU by mvr::gl::composeGpu()) has the CPU's file name and equals
// composite::compose() of the view PNGs it wrote beside it — exactly, anaglyphs within 1/255.
// jps / mpo are still written (by the CPU). Skips when the gl backend has no context here.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/gl/composite_gpu.h"
#include "mvr/io/png.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

std::filesystem::path mvrBinary() {
    return ::mvr::test::mvrBinary();
}

int maxDelta(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return 256;
    int m = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        m = std::max(m, std::abs(int(a.rgba[i]) - int(b.rgba[i])));
    return m;
}

class RenderGpuComposites : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-gl-composite-test-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    // Renders `views` views with every format of `formats` (+ `extra` options); checks each file.
    void check(int views, const std::vector<std::string>& formats, const std::string& extra,
               const composite::ComposeOptions& options) {
        // Is there a GL context at all? (A 1-pixel GPU composite says so without the CLI.)
        const std::vector<Image> probe(2, Image(1, 1));
        Result<Image> g = composeGpu("sbs", probe, {});
        if (!g && g.status().code() == ErrorCode::Unsupported) MVR_SKIP(MethodUnsupportedByDriver) << g.status().message();
        std::string args = fmt::format(
            "render --backend gl --method multipass --size 42x30 "
            "--views {} -q -o '{}' {}",
            views, mDir.string(), extra);
        for (const std::string& f : formats) args += " --format " + f;
        const std::string cmd = fmt::format("'{}' {} 2>'{}'", mvrBinary().string(), args,
                                            (mDir / "stderr.txt").string());
        const int status = std::system(cmd.c_str());
        ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;

        std::vector<Image> rendered;
        for (int v = 0; v < views; ++v) {
            Result<Image> img = readPng(mDir / fmt::format("view-{}.png", v));
            ASSERT_TRUE(img) << img.status().message();
            rendered.push_back(std::move(*img));
        }
        std::vector<std::string> all = formats;
        if (views == 2) all.push_back("anaglyph.png");
        for (const std::string& f : all) {
            const bool stereoDefault = f == "anaglyph.png";
            const std::string format = stereoDefault ? "anaglyph-dubois" : f;
            Result<std::string> name = composite::compositeFileName(format, rendered, options);
            ASSERT_TRUE(name) << name.status().message();
            const std::filesystem::path path = mDir / (stereoDefault ? f : *name);
            ASSERT_TRUE(std::filesystem::exists(path)) << path;
            if (!composeGpuSupports(format)) continue;  // jps / mpo: CPU files, only present
            Result<Image> written = readPng(path);
            ASSERT_TRUE(written) << written.status().message();
            Result<Image> cpu = composite::compose(format, rendered, options);
            ASSERT_TRUE(cpu) << cpu.status().message();
            const int tolerance = format.rfind("anaglyph-", 0) == 0 ? 1 : 0;
            EXPECT_LE(maxDelta(*written, *cpu), tolerance) << path;
        }
    }

    std::filesystem::path mDir;
};

// --synthesize renders a sub-rig of exact views: a method's refusal of it names the option.
TEST_F(RenderGpuComposites, ASynthesizedRigRefusedByAMethodNamesTheOption) {
    const std::vector<Image> probe(2, Image(1, 1));
    Result<Image> g = composeGpu("sbs", probe, {});
    if (!g && g.status().code() == ErrorCode::Unsupported) MVR_SKIP(MethodUnsupportedByDriver) << g.status().message();
    const ::mvr::test::CliRun r = ::mvr::test::runMvr(
        mDir, "render --backend gl --method gs-mrt --views 9 --size 42x30 --synthesize 4 -q -o out");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.err,
              "error: --synthesize 4: the 3 exact views: gl: gs-mrt renders exactly 2 views "
              "(sorbier2008's stereo pair: one MRT attachment per eye); the rig has 3\n");
    EXPECT_FALSE(std::filesystem::exists(mDir / "out"));
}

TEST_F(RenderGpuComposites, StereoFormatsMatchTheCpuComposites) {
    check(2,
          {"anaglyph-color", "anaglyph-gray", "anaglyph-dubois-ab", "sbs", "sbs-half", "tb",
           "tb-half", "rows", "columns", "checkerboard", "quilt", "lenticular", "jps", "mpo"},
          "", {});
}

TEST_F(RenderGpuComposites, SwapEyesAndCrossEyedAsTheCpu) {
    composite::ComposeOptions o;
    o.swapEyes = true;
    o.crossEyed = true;
    check(2, {"sbs", "sbs-half", "checkerboard", "anaglyph-true"}, "--swap-eyes --cross-eyed", o);
}

TEST_F(RenderGpuComposites, MultiViewFormatsMatchTheCpuComposites) {
    composite::ComposeOptions o;
    o.quiltColumns = 3;
    o.quiltRows = 2;
    o.lenticular.bgr = true;
    o.lenticular.flipY = true;
    check(5, {"rows", "columns", "quilt", "lenticular"},
          "--quilt 3x2 --lenticular-bgr --lenticular-flip-y", o);
}

}  // namespace
}  // namespace mvr::gl::test
