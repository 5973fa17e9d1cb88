// `mvr bench`: times rendering methods side by side on one scene and rig — warm-up, then F
// frames; median and min wall time per method, the per-stage breakdown where the backend
// measures it (soft), and the ratio to the first method. Text table or --json.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>
#include <ctime>

#include <fmt/core.h>
#include <unistd.h>

#include "command.h"
#include "mvr/core/platform.h"
#include "options.h"
#include "bench_papers.h"

#include "mvr/raster/soft_backend.h"
#if __has_include(<nlohmann/json.hpp>)
#include <nlohmann/json.hpp>
#define MVR_BENCH_HAVE_JSON 1
#endif

namespace mvr::cli {
namespace {

struct BenchOptions {
    SceneOptions scene;
    std::vector<std::string> methods{"soft:multipass", "soft:unified"};
    int frames = 10;
    int warmup = 2;
    bool json = false;
    int threads = 0;
    std::string simd = "auto";
};

struct BenchResult {
    std::string backend, method, ran;
    double medianMs = 0, minMs = 0;
    double cpuMs = 0;   ///< median process CPU time (all threads) per frame
    StageTimes stages;  ///< medians per stage
    bool hasStages = false;
};

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// CPU time of the whole process (every thread), ms: robust to other processes' load.
double processCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}


Result<std::unique_ptr<Backend>> makeBenchBackend(const std::string& name, const BenchOptions& o) {
    auto made = makeBackend(name, BackendOptions{.threads = o.threads, .simd = o.simd});
    if (!made && made.status().message().find("SIMD") != std::string::npos) {
        return usageError(fmt::format("--simd '{}' is not a SIMD path (expected auto, scalar, avx2 or avx512)", o.simd));
    }
    return made;
}

int runBench(const BenchOptions& o) {
    if (o.frames < 1 || o.frames > 100000) {
        return fail(usageError(fmt::format("--frames {} is out of range (expected 1..100000)", o.frames)));
    }
    if (o.warmup < 0 || o.warmup > 1000) {
        return fail(usageError(fmt::format("--warmup {} is out of range (expected 0..1000)", o.warmup)));
    }
    if (o.threads < 0 || o.threads > 1024) {
        return fail(usageError(fmt::format("--threads {} is out of range (expected 0..1024, 0 = all cores)", o.threads)));
    }
    // Parse and check every backend:method before loading anything.
    struct Job {
        std::string backend, method;
    };
    std::vector<Job> jobs;
    for (const std::string& spec : o.methods) {
        const auto colon = spec.find(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size()) {
            return fail(usageError(fmt::format("--methods entry '{}' is not of the form BACKEND:METHOD "
                                               "(e.g. soft:unified)", spec)));
        }
        jobs.push_back({spec.substr(0, colon), spec.substr(colon + 1)});
    }
    if (jobs.empty()) return fail(usageError("--methods is empty (expected e.g. soft:multipass,soft:unified)"));
    std::vector<std::unique_ptr<Backend>> backends;
    std::vector<std::string> backendNamesSeen;
    auto backendFor = [&](const std::string& name) -> Result<Backend*> {
        for (std::size_t i = 0; i < backendNamesSeen.size(); ++i) {
            if (backendNamesSeen[i] == name) return backends[i].get();
        }
        auto b = makeBenchBackend(name, o);
        if (!b) return b.status();
        backendNamesSeen.push_back(name);
        backends.push_back(std::move(b).value());
        return backends.back().get();
    };
    for (const Job& job : jobs) {
        auto b = backendFor(job.backend);
        if (!b) return fail(b.status());
        if (Status s = (*b)->supports(job.method); !s) return fail(s);
    }

    auto prepared = o.scene.prepare();
    if (!prepared) return fail(prepared.status());
    const Prepared& p = *prepared;
    const bool progress = isatty(STDERR_FILENO) && !o.json;

    // The machine line.
    std::string simdPath = "-";
    int threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    simdPath = raster::simdPathName(raster::bestSimdPath());
    if (o.simd != "auto") simdPath = o.simd;
    std::vector<std::string> backendInfo;
    for (std::size_t i = 0; i < backends.size(); ++i) {
        for (const std::string& line : backends[i]->info()) backendInfo.push_back(backendNamesSeen[i] + ": " + line);
    }

    // Frames are interleaved round-robin over the methods (after each method's warm-up), so that
    // a change in machine load affects every method alike; ratios come from the same rounds.
    struct Samples {
        std::vector<double> ms, cpu, vertex, setup, raster, fill;
    };
    std::vector<BenchResult> results(jobs.size());
    std::vector<Samples> samples(jobs.size());
    const int total = o.warmup + o.frames;
    for (int frame = 0; frame < total; ++frame) {
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            const Job& job = jobs[j];
            Backend* backend = *backendFor(job.backend);
            BenchResult& r = results[j];
            r.backend = job.backend, r.method = job.method;
            if (progress) {
                fmt::print(stderr, "\r{}:{} frame {}/{}{}   ", job.backend, job.method, frame + 1, total,
                           frame < o.warmup ? " (warm-up)" : "");
            }
            const double cpu0 = processCpuMs();
            const auto start = std::chrono::steady_clock::now();
            auto out = backend->render(p.scene, p.rig, p.settings, job.method);
            const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            const double cpu = processCpuMs() - cpu0;
            if (!out) {
                if (progress) fmt::print(stderr, "\n");
                return fail(out.status());
            }
            if (frame < o.warmup) continue;
            r.ran = out->method;
            Samples& sm = samples[j];
            sm.ms.push_back(t), sm.cpu.push_back(cpu);
            const StageTimes& st = out->stages;
            sm.vertex.push_back(st.vertexMs), sm.setup.push_back(st.setupMs),
                sm.raster.push_back(st.rasterMs), sm.fill.push_back(st.fillMs);
            r.hasStages = r.hasStages || st.vertexMs + st.setupMs + st.rasterMs + st.fillMs > 0.0;
        }
    }
    for (std::size_t j = 0; j < jobs.size(); ++j) {
        BenchResult& r = results[j];
        const Samples& sm = samples[j];
        r.medianMs = median(sm.ms);
        r.minMs = *std::min_element(sm.ms.begin(), sm.ms.end());
        r.cpuMs = median(sm.cpu);
        r.stages = {median(sm.vertex), median(sm.setup), median(sm.raster), median(sm.fill)};
    }
    if (progress) fmt::print(stderr, "\r{:60}\r", "");

