// Issue 44, item 2: output sets appear whole or not at all. A still's files (and its comfort
// report), a sequence's frame folder, a video and a composite are written under temporary
// names and moved into place when complete; whatever stops the run — a full disk, a file over
// `ulimit -f`, SIGINT or SIGTERM mid-write — leaves the -o directory byte for byte as it was
// (a sequence: its complete frames, and a message saying how to render the rest).
//
// Processes are run through runShell (a bash line: the run in the background, a poll for the
// moment to stop it, `kill`, and its exit status), each under `timeout`.
#include <sys/mount.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"

namespace mvr {
namespace {

namespace fs = std::filesystem;
using test::CliRun;

/// Every file under `root` (relative name → bytes); directories as "name/" → "".
std::map<std::string, std::string> snapshot(const fs::path& root) {
    std::map<std::string, std::string> files;
    std::error_code ec;
    if (!fs::exists(root, ec)) return files;
    for (auto it = fs::recursive_directory_iterator(root, ec); it != fs::end(it);
         it.increment(ec)) {
        const std::string name = fs::relative(it->path(), root).string();
        if (it->is_directory()) {
            files[name + "/"] = "";
        } else {
            files[name] = test::slurp(it->path());
        }
    }
    return files;
}

std::string names(const std::map<std::string, std::string>& files) {
    std::string s;
    for (const auto& [name, bytes] : files) s += " " + name;
    return s.empty() ? " (none)" : s;
}

class WholeSets : public ::testing::Test {
protected:
    void SetUp() override {
        MVR_REQUIRE_MVR_BINARY(test::mvrBinary());
        std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        mDir = fs::temp_directory_path() / fmt::format("mvr-whole-sets-{}-{}", ::getpid(), name);
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override {
        if (mMounted) ::umount2((mDir / "disk").c_str(), MNT_DETACH);
        fs::remove_all(mDir);
    }

    /// `mvr ARGS` in the test's directory under `prefix` (a bash line before the binary).
    CliRun run(const std::string& args, const std::string& prefix = "") const {
        return test::runShell(fmt::format("cd '{}' && {} timeout 60 '{}' {}", mDir.string(), prefix,
                                          test::mvrBinary().string(), args));
    }

    /// `mvr ARGS` in the background, stopped with `signal` as soon as `ready` (a path under the
    /// test's directory, a glob) exists: its exit status on the last line ("rc=N"), stderr
    /// before it.
    CliRun stopWhen(const std::string& args, const std::string& ready, const std::string& signal) {
        const std::string script = fmt::format(
            "cd '{}' && {{ timeout 120 '{}' {} 2>err.txt >/dev/null & p=$!; "
            "for i in $(seq 1 20000); do ls -d {} >/dev/null 2>&1 && break; "
            "kill -0 $p 2>/dev/null || break; sleep 0.002; done; "
            "kill -{} $p; wait $p; echo \"rc=$?\"; cat err.txt; rm -f err.txt; }}",
            mDir.string(), test::mvrBinary().string(), args, ready, signal);
        CliRun r = test::runShell(script);
        std::smatch m;
        if (std::regex_search(r.output, m, std::regex("rc=(\\d+)"))) r.exitCode = std::stoi(m[1]);
        return r;
    }

    /// A tmpfs of `kib` KiB at disk/ (false where this machine does not let the test mount one).
    bool mountSmallDisk(int kib) {
        fs::create_directories(mDir / "disk");
        const std::string options = fmt::format("size={}k", kib);
        if (::mount("tmpfs", (mDir / "disk").c_str(), "tmpfs", 0, options.c_str()) != 0)
            return false;
        mMounted = true;
        return true;
    }

    void write(const fs::path& name, const std::string& bytes) const {
        fs::create_directories((mDir / name).parent_path());
        std::ofstream(mDir / name, std::ios::binary) << bytes;
    }

    fs::path mDir;
    bool mMounted = false;
};

/// One error line, the exit code, and `needle` in it.
void expectError(const CliRun& r, int code, const std::string& needle) {
    EXPECT_EQ(r.exitCode, code) << r.output;
    EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << "no '" << needle << "' in: " << r.output;
}

// ---- a write that fails midway ------------------------------------------------------------------

TEST_F(WholeSets, AFileOverTheSizeLimitLeavesTheDirectoryAsItWas) {
    // `ulimit -f 24`: no file over 24 KiB; the views of 256x192 are smaller, the quilt is not.
    write("out/view-0.png", "an older render");
    write("out/notes.txt", "the user's");
    const auto before = snapshot(mDir / "out");
    const CliRun r = run("render --views 8 --size 256x192 --format quilt -o out "
                         "--report-json report.json",
                         "ulimit -f 24 &&");
    expectError(r, 4, "File too large");
    EXPECT_EQ(snapshot(mDir / "out"), before) << "now:" << names(snapshot(mDir / "out"));
    EXPECT_FALSE(fs::exists(mDir / "report.json")) << "the report is part of the set";

    // Into a folder that was not there: not even the folder is left.
    const CliRun fresh = run("render --views 8 --size 256x192 --format quilt -o new/out",
                             "ulimit -f 24 &&");
    expectError(fresh, 4, "File too large");
    EXPECT_FALSE(fs::exists(mDir / "new")) << names(snapshot(mDir));
}

TEST_F(WholeSets, AFullDiskLeavesTheDirectoryAsItWas) {
    if (!mountSmallDisk(160)) MVR_SKIP(NotApplicable) << "this machine does not let the test mount a tmpfs";
    write("disk/out/view-0.png", "an older render");
    const auto before = snapshot(mDir / "disk");
    // 16 views of 320x240 with depth: several times 160 KiB.
    const CliRun r = run("render --views 16 --size 320x240 --write views,depth -o disk/out");
    expectError(r, 4, "disk/out");
    EXPECT_EQ(snapshot(mDir / "disk"), before) << "now:" << names(snapshot(mDir / "disk"));

    // A sequence on the same disk: the frames that fit stay, whole, and the message counts them.
    const CliRun seq = run("render --frames 40 --views 2 --size 96x64 -o disk/seq");
    ASSERT_NE(seq.exitCode, 0) << seq.output;
    std::smatch m;
    const std::string& text = seq.output;
    ASSERT_TRUE(std::regex_search(text, m, std::regex("(\\d+) of 40 frames are complete in disk/seq/ "
                                                      "\\(`--frame-range (\\d+):` renders the rest\\)")))
        << text;
    const int done = std::stoi(m[1]);
    EXPECT_EQ(std::stoi(m[2]), done);
    const auto frames = snapshot(mDir / "disk" / "seq");
    int folders = 0;
    for (const auto& [name, bytes] : frames) {
        EXPECT_EQ(name.find(".part"), std::string::npos) << name;
        EXPECT_EQ(name.find(".mvr-part"), std::string::npos) << name;
        if (name.back() == '/') ++folders;
    }
    EXPECT_EQ(folders, done) << names(frames);
    for (int f = 0; f < done; ++f) {
        for (const char* file : {"view-0.png", "view-1.png", "anaglyph.png"})
            EXPECT_TRUE(frames.count(fmt::format("frame-{:04}/{}", f, file))) << f << file;
    }
}

TEST_F(WholeSets, AWriteFailingBesideTheRenderingKeepsTheFramesBeforeIt) {
    // Frames written on their own thread while the next renders (issue 37): a camera path that
    // zooms in makes each frame's PNGs larger than the last, so that under `ulimit -f` a later
    // frame's write fails while the following frames render. The output and the message are
    // those of the run that writes one frame at a time (MVR_WRITE_QUEUE=0).
    write("zoom.json", R"({"keys": [{"time": 0, "position": [0, 0, 60], "target": [0, 0, 0]},
                                     {"time": 1, "position": [0, 0, 2.5], "target": [0, 0, 0]}]})");
    std::map<std::string, std::string> outputs;
    std::string messages;
    for (const char* queue : {"0", "1", "3"}) {
        const std::string dir = fmt::format("seq{}", queue);
        const CliRun r = run(fmt::format("render --views 2 --size 256x192 --camera-path zoom.json "
                                         "--fps 8 -q -o {}",
                                         dir),
                             fmt::format("ulimit -f 8 && MVR_WRITE_QUEUE={}", queue));
        expectError(r, 4, "File too large");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.output, m,
                                      std::regex("(\\d+) of 9 frames are complete in seq\\d/ "
                                                 "\\(`--frame-range (\\d+):` renders the rest\\)")))
            << r.output;
        const int done = std::stoi(m[1]);
        EXPECT_GE(done, 1) << r.output;
        EXPECT_EQ(std::stoi(m[2]), done);
        std::size_t lines = 0;
        for (std::size_t at = 0; (at = r.output.find("error:", at)) != std::string::npos; ++at)
            ++lines;
        EXPECT_EQ(lines, 1u) << r.output;
        const auto frames = snapshot(mDir / dir);
        int folders = 0;
        for (const auto& [name, bytes] : frames) {
            EXPECT_EQ(name.find("part"), std::string::npos) << "left: " << name;
            folders += name.back() == '/';
        }
        EXPECT_EQ(folders, done) << names(frames);
        if (outputs.empty()) {
            outputs = frames;
            messages = std::regex_replace(r.output, std::regex("seq\\d"), "seq");
        } else {
            EXPECT_EQ(frames, outputs) << "MVR_WRITE_QUEUE=" << queue << ": " << names(frames);
            EXPECT_EQ(std::regex_replace(r.output, std::regex("seq\\d"), "seq"), messages);
        }
    }
}

