// tests/support/mvr_test_support.h — what every test executable shares: where the built `mvr`
// binary and the shared models are (one place each, from CMake), and the one way a test skips.
//
// Skips: a closed set of reasons (SkipReason) and one macro, MVR_SKIP(reason) << detail, which
// GTEST_SKIPs with a standard message — or FAILs when the environment requires what is missing:
//   MVR_REQUIRE_GL=1      NoGlContext and NoVulkanDevice fail (a method the driver lacks stays a skip: which
//                         methods a driver must run is tests/conformance/gl_requirements.h's list)
//   MVR_REQUIRE_MODELS=1  ModelsMissing fails
// A missing `mvr` binary is never a skip: the same build builds it (FAIL, see requireMvr()).
// No raw GTEST_SKIP outside tests/support (grep -rn GTEST_SKIP tests finds only this file).
//
// Scenes: test_scenes.h (beside this header) holds the scenes, rigs and image measures the
// cross-backend tests share (conformance, raster, gl, vk); images are compared with
// mvr::compareImages() (mvr/core/image.h).
//
// Processes: runMvr(dir, args) runs the built `mvr` with stdout and stderr apart; runShell(command)
// runs any command line with both together. No test spawns a process another way (the viewer's
// Xvfb server, which must outlive a command, is the one exception).
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace mvr::test {

enum class SkipReason {
    NoGlContext,                // no EGL/GL context can be made here
    NoVulkanDevice,             // no Vulkan device (lavapipe or a GPU) here
    MethodUnsupportedByDriver,  // the driver refuses one method (e.g. no GL_OVR_multiview)
    ModelsMissing,              // MVR_SHARED_DIR/models lacks the file
    FeatureNotBuilt,            // a backend / viewer / video / mpi this build left out
    NoDisplay,                  // no X display (Xvfb) for the viewer
    ToolMissing,                // an optional host tool (exiftool, gnuplot, script)
    NotApplicable,              // the case does not apply to this run (sanitizer, CPU, mode)
};

inline const char* skipReasonName(SkipReason r) {
    switch (r) {
        case SkipReason::NoGlContext: return "NoGlContext";
        case SkipReason::NoVulkanDevice: return "NoVulkanDevice";
        case SkipReason::MethodUnsupportedByDriver: return "MethodUnsupportedByDriver";
        case SkipReason::ModelsMissing: return "ModelsMissing";
        case SkipReason::FeatureNotBuilt: return "FeatureNotBuilt";
        case SkipReason::NoDisplay: return "NoDisplay";
        case SkipReason::ToolMissing: return "ToolMissing";
        case SkipReason::NotApplicable: return "NotApplicable";
    }
    return "?";
}

inline bool envIsOne(const char* name) {
    const char* v = std::getenv(name);
    return v && std::string(v) == "1";
}

/// The variable that turns a skip for `r` into a failure ("" when none does).
inline const char* requiringVariable(SkipReason r) {
    switch (r) {
        case SkipReason::NoGlContext:
        case SkipReason::NoVulkanDevice: return "MVR_REQUIRE_GL";
        case SkipReason::ModelsMissing: return "MVR_REQUIRE_MODELS";
        default: return "";
    }
}

inline bool skipMustFail(SkipReason r) {
    const char* var = requiringVariable(r);
    return *var && envIsOne(var);
}

inline ::testing::TestPartResult::Type skipResultType(SkipReason r) {
    return skipMustFail(r) ? ::testing::TestPartResult::kFatalFailure
                           : ::testing::TestPartResult::kSkip;
}

inline std::string skipHeader(SkipReason r) {
    std::string h = std::string("[skip ") + skipReasonName(r) + "]";
    if (skipMustFail(r)) h += std::string(" fails: ") + requiringVariable(r) + "=1";
    return h;
}

/// The built `mvr`: CMake's $<TARGET_FILE:mvr>, wherever the output folder is
/// (MVR_BINARY_DIR=DIR overrides it with DIR/tools/cli/mvr, for another build's binary).
inline std::filesystem::path mvrBinary() {
    if (const char* bin = std::getenv("MVR_BINARY_DIR"); bin && *bin)
        return std::filesystem::path(bin) / "tools" / "cli" / "mvr";
    return std::filesystem::path(MVR_TEST_CLI);
}

/// MVR_SHARED_DIR (the environment first, else the folder CMake was configured with).
inline std::filesystem::path sharedDir() {
    const char* v = std::getenv("MVR_SHARED_DIR");
    return std::filesystem::path(v && *v ? v : MVR_TEST_SHARED_DIR);
}

inline std::filesystem::path modelsDir() { return sharedDir() / "models"; }

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// A finished process: its exit code (128 + the signal when one ended it) and what it printed
/// (`out` and `err` apart from runMvr; `output`, both together, from runShell).
struct CliRun {
    int exitCode = -1;
    std::string out, err, output;
};

inline int exitCodeOf(int status) {
    if (status == -1) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// `command` run by /bin/sh with stderr joined to stdout (no standard input).
inline CliRun runShell(const std::string& command) {
    CliRun r;
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen((command + " 2>&1 </dev/null").c_str(), "r"),
                                               pclose);
    if (!pipe) return r;
    std::array<char, 512> buf;
    while (std::fgets(buf.data(), int(buf.size()), pipe.get())) r.output += buf.data();
    r.exitCode = exitCodeOf(pclose(pipe.release()));
    return r;
}

/// `mvr ARGS` run in `dir` (no standard input); its output goes through files in `dir`.
/// `shellPrefix` runs in the same shell first (e.g. "ulimit -v 1500000 && ").
inline CliRun runMvr(const std::filesystem::path& dir, const std::string& args,
                     const std::string& shellPrefix = "") {
    const auto outFile = dir / "stdout.txt", errFile = dir / "stderr.txt";
    const std::string cmd = "cd '" + dir.string() + "' && " + shellPrefix + "'" +
                            mvrBinary().string() + "' " + args + " >'" + outFile.string() +
                            "' 2>'" + errFile.string() + "' </dev/null";
    CliRun r;
    r.exitCode = exitCodeOf(std::system(cmd.c_str()));
    r.out = slurp(outFile);
    r.err = slurp(errFile);
    return r;
}

}  // namespace mvr::test

/// MVR_SKIP(reason) << detail; returns from the test (or void helper) like GTEST_SKIP.
#define MVR_SKIP(reason)                                                                   \
    return ::testing::internal::AssertHelper(                                              \
               ::mvr::test::skipResultType(::mvr::test::SkipReason::reason), __FILE__,     \
               __LINE__, ::mvr::test::skipHeader(::mvr::test::SkipReason::reason).c_str()) = \
               ::testing::Message() << " "

/// Fails (never skips) when the built `mvr` is absent: the same build makes it.
#define MVR_REQUIRE_MVR_BINARY(path) \
    ASSERT_TRUE(std::filesystem::exists(path)) << (path) << " is not built (the same build makes it)"
