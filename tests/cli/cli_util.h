// tests/cli — what the CLI tests share (the binary and models: tests/support): running `mvr ARGS` in a folder with its stdout, stderr and exit code captured.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/core.h>
#include "mvr_test_support.h"

namespace mvr::test {

// mvrBinary(), modelsDir(): tests/support/mvr_test_support.h
inline std::filesystem::path sharedModels() { return modelsDir(); }

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