TEST_F(WholeSets, AVideoThatCannotBeFinishedIsRemovedAndTheFramesSaid) {
    // Matroska holds its clusters until the end: the file limit shows when the video's frames
    // are flushed (the video's thread). One error line, the frames that are complete, no video.
    const CliRun r = run("render --frames 12 --views 2 --size 128x96 --format sbs --codec ffv1 "
                         "--write composites,video --video v.mkv -q -o seq",
                         "ulimit -f 100 &&");
    if (r.output.find("built without FFmpeg") != std::string::npos)
        MVR_SKIP(FeatureNotBuilt) << "video (FFmpeg)";
    expectError(r, 4, "--video v.mkv: File too large; every frame is complete in seq/; the "
                      "unfinished video was removed");
    EXPECT_EQ(r.output.find("error:"), r.output.rfind("error:")) << r.output;
    EXPECT_FALSE(fs::exists(mDir / "v.mkv"));
    EXPECT_FALSE(fs::exists(mDir / "v.part.mkv"));
}

TEST_F(WholeSets, TheReportIsPartOfTheSet) {
    // The report cannot be written (a directory is in its place): refused before rendering.
    fs::create_directories(mDir / "report.json");
    const CliRun r = run("render --views 2 --size 32x24 -o out --report-json report.json");
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("report.json"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(mDir / "out")) << names(snapshot(mDir));
    // Under a file, or with a sequence (whose frames have no one report): refused up front.
    write("file", "x");
    const CliRun under = run("render --views 2 --size 32x24 -o out --report-json file/r.json");
    expectError(under, 4, "--report-json file/r.json: 'file' is not a directory");
    const CliRun seq = run("render --views 2 --size 32x24 --frames 2 -o out --report-json r.json");
    expectError(seq, 1, "--report-json r.json: the comfort report is a still's");
    EXPECT_FALSE(fs::exists(mDir / "out")) << names(snapshot(mDir));
    // Where it can, the report and the images are all there, under their own names.
    fs::create_directories(mDir / "r");
    const CliRun ok = run("render --views 2 --size 32x24 -o out --report-json r/report.json");
    ASSERT_EQ(ok.exitCode, 0) << ok.output;
    EXPECT_TRUE(fs::is_regular_file(mDir / "r" / "report.json"));
    EXPECT_EQ(names(snapshot(mDir / "out")), " anaglyph.png view-0.png view-1.png");
    EXPECT_EQ(names(snapshot(mDir / "r")), " report.json");
}

