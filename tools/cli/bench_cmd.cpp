// `mvr bench`: times rendering methods side by side on one scene and rig — warm-up, then F
// frames; median and min wall time per method, the per-stage breakdown where the backend
// measures it (soft), and the ratio to the first method. Text table or --json.
// `mvr bench sorbier | kalaiah | adelson`: the papers' experiments (bench/experiments.h).
#include <fmt/core.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "bench/report.h"
#include "command.h"
#include "options.h"

namespace mvr::cli {
namespace {

struct BenchOptions {
    SceneOptions scene;
    std::vector<std::string> methods = bench::defaultMethodList();
    int frames = 10;
    int warmup = 2;
    bool json = false;
    int threads = 0;
    std::string simd = "auto";
};

std::string joined(const std::vector<std::string>& list) {
    std::string out;
    for (const std::string& s : list) out += (out.empty() ? "" : ",") + s;
    return out;
}

int runBench(const BenchOptions& o) {
    if (o.frames < 1 || o.frames > 100000) {
        return fail(
            usageError(fmt::format("--frames {} is out of range (expected 1..100000)", o.frames)));
    }
    if (o.warmup < 0 || o.warmup > 1000) {
        return fail(
            usageError(fmt::format("--warmup {} is out of range (expected 0..1000)", o.warmup)));
    }
    if (o.threads < 0 || o.threads > 1024) {
        return fail(usageError(fmt::format(
            "--threads {} is out of range (expected 0..1024, 0 = all cores)", o.threads)));
    }
    // Every backend:method is checked before anything is loaded.
    bench::BackendSet backends({.threads = o.threads, .simd = o.simd});
    auto jobs = bench::resolveJobs(o.methods, backends, {});
    if (!jobs) return fail(jobs.status());
    auto prepared = o.scene.prepare();
    if (!prepared) return fail(prepared.status());
    const bench::Machine machine = bench::describeMachine(backends);

    bench::Progress progress(0, o.json, false);
    const std::vector<bench::Measured> measured = bench::measure(
        *jobs, *prepared, {.warmup = o.warmup, .frames = o.frames, .stopAtFirstError = true},
        {.progress = &progress, .label = {}});
    for (const bench::Measured& m : measured) {
        if (m.failed()) {
            progress.done(true);
            return fail(m.error);
        }
    }
    progress.done();
    bench::MethodReport report;
    report.machine = &machine, report.request = &*prepared;
    report.frames = o.frames, report.warmup = o.warmup;
    for (std::size_t j = 0; j < jobs->size(); ++j)
        report.rows.push_back(bench::methodRow((*jobs)[j], measured[j]));
    return bench::printMethodReport(report, o.json);
}

const CommandRegistrar kBench(30, [](CLI::App& root) -> std::function<int()> {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* app = root.add_subcommand(
        "bench",
        "Time rendering methods side by side (warm-up, then F frames): median/min ms, per-stage "
        "breakdown (soft), ratio to the first method; --json for machines");
    o->scene.addTo(app);
    bench::addMethodsOption(app, o->methods,
                            "BACKEND:METHOD list, comma separated (first = baseline)",
                            joined(o->methods));
    app->add_option("--frames", o->frames, "Timed frames per method")->default_val(o->frames);
    app->add_option("--warmup", o->warmup, "Untimed frames before them")->default_val(o->warmup);
    app->add_option("--threads", o->threads, "soft: worker threads (0 = one per core)")
        ->default_val(o->threads);
    app->add_option("--simd", o->simd, "soft: SIMD path auto | scalar | avx2 | avx512")
        ->default_val(o->simd);
    app->add_flag("--json", o->json, "Print JSON: {machine, scene, results: [...]}");
    // bench sorbier | kalaiah | adelson
    const std::vector<bench::PaperBench> papers = {bench::addSorbier(app), bench::addKalaiah(app),
                                                   bench::addAdelson(app), bench::addViews(app),
                                                   bench::addShadows(app), bench::addOutputs(app),
                                                   bench::addLenticular(app)};
    return [o, papers] {
        for (const bench::PaperBench& p : papers) {
            if (p.app->parsed()) return p.run();
        }
        return runBench(*o);
    };
});

}  // namespace
}  // namespace mvr::cli
