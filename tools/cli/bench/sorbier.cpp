// `mvr bench sorbier`: sorbier2008 Tables 1 and 2 — flat, vertex and pixel shading of 1, 3, 5
// and 9 bunnies in a grid, 2 views, each backend's multipass against its one-pass methods.
#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/core.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "bench/report.h"

namespace mvr::cli::bench {

namespace {

namespace fs = std::filesystem;

struct SorbierOptions {
    CommonOptions common;
    std::string model;
    std::string texturedModel;  ///< the textured row's model ("none": no textured row)
    std::vector<int> copies{1, 3, 5, 9};
    std::vector<std::string> shadings{"flat", "vertex", "pixel"};
    std::vector<std::string> sizes{"1024x768"};
    std::vector<std::string> methods{
        "soft:multipass",    "soft:unified",        "gl:multipass",      "gl:gs-mrt",
        "gl:gs-depthmap",    "gl:gs-layered",       "gl:gs-invocations", "gl:instanced-layer",
        "gl:viewport-array", "gl:kalaiah-emulation"};
};

/// The artifacts of each one-pass job for the bench's own camera: one more (untimed) frame of
/// the job and of its backend's multipass, compared per view (channels > 2/255 apart), as
/// `mvr render --check` and src/gl/README.md count them.
void fillArtifacts(const std::vector<Job>& jobs, const std::vector<Measured>& measured,
                   const Prepared& p, std::vector<RenderRow>& rows, std::size_t first) {
    // Each backend's reference frame once, for all of its one-pass jobs.
    std::map<Backend*, std::optional<RenderOutput>> references;
    for (std::size_t j = 0; j < jobs.size(); ++j) {
        if (measured[j].failed() || jobs[j].spec.method == kBaselineMethod) continue;
        Backend* reference = nullptr;
        for (const Job& k : jobs) {
            if (k.spec.backend == jobs[j].spec.backend && k.spec.method == kBaselineMethod)
                reference = k.backend;
        }
        if (!reference) continue;
        auto [ref, added] = references.try_emplace(reference);
        if (added) {
            auto r = reference->render(p.scene, p.rig, p.settings, kBaselineMethod);
            if (r) ref->second = std::move(r).value();
        }
        auto out = jobs[j].backend->render(p.scene, p.rig, p.settings, jobs[j].spec.method);
        if (!ref->second || !out) continue;
        RenderRow& row = rows[first + j];
        for (const ViewDifference& d : viewDifferences(out->color, ref->second->color)) {
            row.artifactPercent.push_back(d.percent());
            row.artifactMaxDelta = std::max(row.artifactMaxDelta, d.maxDelta);
        }
    }
}

int runSorbier(const SorbierOptions& o) {
    if (Status s = checkCommonOptions(o.common); !s) return fail(s);
    if (o.copies.empty()) return fail(usageError("--copies is empty (expected e.g. 1,3,5,9)"));
    for (const int c : o.copies) {
        if (c < 1 || c > 1024)
            return fail(
                usageError(fmt::format("--copies {} is out of range (expected 1..1024)", c)));
    }
    std::vector<std::pair<int, int>> sizes;
    for (const std::string& sz : o.sizes) {
        auto p = parseSize(sz, "--sizes");
        if (!p) return fail(p.status());
        sizes.push_back(*p);
    }
    if (sizes.empty()) return fail(usageError("--sizes is empty (expected e.g. 1024x768)"));
    std::vector<Shading> shadings;
    for (const std::string& s : o.shadings) {
        auto sh = parseShading(s);
        if (!sh) return fail(usageError("--shadings: " + sh.status().message()));
        shadings.push_back(*sh);
    }
    if (shadings.empty())
        return fail(usageError("--shadings is empty (expected flat,vertex,pixel)"));
    BackendSet backends({.threads = o.common.threads});
    std::vector<Skipped> skipped;
    auto jobsR = resolvePaperJobs(o.methods, backends, skipped);
    if (!jobsR) return fail(jobsR.status());
    const std::vector<Job> jobs = std::move(jobsR).value();
    auto model = findModel(o.model, "stanford-bunny.obj");
    if (!model) return fail(model.status());
    const std::string modelName = fs::path(*model).filename().string();
    std::optional<std::string> texturedModel;
    if (o.texturedModel != "none") {
        auto t = findModel(o.texturedModel, "spot.obj");
        if (t) {
            texturedModel = *t;
        } else if (!o.texturedModel.empty()) {
            return fail(t.status());
        } else {
            skipped.push_back({"textured row", t.status().message()});
        }
    }
    const Machine machine = describeMachine(backends);

    const int configs = int(o.copies.size()) + (texturedModel ? 1 : 0);
    Progress progress(int(sizes.size()) * configs * int(shadings.size() * jobs.size()),
                      o.common.machineReadable(), o.common.progress);
    RenderReport report;
    report.bench = "sorbier2008", report.machine = &machine, report.skipped = skipped;
    for (const Job& j : jobs) report.series.push_back(j.text());
    for (const auto& [w, h] : sizes) {
        for (const int copies : o.copies) {
            SceneOptions so;
            so.models = {*model};
            so.grid = copies;
            so.size = fmt::format("{}x{}", w, h);
            so.views = 2;
            auto prepared = so.prepare();
            if (!prepared) return fail(prepared.status());
            Prepared& p = *prepared;
            for (std::size_t si = 0; si < shadings.size(); ++si) {
                p.settings.shading = shadings[si];
                const std::string label =
                    fmt::format("{}x{} {} {} tris", w, h, o.shadings[si], p.scene.triangleCount());
                const std::vector<Measured> m =
                    measure(jobs, p, {.warmup = o.common.warmup, .frames = o.common.frames},
                            {.progress = &progress, .label = label});
                const std::size_t first = report.rows.size();
                for (std::size_t j = 0; j < jobs.size(); ++j) {
                    RenderRow r = renderRow(jobs[j], m[j], p.scene.triangleCount());
                    r.shading = shadingName(shadings[si]);
                    r.model = modelName;
                    r.copies = copies, r.views = 2, r.width = w, r.height = h;
                    r.config = "2x1";
                    report.rows.push_back(r);
                }
                fillSpeedups(report.rows, first);
                fillArtifacts(jobs, m, p, report.rows, first);
            }
        }
    }
    // The textured row (issue 14): one copy of a shared model with texture coordinates (spot),
    // a checker texture generated here (512², 16×16 squares, mipmapped, repeated), each shading.
    if (texturedModel) {
        const std::string texName = fs::path(*texturedModel).filename().string() + " (textured)";
        for (const auto& [w, h] : sizes) {
            SceneOptions so;
            so.models = {*texturedModel};
            so.size = fmt::format("{}x{}", w, h);
            so.views = 2;
            auto prepared = so.prepare();
            if (!prepared) return fail(prepared.status());
            Prepared& p = *prepared;
            p.scene.textures = {makeCheckerTexture(512, 16, {235, 225, 200, 255},
                                                   {60, 90, 150, 255}, "checker (generated)")};
            for (Instance& inst : p.scene.instances) {
                inst.material.albedo = glm::vec3(1.0f);
                inst.material.baseColorTexture = 0;
            }
            if (Status st = validateScene(p.scene); !st) return fail(st);
            for (std::size_t si = 0; si < shadings.size(); ++si) {
                p.settings.shading = shadings[si];
                const std::string label = fmt::format("{}x{} {} textured {} tris", w, h,
                                                      o.shadings[si], p.scene.triangleCount());
                const std::vector<Measured> m =
                    measure(jobs, p, {.warmup = o.common.warmup, .frames = o.common.frames},
                            {.progress = &progress, .label = label});
                const std::size_t first = report.rows.size();
                for (std::size_t j = 0; j < jobs.size(); ++j) {
                    RenderRow r = renderRow(jobs[j], m[j], p.scene.triangleCount());
                    r.shading = shadingName(shadings[si]);
                    r.model = texName;
                    r.copies = 1, r.views = 2, r.width = w, r.height = h;
                    r.config = "2x1";
                    r.textured = true;
                    report.rows.push_back(r);
                }
                fillSpeedups(report.rows, first);
                fillArtifacts(jobs, m, p, report.rows, first);
            }
        }
    }
    progress.done();

    // One table per size: a line per shading and method, a column per triangle count.
    for (const auto& [w, h] : sizes) {
        report.tables.push_back(PivotTable{
            .caption = fmt::format(
                "sorbier2008 Tables 1 and 2 — {} × 1..{} copies, {}x{}, 2 views (off-axis), {} frames after {} "
                "warm-up; cell: fps = 1000 / median wall ms [slowest–fastest frame] and speed-up over "
                "multipass of the same backend (wall, and process CPU time); wrong px: per eye, the pixels more "
                "than 2/255 off that multipass for this camera",
                modelName, o.copies.back(), w, h, o.common.frames, o.common.warmup),
            .rowHeads = {"shading", "method"},
            .filter =
                [w = w, h = h](const RenderRow& r) {
                    return r.width == w && r.height == h && !r.textured;
                },
            .rowLabels =
                [](const RenderRow& r) {
                    return std::vector<std::string>{r.shading, r.spec()};
                },
            .column = [](const RenderRow& r) { return fmt::format("{} tris", r.triangles); },
            .cell = {}});
        if (!texturedModel) continue;
        report.tables.push_back(PivotTable{
            .caption = fmt::format(
                "Textured (issue 14) — {}, one copy, a generated 512² checker texture (sRGB, "
                "mipmapped, trilinear), {}x{}, 2 views; cells as above",
                fs::path(*texturedModel).filename().string(), w, h),
            .rowHeads = {"shading", "method"},
            .filter =
                [w = w, h = h](const RenderRow& r) {
                    return r.width == w && r.height == h && r.textured;
                },
            .rowLabels =
                [](const RenderRow& r) {
                    return std::vector<std::string>{r.shading, r.spec()};
                },
            .column = [](const RenderRow& r) { return fmt::format("{} tris", r.triangles); },
            .cell = {}});
    }
    // One panel per shading, fps against triangles, one line per method (first size).
    const auto [w0, h0] = sizes[0];
    report.plot = RenderPlot{
        .title = fmt::format("sorbier2008 Tables 1-2 on this machine: {}x{}, 2 views", w0, h0),
        .xlabel = "triangles",
        .filter =
            [w0 = w0, h0 = h0](const RenderRow& r) {
                return r.width == w0 && r.height == h0 && !r.textured;
            },
        .panel = [](const RenderRow& r) { return r.shading + " shading"; },
        .x = [](const RenderRow& r) { return double(r.triangles); },
        .y = {},
        .ylabel = {}};
    return printRenderReport(report, o.common);
}

}  // namespace

PaperBench addSorbier(CLI::App* bench) {
    auto o = std::make_shared<SorbierOptions>();
    CLI::App* s = bench->add_subcommand(
        "sorbier",
        "sorbier2008 Tables 1-2: flat/vertex/pixel shading x 1,3,5,9 bunnies (70k-630k triangles), "
        "2 views, multipass vs every one-pass method: fps and speed-up");
    s->add_option("model", o->model, "Model (default: $MVR_SHARED_DIR/models/stanford-bunny.obj)");
    s->add_option("--textured-model", o->texturedModel,
                  "Model of the textured row (with texture coordinates; a checker texture is "
                  "generated), or none (default: $MVR_SHARED_DIR/models/spot.obj)");
    s->add_option("--copies", o->copies, "Copies of the model in a grid, comma separated")
        ->delimiter(',')
        ->default_str("1,3,5,9");
    s->add_option("--shadings", o->shadings, "Shading modes, comma separated")
        ->delimiter(',')
        ->default_str("flat,vertex,pixel");
    s->add_option("--sizes", o->sizes, "Image sizes WxH per view, comma separated")
        ->delimiter(',')
        ->default_str("1024x768");
    addMethodsOption(
        s, o->methods, "BACKEND:METHOD list (BACKEND:multipass is added as the baseline)",
        "soft:multipass,soft:unified,gl:multipass,gl:gs-mrt,gl:gs-depthmap,gl:gs-layered,...");
    addCommonOptions(s, o->common, "Timed frames per method and configuration");
    return {s, [o] { return runSorbier(*o); }};
}

}  // namespace mvr::cli::bench