TEST_F(WholeSets, ADeviceInAnOutputsPlaceIsNotReplaced) {
    // As root, a rename would replace /dev/full itself: it is refused before anything is made.
    const CliRun r = run("render --views 2 --size 32x24 -o out --report-json /dev/full");
    expectError(r, 4, "/dev/full");
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
    EXPECT_FALSE(fs::exists(mDir / "out")) << names(snapshot(mDir));
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/dev", ec))
        EXPECT_EQ(e.path().filename().string().find(".mvr-part"), std::string::npos) << e.path();
}

TEST_F(WholeSets, ComposeWritesItsFileWholeOrNotAtAll) {
    ASSERT_EQ(run("render --views 2 --size 256x192 --write views -o in").exitCode, 0);
    write("out/anaglyph.png", "an older one");
    const auto before = snapshot(mDir / "out");
    const CliRun r = run("compose in/view-0.png in/view-1.png --format sbs -o out",
                         "ulimit -f 8 &&");
    expectError(r, 4, "File too large");
    EXPECT_EQ(snapshot(mDir / "out"), before) << "now:" << names(snapshot(mDir / "out"));
    const CliRun file = run("compose in/view-0.png in/view-1.png --format sbs -o x/sbs.png",
                            "ulimit -f 8 &&");
    expectError(file, 4, "File too large");
    EXPECT_FALSE(fs::exists(mDir / "x")) << names(snapshot(mDir));
}

