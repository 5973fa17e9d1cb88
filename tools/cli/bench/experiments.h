// tools/cli/bench/experiments.h — `mvr bench sorbier | kalaiah | adelson`: the experiments of
// the papers (sorbier2008 Tables 1–2, kalaiah2007 Table 1, adelson1991 Table 1) on this
// machine. Each file measures through harness.h and hands its rows to report.h: markdown
// tables, --json, --csv and a gnuplot --plot.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace mvr::cli::bench {

/// A paper's subcommand of `mvr bench` and the function that runs it (returns the exit code).
struct PaperBench {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

PaperBench addSorbier(CLI::App* bench);  ///< sorbier.cpp
PaperBench addKalaiah(CLI::App* bench);  ///< kalaiah.cpp
PaperBench addAdelson(CLI::App* bench);  ///< adelson.cpp
PaperBench addViews(CLI::App* bench);    ///< views.cpp: N views, × one view
PaperBench addShadows(CLI::App* bench);  ///< shadows.cpp: K lights' maps, one pass vs K
PaperBench addOutputs(CLI::App* bench);  ///< outputs.cpp: writing files and videos (issue 37)
PaperBench addLenticular(CLI::App* bench);  ///< lenticular.cpp: direct lenticular (issue 43)

}  // namespace mvr::cli::bench
