// `mvr bench shadows`: kalaiah2007 §3 — "the lights are the views". The shadow maps of K lights
// (directional, spread on a cone around the zenith, each fitted to the scene: mvr/core/
// shadows.h) rendered as ONE multi-view pass whose views are the lights (an explicit view list)
// against K separate single-view passes, for every BACKEND:METHOD; table, JSON, --plot (the
// speed-up of one pass over K passes against K).
#include <chrono>
#include <cmath>
#include <filesystem>

#include <fmt/core.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "bench/report.h"
#include "mvr/core/shadows.h"

namespace mvr::cli::bench {

namespace {

struct ShadowsOptions {
    CommonOptions common;
    std::vector<std::string> models;
    int grid = 1;
    std::vector<int> lights{1, 2, 4, 8};
    int mapSize = 1024;
    std::vector<std::string> methods{"soft:unified", "gl:instanced-layer", "gl:gs-layered"};
};

/// K directional lights on a cone of 35° around +Y, evenly in azimuth; their maps' views.
std::vector<ShadowMap> lightMaps(const Scene& scene, int k, int size) {
    std::vector<ShadowMap> maps;
    const Bounds b = scene.bounds();
    for (int i = 0; i < k; ++i) {
        const float a = 6.2831853f * float(i) / float(k), t = 0.61086524f;
        Light l;
        l.towardLight = glm::normalize(
            glm::vec3(std::cos(a) * std::sin(t), std::cos(t), std::sin(a) * std::sin(t)));
        maps.push_back(makeShadowMapView(l, i, b, size));
    }
    return maps;
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

int runShadows(const ShadowsOptions& o) {
    if (Status s = checkCommonOptions(o.common); !s) return fail(s);
    if (o.grid < 1 || o.grid > 64) {
        return fail(usageError(fmt::format("--grid {} is out of range (expected 1..64)", o.grid)));
    }
    if (o.mapSize < 16 || o.mapSize > 8192) {
        return fail(usageError(
            fmt::format("--map-size {} is out of range (expected 16..8192)", o.mapSize)));
    }
    if (o.lights.empty()) return fail(usageError("--lights is empty (expected e.g. 1,2,4,8)"));
    for (int k : o.lights) {
        if (k < 1 || k > kMaxViews) {
            return fail(usageError(
                fmt::format("--lights entry {} is out of range (expected 1..{})", k, kMaxViews)));
        }
    }
    BackendSet backends({.threads = o.common.threads});
    std::vector<Skipped> skipped;
    auto jobsR =
        resolveJobs(o.methods, backends,
                    {.addBaseline = false, .skipUnavailable = true, .allowAuto = false}, &skipped);
    if (!jobsR) return fail(jobsR.status());
    const std::vector<Job> jobs = std::move(jobsR).value();
    if (jobs.empty()) return fail(unsupportedError("bench shadows: none of --methods runs here"));
    const Machine machine = describeMachine(backends);
    std::vector<std::string> models;
    for (const std::string& m : o.models) {
        std::error_code ec;
        auto path = std::filesystem::exists(m, ec) || m.find('/') != std::string::npos
                        ? Result<std::string>(m)
                        : findModel("", m);
        if (!path) return fail(path.status());
        models.push_back(*path);
    }
    SceneOptions so;
    so.models = models;
    so.grid = o.grid;
    auto prepared = so.prepare();
    if (!prepared) return fail(prepared.status());
    const Scene& scene = prepared->scene;
    const std::string model = std::filesystem::path(prepared->sceneName).filename().string();
    const RenderSettings settings = shadowPassSettings(o.mapSize);

    Progress progress(int(o.lights.size() * jobs.size()), o.common.machineReadable(),
                      o.common.progress);
    RenderReport report;
    report.bench = "shadows", report.machine = &machine, report.skipped = skipped;
    for (const Job& j : jobs) report.series.push_back(j.text());
    for (int k : o.lights) {
        const std::vector<ShadowMap> maps = lightMaps(scene, k, o.mapSize);
        Result<Rig> all = shadowRig(maps);
        if (!all) return fail(all.status());
        std::vector<Rig> single;
        for (const ShadowMap& m : maps) single.push_back(*shadowRig(std::span(&m, 1)));
        // Interleaved rounds: each job's one pass, then its K passes, job after job.
        std::vector<Measured> one(jobs.size()), many(jobs.size());
        for (int round = 0; round < o.common.warmup + o.common.frames; ++round) {
            for (std::size_t j = 0; j < jobs.size(); ++j) {
                if (one[j].failed() || many[j].failed()) continue;
                Backend& b = *jobs[j].backend;
                const std::string& method = jobs[j].spec.method;
                double c0 = processCpuMs();
                auto t0 = std::chrono::steady_clock::now();
                auto r = b.render(scene, *all, settings, method);
                const double w1 = msSince(t0), cpu1 = processCpuMs() - c0;
                if (!r) {
                    one[j].error = r.status();
                    continue;
                }
                const RenderStats stats1 = b.lastStats().value_or(RenderStats{});
                one[j].ran = stats1.method;
                // The K passes' stats (draw, readback, GPU timer) summed per frame.
                std::vector<RenderStats> parts;
                c0 = processCpuMs();
                t0 = std::chrono::steady_clock::now();
                for (const Rig& rig : single) {
                    auto s = b.render(scene, rig, settings, method);
                    if (!s) {
                        many[j].error = s.status();
                        break;
                    }
                    parts.push_back(b.lastStats().value_or(RenderStats{}));
                }
                const double wk = msSince(t0), cpuk = processCpuMs() - c0;
                many[j].ran = one[j].ran;
                if (round < o.common.warmup) continue;
                one[j].wallMs.push_back(w1), one[j].cpuMs.push_back(cpu1);
                one[j].stats.push_back(stats1);
                many[j].wallMs.push_back(wk), many[j].cpuMs.push_back(cpuk);
                many[j].stats.push_back(sumStats(parts));
            }
        }
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            progress.step(fmt::format("{} lights {}", k, jobs[j].text()));
            RenderRow a = renderRow(jobs[j], one[j], scene.triangleCount());
            RenderRow b = renderRow(jobs[j], many[j], scene.triangleCount());
            for (RenderRow* r : {&a, &b}) {
                r->shading = "depth", r->model = model, r->copies = o.grid, r->views = k;
                r->width = r->height = o.mapSize;
            }
            a.config = "one pass", b.config = "K passes";
            if (a.error.empty() && b.error.empty() && a.wall.median > 0) {
                a.speedup = b.wall.median / a.wall.median;
                a.cpuSpeedup = a.cpu.median > 0 ? b.cpu.median / a.cpu.median : 0;
            }
            report.rows.push_back(a);
            report.rows.push_back(b);
        }
    }
    progress.done();
    report.tables.push_back(PivotTable{
        .caption = fmt::format(
            "Shadow maps of K lights (kalaiah2007 §3: the lights are the views) — {} ({} "
            "copies), maps of {}x{}, {} frames after {} warm-up; one pass = one multi-view "
            "render whose views are the K lights, K passes = K single-view renders; cell: "
            "median wall ms (one pass: its speed-up over K passes); a GPU backend's K passes: "
            "their draw, readback and GPU timer summed per frame",
            model, o.grid, o.mapSize, o.mapSize, o.common.frames, o.common.warmup),
        .rowHeads = {"lights K"},
        .filter = [](const RenderRow&) { return true; },
        .rowLabels =
            [](const RenderRow& r) { return std::vector<std::string>{fmt::format("{}", r.views)}; },
        .column = [](const RenderRow& r) { return r.spec() + " " + r.config; },
        .cell = [](const RenderRow& r) -> std::string {
            if (!r.error.empty()) return "error";
            std::string cell = fmt::format("{:.1f} ms", r.wall.median);
            if (r.speedup > 0) cell += fmt::format(", {:.2f}× vs K passes", r.speedup);
            return cell;
        }});
    report.plot = RenderPlot{
        .title = fmt::format("Shadow maps of K lights: one multi-view pass vs K passes, {}x{}",
                             o.mapSize, o.mapSize),
        .xlabel = "views K",
        .filter = [](const RenderRow& r) { return r.speedup > 0; },
        .panel =
            [](const RenderRow& r) {
                return fmt::format("{} ({} triangles)", r.model, r.triangles);
            },
        .x = [](const RenderRow& r) { return double(r.views); },
        .y =
            [](const RenderRow& r) {
                return std::array<double, 3>{r.speedup, r.speedup, r.speedup};
            },
        .ylabel = "speed-up of one pass over K passes (median)"};
    return printRenderReport(report, o.common);
}

}  // namespace

PaperBench addShadows(CLI::App* bench) {
    auto o = std::make_shared<ShadowsOptions>();
    o->common.frames = 5;
    CLI::App* v = bench->add_subcommand(
        "shadows",
        "Shadow maps of K lights as one multi-view pass (the lights are the views, kalaiah2007 "
        "§3) vs K separate passes, per backend and method");
    addModelOptions(v, o->models, o->grid);
    v->add_option("--lights", o->lights, "Light counts K, comma separated")
        ->delimiter(',')
        ->default_str("1,2,4,8");
    v->add_option("--map-size", o->mapSize, "Shadow map texels per side")->default_val(o->mapSize);
    addMethodsOption(v, o->methods, "BACKEND:METHOD list",
                     "soft:unified,gl:instanced-layer,gl:gs-layered");
    addCommonOptions(v, o->common, "Timed frames per method and light count");
    return {v, [o] { return runShadows(*o); }};
}

}  // namespace mvr::cli::bench