TEST_F(WholeSets, AStagingFolderOfAKilledRunIsRemovedByTheNext) {
    // SIGKILL leaves its staging folder: the next run into -o removes it, when its process is
    // gone (no PID reaches 999999999: Linux's pid_max is at most 2^22), and leaves a running
    // one's (PID 1 runs) alone.
    write("out/.mvr-part-999999999-0/view-0.png", "half a render");
    write("out/.mvr-part-1-0/view-0.png", "another run's, going on");
    const CliRun r = run("render --views 2 --size 32x24 -q -o out");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(names(snapshot(mDir / "out")),
              " .mvr-part-1-0/ .mvr-part-1-0/view-0.png anaglyph.png view-0.png view-1.png");
}

// ---- a signal mid-run ---------------------------------------------------------------------------

TEST_F(WholeSets, SigintWhileAStillIsWrittenLeavesNothing) {
    write("out/view-0.png", "an older render");
    const auto before = snapshot(mDir / "out");
    // Stopped as soon as its staging folder appears: the views are being written.
    const CliRun r = stopWhen("render --views 24 --size 640x480 --write views,depth -o out",
                              "out/.mvr-part-*", "INT");
    ASSERT_EQ(r.exitCode, 130) << r.output;
    EXPECT_NE(r.output.find("error: stopped by SIGINT: nothing was written"), std::string::npos)
        << r.output;
    EXPECT_EQ(snapshot(mDir / "out"), before) << "now:" << names(snapshot(mDir / "out"));
}

TEST_F(WholeSets, SigtermMidSequenceLeavesWholeFramesAndSaysHowToResume) {
    const std::string args = "render --frames 30 --views 2 --size 200x150 -o seq";
    const CliRun r = stopWhen(args, "seq/frame-0002", "TERM");
    ASSERT_EQ(r.exitCode, 143) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m,
                                  std::regex("error: stopped by SIGTERM: (\\d+) of 30 frames are "
                                             "complete in seq/ \\(`--frame-range (\\d+):` renders "
                                             "the rest\\)")))
        << r.output;
    const int done = std::stoi(m[1]);
    ASSERT_GE(done, 3);
    ASSERT_LT(done, 30) << "the run ended before it was stopped";
    auto frames = snapshot(mDir / "seq");
    int folders = 0;
    for (const auto& [name, bytes] : frames) {
        EXPECT_EQ(name.find("part"), std::string::npos) << "left: " << name;
        if (name.back() == '/') ++folders;
    }
    EXPECT_EQ(folders, done) << names(frames);
    for (int f = 0; f < done; ++f) {
        for (const char* file : {"view-0.png", "view-1.png", "anaglyph.png"})
            EXPECT_TRUE(frames.count(fmt::format("frame-{:04}/{}", f, file))) << f << file;
    }
    // The message's range renders the rest, and the folders are those of one run.
    const CliRun rest = run(fmt::format("{} -q --frame-range {}:", args, m[2].str()));
    ASSERT_EQ(rest.exitCode, 0) << rest.output;
    frames = snapshot(mDir / "seq");
    folders = 0;
    for (const auto& [name, bytes] : frames) folders += name.back() == '/';
    EXPECT_EQ(folders, 30) << names(frames);
}

TEST_F(WholeSets, SigtermMidVideoRemovesTheUnfinishedVideo) {
    const CliRun r = stopWhen(
        "render --frames 40 --views 2 --size 128x96 --format sbs --video v.mkv -o seq",
        "v.part.mkv", "TERM");
    if (r.output.find("built without FFmpeg") != std::string::npos)
        MVR_SKIP(FeatureNotBuilt) << "video (FFmpeg)";
    ASSERT_EQ(r.exitCode, 143) << r.output;
    EXPECT_NE(r.output.find("the unfinished video was removed"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(mDir / "v.mkv"));
    EXPECT_FALSE(fs::exists(mDir / "v.part.mkv"));
}

}  // namespace
}  // namespace mvr