    const std::size_t triangles = p.scene.triangleCount();
    const int views = p.rig.viewCount();
    const char* shading = shadingName(p.settings.shading);
    if (o.json) {
#ifdef MVR_BENCH_HAVE_JSON
        nlohmann::json j;
        j["machine"] = {{"cpu", cpuModelName()},
                        {"cores", int(std::max(1u, std::thread::hardware_concurrency()))},
                        {"simd", simdPath},
                        {"threads", threads},
                        {"backends", backendInfo}};
        j["scene"] = {{"name", p.sceneName}, {"rig", rigKindName(p.rig.kind)},
                      {"columns", p.rig.columns}, {"rows", p.rig.rows}, {"cull", p.settings.cullBackFaces},
                      {"wireframe", p.settings.wireframe}};
        j["results"] = nlohmann::json::array();
        for (const BenchResult& r : results) {
            nlohmann::json e = {{"backend", r.backend}, {"method", r.method}, {"views", views},
                                {"triangles", triangles}, {"shading", shading},
                                {"width", p.settings.width}, {"height", p.settings.height},
                                {"median_ms", r.medianMs}, {"min_ms", r.minMs}, {"frames", o.frames},
                                {"cpu_ms", r.cpuMs},
                                {"speedup_vs_first", results[0].medianMs / r.medianMs}};
            if (r.ran != r.method) e["ran"] = r.ran;
            if (r.hasStages) {
                e["stages_ms"] = {{"vertex", r.stages.vertexMs}, {"setup", r.stages.setupMs},
                                  {"raster", r.stages.rasterMs}, {"fill", r.stages.fillMs}};
            }
            j["results"].push_back(e);
        }
        fmt::print("{}\n", j.dump(2));
        return 0;
#else
        return fail(unsupportedError("--json needs nlohmann-json, which this mvr was built without"));
#endif
    }
    fmt::print("machine: {} | {} hardware threads | soft SIMD path: {} | soft worker threads: {}\n",
               cpuModelName(), std::max(1u, std::thread::hardware_concurrency()), simdPath, threads);
    for (const std::string& line : backendInfo) fmt::print("  {}\n", line);
    fmt::print("scene: {} ({} triangles) | {} rig {}x{} = {} views | {}x{} | {} shading{}{} | {} frames after {} warm-up\n",
               p.sceneName, triangles, rigKindName(p.rig.kind), p.rig.columns, p.rig.rows, views,
               p.settings.width, p.settings.height, shading, p.settings.cullBackFaces ? " | cull" : "",
               p.settings.wireframe ? " | wireframe" : "", o.frames, o.warmup);
    fmt::print("{:<24} {:>10} {:>10} {:>9} {:>10} {:>12}   {:>8} {:>8} {:>8} {:>8}\n", "backend:method",
               "median ms", "min ms", "vs first", "cpu ms", "Mtri·view/s", "vertex", "setup", "raster", "fill");
    for (const BenchResult& r : results) {
        const std::string name = r.backend + ":" + r.method + (r.ran != r.method ? " (" + r.ran + ")" : "");
        const double rate = double(triangles) * views / (r.medianMs * 1e3);
        if (r.hasStages) {
            fmt::print("{:<24} {:>10.2f} {:>10.2f} {:>8.2f}x {:>10.2f} {:>12.1f}   {:>8.2f} {:>8.2f} {:>8.2f} {:>8.2f}\n",
                       name, r.medianMs, r.minMs, results[0].medianMs / r.medianMs, r.cpuMs, rate,
                       r.stages.vertexMs, r.stages.setupMs, r.stages.rasterMs, r.stages.fillMs);
        } else {
            fmt::print("{:<24} {:>10.2f} {:>10.2f} {:>8.2f}x {:>10.2f} {:>12.1f}\n", name, r.medianMs, r.minMs,
                       results[0].medianMs / r.medianMs, r.cpuMs, rate);
        }
    }
    return 0;
}

