// Issue 44, "all or nothing": bad input gets exactly one `error:` line naming the culprit and a
// non-zero exit, never a hang nor a half-written output directory.
//  - Only regular files are read: a FIFO blocks its reader, /dev/zero and /dev/urandom never
//    end. Each `mvr` run here is wrapped in `timeout 20`, so a regression fails (exit 124)
//    instead of hanging the test run.
//  - Every --format is checked against the views and their size before anything is rendered:
//    the -o directory is left exactly as it was (not even created).
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"

namespace mvr {
namespace {

using test::CliRun;

class AllOrNothing : public ::testing::Test {
protected:
    void SetUp() override {
        MVR_REQUIRE_MVR_BINARY(test::mvrBinary());
        std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        std::replace(name.begin(), name.end(), '/', '_');
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-all-or-nothing-{}-{}", ::getpid(), name);
        std::filesystem::remove_all(mDir);
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    /// `mvr ARGS` in the test's directory, killed after 20 s (exit 124) should it hang.
    CliRun run(const std::string& args) const { return test::runMvr(mDir, args, "timeout 20 "); }

    /// Exit `code` (any non-zero one when 0), and on stderr one error line, "error: ...", holding
    /// every one of `needles` (and nothing else but a usage hint).
    static void expectOneError(const CliRun& r, const std::string& args, int code,
                               std::initializer_list<std::string> needles) {
        EXPECT_NE(r.exitCode, 124) << args << ": timed out (a hang)";
        if (code != 0) {
            EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        } else {
            EXPECT_NE(r.exitCode, 0) << args << "\n" << r.err;
        }
        EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
        // The error, and for an option's value CLI11 refuses, the usage hint after it.
        const std::string rest = r.err.substr(std::min(r.err.size(), r.err.find('\n') + 1));
        EXPECT_TRUE(rest.empty() || rest.rfind("run `mvr --help`", 0) == 0)
            << args << ": " << r.err;
        EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << args << ": " << r.err;
        for (const std::string& needle : needles)
            EXPECT_NE(r.err.find(needle), std::string::npos)
                << args << ": no '" << needle << "' in: " << r.err;
    }

    void mkfifo(const std::string& name) const {
        ASSERT_EQ(::mkfifo((mDir / name).c_str(), 0600), 0) << name;
    }
    void symlink(const std::string& target, const std::string& name) const {
        std::filesystem::create_symlink(target, mDir / name);
    }
    void write(const std::string& name, const std::string& bytes) const {
        std::ofstream(mDir / name, std::ios::binary) << bytes;
    }
    /// The names in a directory of the test's (empty when there is none).
    std::set<std::string> listing(const std::string& name) const {
        std::set<std::string> names;
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator(mDir / name, ec))
            names.insert(e.path().filename().string());
        return names;
    }

    /// A one-triangle glTF 2.0 whose one buffer is the external file `bin`.
    void writeGltf(const std::string& name, const std::string& bin) const {
        write(name, fmt::format(R"({{
  "asset": {{"version": "2.0"}},
  "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "buffers": [{{"uri": "{}", "byteLength": 36}}]
}})",
                                bin));
    }

    std::filesystem::path mDir;
};

// ---- A: only regular files are read -------------------------------------------------------------

TEST_F(AllOrNothing, ComposeRefusesAFifoInput) {
    mkfifo("fifo.png");
    const std::string args = "compose fifo.png fifo.png -o out.png";
    const CliRun r = run(args);
    expectOneError(r, args, 0, {"fifo.png", "not a regular file"});
    EXPECT_FALSE(std::filesystem::exists(mDir / "out.png"));
}

TEST_F(AllOrNothing, ComposeRefusesDevicesBehindSymlinks) {
    symlink("/dev/zero", "z.png");
    symlink("/dev/urandom", "u.jpg");
    symlink("/dev/zero", "z.mpo");
    for (const std::string args : {"compose z.png z.png -o out.png",
                                   "compose u.jpg u.jpg -o out.png", "compose z.mpo -o out.png"}) {
        const CliRun r = run(args);
        const std::string culprit = args.substr(8, args.find(' ', 8) - 8);
        expectOneError(r, args, 0, {culprit, "not a regular file"});
        EXPECT_FALSE(std::filesystem::exists(mDir / "out.png")) << args;
    }
}

