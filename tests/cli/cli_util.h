// tests/cli — what the CLI tests share: where the `mvr` binary and the shared models are, and
// running `mvr ARGS` in a folder with its stdout, stderr and exit code captured.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/core.h>

namespace mvr::test {

inline std::filesystem::path mvrBinary() {
    const char* bin = std::getenv("MVR_BINARY_DIR");
    return std::filesystem::path(bin ? bin : MVR_TEST_BINARY_DIR) / "tools" / "cli" / "mvr";
}

inline std::filesystem::path sharedModels() {
    const char* dir = std::getenv("MVR_SHARED_DIR");
    return std::filesystem::path(dir ? dir : MVR_TEST_SHARED_DIR) / "models";
}

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct CliRun {
    int exitCode = -1;
    std::string out, err;
};

/// `mvr ARGS` run in `dir` (no standard input); its output goes through files in `dir`.
/// `shellPrefix` runs in the same shell first (e.g. "ulimit -v 1500000 && ").
inline CliRun runMvr(const std::filesystem::path& dir, const std::string& args,
                     const std::string& shellPrefix = "") {
    const auto outFile = dir / "stdout.txt", errFile = dir / "stderr.txt";
    const std::string cmd =
        fmt::format("cd '{}' && {}'{}' {} >'{}' 2>'{}' </dev/null", dir.string(), shellPrefix,
                    mvrBinary().string(), args, outFile.string(), errFile.string());
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(outFile);
    r.err = slurp(errFile);
    return r;
}

}  // namespace mvr::test
