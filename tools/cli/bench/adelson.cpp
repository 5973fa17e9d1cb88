// `mvr bench adelson`: adelson1991 Table 1 — each simultaneous (both eyes at once) CPU
// algorithm against its single-eye version run once per eye: operation counts and time.
#include <algorithm>
#include <cctype>

#include <fmt/core.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "bench/report.h"
#include "mvr/adelson/adelson.h"

namespace mvr::cli::bench {

namespace {

struct AdelsonOptions {
    CommonOptions common;
    bool tiny = false;
    double minBatchMs = 20.0;
    std::string only;
};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// Checks, counts and times one case: batches alternating separate and simultaneous.
AdelsonRow measureCase(adelson::ExperimentCase& c, const CommonOptions& o, double minBatchMs) {
    AdelsonRow r;
    r.algorithm = c.algorithm, r.caseName = c.caseName, r.label = c.label, r.paperI = c.paperI,
    r.paperII = c.paperII, r.paperIII = c.paperIII, r.opsNote = c.opsNote;
    r.check = c.check(r.checkDetail);  // results must agree before anything is timed
    c.separate(&r.opsSep);
    c.simultaneous(&r.opsSim);
    for (int i = 0; i < o.warmup; ++i) c.separate(nullptr), c.simultaneous(nullptr);
    const std::function<void()> fns[2] = {[&c] { c.separate(nullptr); },
                                          [&c] { c.simultaneous(nullptr); }};
    r.reps =
        repetitionsFor(fns[0], minBatchMs);  // enough for --min-batch-ms of the separate version
    const std::vector<BatchSamples> t = measureBatches(fns, o.frames, r.reps);
    r.sepMs = statsOf(t[0].cpuMs), r.simMs = statsOf(t[1].cpuMs);
    r.sepWall = statsOf(t[0].wallMs), r.simWall = statsOf(t[1].wallMs);
    r.byOps = adelson::savingsFrom(double(r.opsSep.total()), double(r.opsSim.total()));
    r.byTime = adelson::savingsFrom(r.sepMs.median, r.simMs.median);
    // Interpolation counts are the paper's measure for Gouraud shading only.
    r.hasInterp = r.opsSep.interps > 0 && (r.algorithm.find("Gouraud") != std::string::npos ||
                                           r.caseName.find("Gouraud") != std::string::npos);
    if (r.hasInterp)
        r.byInterp = adelson::savingsFrom(double(r.opsSep.interps), double(r.opsSim.interps));
    return r;
}

int runAdelson(const AdelsonOptions& o) {
    if (Status s = checkCommonOptions(o.common); !s) return fail(s);
    if (!(o.minBatchMs >= 0.0 && o.minBatchMs <= 10000.0)) {
        return fail(usageError(
            fmt::format("--min-batch-ms {} is out of range (expected 0..10000)", o.minBatchMs)));
    }
    const Machine machine = describeMachine(BackendSet({.threads = o.common.threads}));
    std::vector<adelson::ExperimentCase> cases = adelson::adelsonCases(o.tiny);
    if (!o.only.empty()) {
        std::erase_if(cases, [&](const adelson::ExperimentCase& c) {
            return lower(c.algorithm).find(lower(o.only)) == std::string::npos;
        });
        if (cases.empty())
            return fail(
                usageError(fmt::format("--only '{}' matches no algorithm of Table 1", o.only)));
    }
    Progress progress(int(cases.size()), o.common.machineReadable(), o.common.progress);
    AdelsonReport report;
    report.machine = &machine, report.tiny = o.tiny;
    for (adelson::ExperimentCase& c : cases) {
        report.rows.push_back(measureCase(c, o.common, o.minBatchMs));
        progress.step(c.algorithm + ": " + c.caseName);
    }
    progress.done();
    if (int rc = printAdelsonReport(report, o.common); rc != 0) return rc;
    for (const AdelsonRow& r : report.rows) {
        if (!r.check.empty()) {
            return fail(
                internalError("adelson: a simultaneous algorithm disagreed with its single-eye "
                              "version (see the table)"));
        }
    }
    return 0;
}

}  // namespace

PaperBench addAdelson(CLI::App* bench) {
    auto o = std::make_shared<AdelsonOptions>();
    o->common.frames = 7;
    CLI::App* a = bench->add_subcommand(
        "adelson",
        "adelson1991 Table 1: savings of each simultaneous stereo CPU algorithm (and the village "
        "renderer) over two single-eye runs, measures I, II, III from operation counts and time");
    a->add_flag("--tiny", o->tiny, "Small workloads (for tests)");
    a->add_option("--min-batch-ms", o->minBatchMs,
                  "Repeat each algorithm until a batch takes this long")
        ->default_val(o->minBatchMs);
    a->add_option("--only", o->only, "Only the algorithms whose name contains this text");
    addCommonOptions(a, o->common, "Timed batches per algorithm");
    return {a, [o] { return runAdelson(*o); }};
}

}  // namespace mvr::cli::bench