const CommandRegistrar kBench(30, [](CLI::App& root) -> std::function<int()> {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* app = root.add_subcommand(
        "bench", "Time rendering methods side by side (warm-up, then F frames): median/min ms, per-stage "
                 "breakdown (soft), ratio to the first method; --json for machines");
    o->scene.addTo(app);
    app->add_option("--methods", o->methods, "BACKEND:METHOD list, comma separated (first = baseline)")
        ->delimiter(',')
        ->default_str("soft:multipass,soft:unified");
    app->add_option("--frames", o->frames, "Timed frames per method")->default_val(o->frames);
    app->add_option("--warmup", o->warmup, "Untimed frames before them")->default_val(o->warmup);
    app->add_option("--threads", o->threads, "soft: worker threads (0 = one per core)")->default_val(o->threads);
    app->add_option("--simd", o->simd, "soft: SIMD path auto | scalar | avx2 | avx512")->default_val(o->simd);
    app->add_flag("--json", o->json, "Print JSON: {machine, scene, results: [...]}");
    auto papers = addPaperBenches(app);  // bench sorbier | kalaiah | adelson (bench_papers.cpp)
    return [o, papers] {
        if (auto rc = papers()) return *rc;
        return runBench(*o);
    };
});

}  // namespace
}  // namespace mvr::cli
