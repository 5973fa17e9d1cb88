// `mvr bench views`: many views at the cost of how many? For each view count N (an off-axis
// row of N views, or the C×R grids of --grid-views), the time of every method, its multiple of
// one view (time(N) / time(1) of the same method) and its speed-up over multipass of the same
// backend; the passes a gl method drew the views in (kalaiah2007 §3's batches). With --rounds R
// the whole sweep runs R times, each view count's frames of every round pooled: a change in
// machine load then hits the counts alike, so that the multiples of one view come from the same
// stretch of time (the jobs of one count are interleaved by measure() already).
#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <regex>

#include <fmt/core.h>

#include "bench/experiments.h"
#include "mvr/core/antialias.h"
#include "mvr/core/synthesize.h"
#include "bench/harness.h"
#include "bench/report.h"

namespace mvr::cli::bench {

namespace {

struct ViewsOptions {
    CommonOptions common;
    std::vector<std::string> models;
    int grid = 1;
    std::vector<int> counts{1, 2, 4, 9, 16, 45, 72, 100};
    std::vector<std::string> gridViews;  ///< CxR entries; replace --counts when given
    std::string size = "420x560";
    std::string shading = "vertex";
    std::string specular = "center";  ///< --specular center | per-view
    std::string environment;          ///< --environment MAP (image lighting); empty: none
    std::vector<std::string> methods{"soft:multipass", "soft:unified"};
    int rounds = 1;  ///< sweeps over the view counts, pooled
    std::vector<int> aa{1};  ///< --aa: samples a pixel, each count measured with each
    std::vector<int> synthesize{1};  ///< --synthesize: K, each count of 3+ views with each
};

/// The view arrangements to measure: "Nx1" rows, or the --grid-views entries.
Result<std::vector<std::pair<int, int>>> viewConfigs(const ViewsOptions& o) {
    std::vector<std::pair<int, int>> configs;
    if (!o.gridViews.empty()) {
        static const std::regex kGrid(R"((\d{1,3})[xX](\d{1,3}))");
        for (const std::string& g : o.gridViews) {
            std::smatch m;
            if (!std::regex_match(g, m, kGrid)) {
                return usageError(
                    fmt::format("--grid-views entry '{}' is not of the form CxR (e.g. 9x9)", g));
            }
            const int c = std::stoi(m[1].str()), r = std::stoi(m[2].str());
            if (c < 1 || r < 1 || c * r > kMaxViews) {
                return usageError(
                    fmt::format("--grid-views entry '{}' is out of range (expected 1..{} views)", g,
                                kMaxViews));
            }
            configs.push_back({c, r});
        }
        return configs;
    }
    for (int n : o.counts) {
        if (n < 1 || n > kMaxViews) {
            return usageError(
                fmt::format("--counts entry {} is out of range (expected 1..{})", n, kMaxViews));
        }
        configs.push_back({n, 1});
    }
    if (configs.empty()) return usageError("--counts is empty (expected e.g. 1,2,4,9,16,45)");
    return configs;
}

/// The lowest PSNR of a warped view of `p` (--synthesize K) against the same job's exact render.
double lowestPsnr(Backend& backend, const std::string& method, const Prepared& p) {
    auto exact = backend.render(p.scene, p.rig, p.settings, method);
    auto warped = renderSynthesized(backend, p.scene, p.rig, p.settings, method, p.synthesize);
    if (!exact || !warped) return 0.0;
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < exact->color.size(); ++v)
        lowest = std::min(lowest, compareImages(warped->color[v], exact->color[v]).psnr);
    return lowest;
}

int runViews(const ViewsOptions& o) {
    if (Status s = checkCommonOptions(o.common); !s) return fail(s);
    if (o.grid < 1 || o.grid > 64) {
        return fail(usageError(fmt::format("--grid {} is out of range (expected 1..64)", o.grid)));
    }
    if (o.rounds < 1 || o.rounds > 100) {
        return fail(
            usageError(fmt::format("--rounds {} is out of range (expected 1..100)", o.rounds)));
    }
    auto configsR = viewConfigs(o);
    if (!configsR) return fail(configsR.status());
    // Every view arrangement with every --aa count and --synthesize step (rows of 3 or more
    // views: K > 1 needs views to warp): (columns, rows, samples, K).
    std::vector<std::array<int, 4>> configs;
    for (const int k : o.synthesize) {
        if (k < 1 || k > kMaxSynthesisStep) {
            return fail(usageError(fmt::format(
                "--synthesize {} is out of range (expected 1..{})", k, kMaxSynthesisStep)));
        }
    }
    for (const auto& [c, r] : *configsR) {
        for (const int a : o.aa) {
            if (!validSampleCount(a))
                return fail(usageError(fmt::format("--aa {}: expected 1, 2, 4 or 8 samples a pixel", a)));
            for (const int k : o.synthesize)
                if (k == 1 || c >= 3) configs.push_back({c, r, a, k});
        }
    }
    if (auto size = parseSize(o.size, "--size"); !size) return fail(size.status());
    if (auto shading = parseShading(o.shading); !shading) return fail(shading.status());
    BackendSet backends({.threads = o.common.threads});
    std::vector<Skipped> skipped;
    auto jobsR = resolvePaperJobs(o.methods, backends, skipped);
    if (!jobsR) return fail(jobsR.status());
    const std::vector<Job> jobs = std::move(jobsR).value();
    const Machine machine = describeMachine(backends);
    // A bare name that is not a file here is one of the shared models (stanford-bunny.obj).
    std::vector<std::string> models;
    for (const std::string& m : o.models) {
        std::error_code ec;
        auto path = std::filesystem::exists(m, ec) || m.find('/') != std::string::npos
                        ? Result<std::string>(m)
                        : findModel("", m);
        if (!path) return fail(path.status());
        models.push_back(*path);
    }

    // Each view count's scene is prepared once (the model is read once per count), then measured
    // in every round.
    std::vector<Prepared> scenes;
    for (const auto& [c, r, a, k] : configs) {
        SceneOptions so;
        so.aa = a;
        so.synthesize = k;
        so.models = models;
        so.grid = o.grid;
        so.viewGrid = fmt::format("{}x{}", c, r);
        so.size = o.size;
        so.shading = o.shading;
        so.specular = o.specular;
        so.environment = o.environment;
        auto prepared = so.prepare();
        if (!prepared) return fail(prepared.status());
        scenes.push_back(std::move(prepared).value());
    }
    Progress progress(int(configs.size() * jobs.size()) * o.rounds, o.common.machineReadable(),
                      o.common.progress);
    std::vector<std::vector<Measured>> pooled(configs.size());
    for (int round = 0; round < o.rounds; ++round) {
        for (std::size_t i = 0; i < configs.size(); ++i) {
            const int views = configs[i][0] * configs[i][1];
            std::vector<Measured> m = measure(
                jobs, scenes[i], {.warmup = o.common.warmup, .frames = o.common.frames},
                {.progress = &progress,
                 .label = o.rounds > 1
                              ? fmt::format("{} views, round {}/{}", views, round + 1, o.rounds)
                              : fmt::format("{} views", views)});
            if (round == 0) {
                pooled[i] = std::move(m);
                continue;
            }
            for (std::size_t j = 0; j < jobs.size(); ++j) {
                Measured& to = pooled[i][j];
                if (to.failed()) continue;  // its first error stands
                if (m[j].failed()) {
                    to.error = m[j].error;
                    continue;
                }
                to.wallMs.insert(to.wallMs.end(), m[j].wallMs.begin(), m[j].wallMs.end());
                to.cpuMs.insert(to.cpuMs.end(), m[j].cpuMs.begin(), m[j].cpuMs.end());
                to.stats.insert(to.stats.end(), m[j].stats.begin(), m[j].stats.end());
            }
        }
    }
    // Per-view specular is per pixel (the prepared settings).
    const std::string shadingLabel =
        (o.specular == "per-view" ? std::string("pixel per-view") : o.shading) +
        (o.environment.empty() ? "" : " + environment");
    RenderReport report;
    report.bench = "views", report.machine = &machine, report.skipped = skipped;
    for (const Job& j : jobs) report.series.push_back(j.text());
    std::string model = "default scene";
    for (std::size_t i = 0; i < configs.size(); ++i) {
        const auto [c, r, a, k] = configs[i];
        const Prepared& p = scenes[i];
        model = std::filesystem::path(p.sceneName).filename().string();
        const std::vector<Measured>& m = pooled[i];
        const std::size_t first = report.rows.size();
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            RenderRow row = renderRow(jobs[j], m[j], p.scene.triangleCount());
            row.shading = shadingName(p.settings.shading), row.model = model, row.copies = o.grid;
            row.views = c * r, row.samples = a, row.synthesize = k;
            row.config = fmt::format("{}x{}{}{}", c, r, a > 1 ? fmt::format(" aa{}", a) : "",
                                     k > 1 ? fmt::format(" k{}", k) : "");
            if (k > 1 && !m[j].failed()) row.psnr = lowestPsnr(*jobs[j].backend, jobs[j].spec.method, p);
            row.width = p.settings.width, row.height = p.settings.height;
            if (!m[j].stats.empty()) row.passes = m[j].stats.back().passes;
            if (!m[j].stats.empty()) row.drawnSamples = m[j].stats.back().samples;
            report.rows.push_back(row);
        }
        fillSpeedups(report.rows, first);
    }
    progress.done();
    // × one view: against the same job's single view (a 1x1 config), where one was measured.
    for (RenderRow& r : report.rows) {
        for (const RenderRow& one : report.rows) {
            if (one.spec() != r.spec() || !one.error.empty() || !r.error.empty() ||
                !(one.wall.median > 0))
                continue;
            if (one.views == 1 && one.samples == r.samples) r.timesOne = r.wall.median / one.wall.median;
            if (one.views == r.views && one.samples == 1 && r.samples > 1 &&
                one.synthesize == r.synthesize)
                r.timesOneSample = r.wall.median / one.wall.median;
            if (one.views == r.views && one.samples == r.samples && one.synthesize == 1 &&
                r.synthesize > 1)
                r.timesExact = r.wall.median / one.wall.median;
        }
    }
    report.tables.push_back(PivotTable{
        .caption = fmt::format(
            "Many views — {} ({} copies), views of {} each, {} shading, {}; "
            "cell: median wall ms, × one view of the same method, speed-up over multipass of the "
            "same backend, and the passes where a method batched the views",
            model, o.grid, o.size,
            shadingLabel,
            o.rounds > 1
                ? fmt::format("{} rounds over the view counts of {} frames after {} "
                              "warm-up each, pooled",
                              o.rounds, o.common.frames, o.common.warmup)
                : fmt::format("{} frames after {} warm-up", o.common.frames, o.common.warmup)),
        .rowHeads = {"views"},
        .filter = [](const RenderRow&) { return true; },
        .rowLabels = [](const RenderRow& r) { return std::vector<std::string>{r.config}; },
        .column = [](const RenderRow& r) { return r.spec(); },
        .cell = [](const RenderRow& r) -> std::string {
            if (!r.error.empty()) return "error";
            std::string cell = fmt::format("{:.1f} ms", r.wall.median);
            if (r.timesOne > 0) cell += fmt::format(", {:.2f}× one view", r.timesOne);
            if (r.timesOneSample > 0) cell += fmt::format(", {:.2f}× one sample", r.timesOneSample);
            if (r.samples > 1 && r.drawnSamples > 0)
                cell += r.drawnSamples > 1 ? ", multisampled"
                                           : fmt::format(", {} sub-pixel passes", r.samples);
            if (r.timesExact > 0) cell += fmt::format(", {:.2f}× exact", r.timesExact);
            if (r.psnr > 0) cell += fmt::format(", PSNR ≥ {:.1f} dB", r.psnr);
            if (r.speedup > 0) cell += fmt::format(", {:.2f}× vs multipass", r.speedup);
            if (r.passes > 1) cell += fmt::format(", {} passes", r.passes);
            return cell;
        }});
    report.plot = RenderPlot{
        .title = fmt::format("Many views: time(N) / time(1), views of {}", o.size),
        .xlabel = "views N",
        .filter =
            [](const RenderRow& r) { return r.timesOne > 0 && r.samples == 1 && r.synthesize == 1; },
        .panel =
            [](const RenderRow& r) {
                return fmt::format("{} ({} triangles)", r.model, r.triangles);
            },
        .x = [](const RenderRow& r) { return double(r.views); },
        .y =
            [](const RenderRow& r) {
                const double perMs = r.timesOne / r.wall.median;
                return std::array<double, 3>{r.timesOne, r.wall.min * perMs, r.wall.max * perMs};
            },
        .ylabel = "x one view (time(N) / time(1), median; bars: min-max)"};
    return printRenderReport(report, o.common);
}

}  // namespace

