// `mvr bench kalaiah`: kalaiah2007 Table 1 — 1x1 to 3x3 views sharing one 800x600 buffer,
// several models, conventional (multipass) against unified (one-pass) rendering.
#include <filesystem>
#include <regex>

#include <fmt/core.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "bench/report.h"

namespace mvr::cli::bench {

namespace {

namespace fs = std::filesystem;

struct KalaiahOptions {
    CommonOptions common;
    std::vector<std::string> models;
    std::vector<std::string> configs{"1x1", "2x1", "3x1", "2x2", "3x2", "3x3"};
    std::vector<std::string> sizes{"800x600"};
    std::string shading = "vertex";
    std::vector<std::string> methods{
        "soft:multipass", "soft:unified",      "gl:multipass",       "gl:kalaiah-emulation",
        "gl:gs-layered",  "gl:gs-invocations", "gl:instanced-layer", "gl:viewport-array"};
};

/// MODEL[@K]: K copies of MODEL in a grid.
struct ModelSpec {
    std::string path, name;
    int copies = 1;
};

/// The models of the command line, or the shared ones (smallest first).
Result<std::vector<ModelSpec>> modelSpecs(std::vector<std::string> given) {
    if (given.empty()) {
        for (const char* name : {"suzanne.obj", "spot.obj", "teapot.obj", "stanford-bunny.obj",
                                 "stanford-bunny.obj@2"}) {
            std::string n = name;
            int k = 1;
            if (auto at = n.find('@'); at != std::string::npos)
                k = std::stoi(n.substr(at + 1)), n = n.substr(0, at);
            auto path = findModel("", n);
            if (!path) return path.status();
            given.push_back(*path + (k > 1 ? fmt::format("@{}", k) : ""));
        }
    }
    std::vector<ModelSpec> models;
    for (const std::string& g : given) {
        ModelSpec m;
        m.path = g;
        static const std::regex kCopies(R"((.*)@(\d{1,4}))");
        std::smatch sm;
        if (std::regex_match(g, sm, kCopies))
            m.path = sm[1].str(), m.copies = std::stoi(sm[2].str());
        if (m.copies < 1 || m.copies > 1024) {
            return usageError(fmt::format("model '{}': copies out of range (expected 1..1024)", g));
        }
        m.name =
            fs::path(m.path).stem().string() + (m.copies > 1 ? fmt::format("×{}", m.copies) : "");
        models.push_back(m);
    }
    return models;
}

int runKalaiah(const KalaiahOptions& o) {
    if (Status s = checkCommonOptions(o.common); !s) return fail(s);
    std::vector<std::pair<int, int>> configs;
    static const std::regex kGrid(R"((\d{1,2})[xX](\d{1,2}))");
    for (const std::string& c : o.configs) {
        std::smatch m;
        if (!std::regex_match(c, m, kGrid)) {
            return fail(usageError(
                fmt::format("--configs entry '{}' is not of the form CxR (e.g. 3x2)", c)));
        }
        const int cols = std::stoi(m[1].str()), rowsN = std::stoi(m[2].str());
        if (cols < 1 || rowsN < 1 || cols * rowsN > kMaxViews) {
            return fail(usageError(fmt::format(
                "--configs entry '{}' is out of range (expected 1..{} views)", c, kMaxViews)));
        }
        configs.push_back({cols, rowsN});
    }
    if (configs.empty()) return fail(usageError("--configs is empty (expected e.g. 1x1,2x1,3x3)"));
    std::vector<std::pair<int, int>> sizes;
    for (const std::string& sz : o.sizes) {
        auto p = parseSize(sz, "--sizes");
        if (!p) return fail(p.status());
        sizes.push_back(*p);
    }
    if (sizes.empty()) return fail(usageError("--sizes is empty (expected e.g. 800x600)"));
    for (const auto& [w, h] : sizes) {
        for (const auto& [c, r] : configs) {
            if (w / c < 1 || h / r < 1) {
                return fail(usageError(fmt::format(
                    "--sizes {}x{} is too small for {}x{} views (each view needs a pixel)", w, h, c,
                    r)));
            }
        }
    }
    if (auto shading = parseShading(o.shading); !shading) return fail(shading.status());
    auto modelsR = modelSpecs(o.models);
    if (!modelsR) return fail(modelsR.status());
    const std::vector<ModelSpec> models = std::move(modelsR).value();
    BackendSet backends({.threads = o.common.threads});
    std::vector<Skipped> skipped;
    auto jobsR = resolvePaperJobs(o.methods, backends, skipped);
    if (!jobsR) return fail(jobsR.status());
    const std::vector<Job> jobs = std::move(jobsR).value();
    const Machine machine = describeMachine(backends);

    Progress progress(int(sizes.size() * models.size() * configs.size() * jobs.size()),
                      o.common.machineReadable(), o.common.progress);
    RenderReport report;
    report.bench = "kalaiah2007", report.machine = &machine, report.skipped = skipped;
    for (const Job& j : jobs) report.series.push_back(j.text());
    for (const auto& [w, h] : sizes) {
        for (const ModelSpec& ms : models) {
            for (const auto& [c, r] : configs) {
                SceneOptions so;
                so.models = {ms.path};
                so.grid = ms.copies;
                so.viewGrid = fmt::format("{}x{}", c, r);
                so.size =
                    fmt::format("{}x{}", w / c, h / r);  // one buffer of w×h shared by the views
                so.shading = o.shading;
                auto prepared = so.prepare();
                if (!prepared) return fail(prepared.status());
                const Prepared& p = *prepared;
                const std::vector<Measured> m = measure(
                    jobs, p, {.warmup = o.common.warmup, .frames = o.common.frames},
                    {.progress = &progress, .label = fmt::format("{} {}x{}", ms.name, c, r)});
                const std::size_t first = report.rows.size();
                for (std::size_t j = 0; j < jobs.size(); ++j) {
                    RenderRow row = renderRow(jobs[j], m[j], p.scene.triangleCount());
                    row.shading = o.shading, row.model = ms.name, row.copies = ms.copies;
                    row.views = c * r, row.config = fmt::format("{}x{}", c, r);
                    row.width = w / c, row.height = h / r, row.bufferW = w, row.bufferH = h;
                    report.rows.push_back(row);
                }
                fillSpeedups(report.rows, first);
            }
        }
    }
    progress.done();

    // One table per buffer size: a line per model and view configuration, a column per method.
    for (const auto& [w, h] : sizes) {
        report.tables.push_back(PivotTable{
            .caption = fmt::format(
                "kalaiah2007 Table 1 — C×R views sharing one {}x{} buffer (each view {}/C × {}/R), {} shading, "
                "{} frames after {} warm-up; cell: fps = 1000 / median wall ms [slowest–fastest frame] and "
                "speed-up over multipass of the same backend (C = multipass, U = the one-pass method)",
                w, h, w, h, o.shading, o.common.frames, o.common.warmup),
            .rowHeads = {"model (triangles)", "views"},
            .filter = [w = w,
                       h = h](const RenderRow& r) { return r.bufferW == w && r.bufferH == h; },
            .rowLabels =
                [](const RenderRow& r) {
                    return std::vector<std::string>{fmt::format("{} ({})", r.model, r.triangles),
                                                    r.config};
                },
            .column = [](const RenderRow& r) { return r.spec(); },
            .cell = {}});
    }
    // One panel per model, fps against the number of views, one line per method (first size).
    const auto [w0, h0] = sizes[0];
    report.plot = RenderPlot{
        .title = fmt::format("kalaiah2007 Table 1 on this machine: views sharing one {}x{} buffer",
                             w0, h0),
        .xlabel = "views",
        .filter = [w0 = w0,
                   h0 = h0](const RenderRow& r) { return r.bufferW == w0 && r.bufferH == h0; },
        .panel =
            [](const RenderRow& r) {
                return fmt::format("{} ({} triangles)", r.model, r.triangles);
            },
        .x = [](const RenderRow& r) { return double(r.views); },
        .y = {},
        .ylabel = {}};
    return printRenderReport(report, o.common);
}

}  // namespace

PaperBench addKalaiah(CLI::App* bench) {
    auto o = std::make_shared<KalaiahOptions>();
    o->common.frames = 5;
    CLI::App* k = bench->add_subcommand(
        "kalaiah",
        "kalaiah2007 Table 1: views 1x1..3x3 sharing one 800x600 buffer, several models, conventional "
        "(multipass) vs unified (one-pass) fps");
    k->add_option(
        "models", o->models,
        "Models, MODEL[@K] for K copies (default: suzanne, spot, teapot, bunny, bunny@2)");
    k->add_option("--configs", o->configs, "View configurations CxR, comma separated")
        ->delimiter(',')
        ->default_str("1x1,2x1,3x1,2x2,3x2,3x3");
    k->add_option("--sizes", o->sizes, "Shared buffer sizes WxH, comma separated")
        ->delimiter(',')
        ->default_str("800x600");
    k->add_option("--shading", o->shading, "flat, vertex or pixel")->default_val(o->shading);
    addMethodsOption(
        k, o->methods, "BACKEND:METHOD list (BACKEND:multipass is added as the baseline)",
        "soft:multipass,soft:unified,gl:multipass,gl:kalaiah-emulation,gl:gs-layered,...");
    addCommonOptions(k, o->common, "Timed frames per method and configuration");
    return {k, [o] { return runKalaiah(*o); }};
}

}  // namespace mvr::cli::bench
