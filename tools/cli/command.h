// tools/cli/command.h — self-registering subcommands of the `mvr` tool.
//
// Each `*_cmd.cpp` file in tools/cli/ defines one subcommand and registers it with a static
// CommandRegistrar; CMake compiles every *_cmd.cpp into the `mvr` executable, so adding a
// command needs no edit anywhere else.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace mvr::cli {

/// Called once at start-up: adds the subcommand (and its options) to `root` and returns the
/// function that runs it after parsing; that function returns the process exit code.
using CommandSetup = std::function<std::function<int()>(CLI::App& root)>;

struct CommandEntry {
    int order;  ///< position in `mvr --help`
    CommandSetup setup;
};

std::vector<CommandEntry>& commandRegistry();

struct CommandRegistrar {
    CommandRegistrar(int order, CommandSetup setup) {
        commandRegistry().push_back({order, std::move(setup)});
    }
};

}  // namespace mvr::cli