PaperBench addViews(CLI::App* bench) {
    auto o = std::make_shared<ViewsOptions>();
    o->common.frames = 5;
    CLI::App* v = bench->add_subcommand(
        "views",
        "Many views: time, multiple of one view and speed-up over multipass for rows of N views "
        "(1..100: light-field panels), every method batching past its per-pass limit");
    addModelOptions(v, o->models, o->grid);
    v->add_option("--counts", o->counts, "View counts N (a row of N views), comma separated")
        ->delimiter(',')
        ->default_str("1,2,4,9,16,45,72,100");
    v->add_option("--grid-views", o->gridViews,
                  "View grids CxR instead of rows, comma separated (e.g. 1x1,3x3,9x9)")
        ->delimiter(',');
    v->add_option("--size", o->size, "One view's size WxH")->default_val(o->size);
    v->add_option("--aa", o->aa,
                  "Samples a pixel to measure each count with (1, 2, 4, 8; comma separated): "
                  "cells say × one sample")
        ->delimiter(',')
        ->default_str("1");
    v->add_option("--synthesize", o->synthesize,
                  "View synthesis steps K to measure each count of 3 or more views with (1: "
                  "exact; comma separated): cells say × exact and the lowest PSNR of a warped view")
        ->delimiter(',')
        ->default_str("1");
    v->add_option("--shading", o->shading, "flat, vertex or pixel")->default_val(o->shading);
    v->add_option("--specular", o->specular,
                  "center or per-view: each view's highlights from its own eye (per pixel)")
        ->default_val(o->specular);
    v->add_option("--environment", o->environment,
                  "Light the scene with an environment map (as render's --environment; built "
                  "once, before timing)")
        ->type_name("MAP");
    addMethodsOption(v, o->methods,
                     "BACKEND:METHOD list (BACKEND:multipass is added as the baseline)",
                     "soft:multipass,soft:unified");
    addCommonOptions(v, o->common, "Timed frames per method and view count (per round)");
    v->add_option("--rounds", o->rounds,
                  "Sweeps over the view counts, each count's frames pooled over them (so that "
                  "load changes on a shared machine hit every count alike)")
        ->default_val(o->rounds);
    return {v, [o] { return runViews(*o); }};
}

}  // namespace mvr::cli::bench
