// tests/cli — what the CLI tests share beyond tests/support (which runs `mvr`, finds the binary
// and the models).
#pragma once

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

// slurp(), CliRun, runMvr(): tests/support/mvr_test_support.h

}  // namespace mvr::test