TEST_F(AllOrNothing, ComposeRefusesADirectoryInput) {
    std::filesystem::create_directories(mDir / "views.png");
    const std::string args = "compose views.png views.png -o out.png";
    expectOneError(run(args), args, 0, {"views.png", "not a regular file"});
}

TEST_F(AllOrNothing, GltfBufferThatIsAFifoOrADeviceIsRefused) {
    mkfifo("fifo.bin");
    writeGltf("fifo.gltf", "fifo.bin");
    symlink("/dev/zero", "zero.bin");
    writeGltf("zero.gltf", "zero.bin");
    for (const std::string model : {"fifo", "zero"}) {
        const std::string args = fmt::format("render {}.gltf --size 16x12 -o out", model);
        const CliRun r = run(args);
        expectOneError(r, args, 2, {model + ".bin", "not a regular file"});
        EXPECT_FALSE(std::filesystem::exists(mDir / "out")) << args;
    }
}

TEST_F(AllOrNothing, OtherInputFilesThatAreFifosAreRefused) {
    mkfifo("fifo");
    symlink("/dev/zero", "zero.json");
    struct Case {
        std::string option, file;
    };
    const Case cases[] = {
        {"--sky fifo", "fifo"},
        {"--camera-path fifo", "fifo"},
        {"--camera-path zero.json", "zero.json"},
        {"--camera-matrix fifo", "fifo"},
        {"--lenticular-calibration fifo --format lenticular", "fifo"},
        {"--lenticular-calibration zero.json --format lenticular", "zero.json"},
    };
    for (const Case& c : cases) {
        std::filesystem::remove_all(mDir / "out");
        const std::string args = "render --size 16x12 -o out " + c.option;
        expectOneError(run(args), args, 0, {c.file, "not a regular file"});
        EXPECT_FALSE(std::filesystem::exists(mDir / "out")) << args;
    }
}

// ---- B: formats are checked before anything is written ------------------------------------------

TEST_F(AllOrNothing, AFormatTheViewsCannotMakeWritesNothing) {
    struct Case {
        std::string args, format, why;
    };
    const Case cases[] = {
        {"--size 64x48 --views 4 --format jps", "jps", "needs 2 views (got 4)"},
        {"--size 64x48 --views 4 --format sbs", "sbs", "needs 2 views (got 4)"},
        {"--size 64x48 --views 4 --format anaglyph-dubois", "anaglyph-dubois",
         "needs 2 views (got 4)"},
        {"--size 64x48 --views 4 --format anaglyph-dubois-gm", "anaglyph-dubois-gm",
         "needs 2 views (got 4)"},
        {"--size 64x48 --format hdmi-frame-packing", "hdmi-frame-packing",
         "no HDMI 1.4a frame packing"},
        {"--size 63x48 --format sbs-half", "sbs-half", "odd"},
        {"--size 64x48 --views 4 --format sbs --frames 1", "sbs", "needs 2 views (got 4)"},
        {"--size 64x48 --views 1 --format mpo", "mpo", "views (got 1)"},
    };
    for (const Case& c : cases) {
        for (const bool existed : {false, true}) {
            std::filesystem::remove_all(mDir / "o");
            if (existed) {
                std::filesystem::create_directories(mDir / "o");
                write("o/keep.txt", "kept");
            }
            const std::string args = "render " + c.args + " -o o";
            const CliRun r = run(args);
            expectOneError(r, args, 1, {"--format " + c.format, c.why});
            if (existed) {
                EXPECT_EQ(listing("o"), std::set<std::string>{"keep.txt"}) << args;
                EXPECT_EQ(test::slurp(mDir / "o" / "keep.txt"), "kept") << args;
            } else {
                EXPECT_FALSE(std::filesystem::exists(mDir / "o")) << args;
            }
        }
    }
}

}  // namespace
}  // namespace mvr
