// tools/cli/bench_papers.h — `mvr bench sorbier | kalaiah | adelson`: the experiments of the
// papers (sorbier2008 Tables 1–2, kalaiah2007 Table 1, adelson1991 Table 1) on this machine,
// as markdown tables, --json, --csv and a gnuplot --plot.
#pragma once

#include <functional>
#include <optional>

#include <CLI/CLI.hpp>

namespace mvr::cli {

/// Adds the paper subcommands to the `bench` command. The returned function runs the one that
/// was given on the command line and returns its exit code, or nullopt when none was.
std::function<std::optional<int>()> addPaperBenches(CLI::App* bench);

}  // namespace mvr::cli
