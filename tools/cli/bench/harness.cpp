#include "bench/harness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <set>
#include <thread>

#include <fmt/core.h>
#include <unistd.h>

#include "bench/report.h"
#include "mvr/core/platform.h"
#include "mvr/core/synthesize.h"
#include "mvr/raster/soft_backend.h"

#ifndef MVR_DEFAULT_SHARED_DIR
#define MVR_DEFAULT_SHARED_DIR ""
#endif

namespace mvr::cli::bench {

namespace fs = std::filesystem;

// ---- statistics -----------------------------------------------------------------------------

double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const double pos = q * double(sorted.size() - 1);
    const std::size_t i = std::size_t(pos);
    const double f = pos - double(i);
    return i + 1 < sorted.size() ? sorted[i] * (1 - f) + sorted[i + 1] * f : sorted[i];
}

Stats statsOf(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.n = int(v.size());
    s.median = quantile(v, 0.5), s.q1 = quantile(v, 0.25), s.q3 = quantile(v, 0.75);
    s.min = v.front(), s.max = v.back();
    return s;
}

namespace {
double clockMs(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}
}  // namespace

double threadCpuMs() { return clockMs(CLOCK_THREAD_CPUTIME_ID); }
double processCpuMs() { return clockMs(CLOCK_PROCESS_CPUTIME_ID); }

// ---- jobs -----------------------------------------------------------------------------------

Result<Backend*> BackendSet::get(const std::string& name) {
    for (const Made& m : mMade) {
        if (m.name == name) return m.backend.get();
    }
    auto entry = findBackend(name);
    if (!entry) return entry.status();
    auto made = (*entry)->make(mOptions);
    if (!made) {
        // A backend that refuses the bench's SIMD path but not the default one: name the option.
        const BackendOptions plain{.threads = mOptions.threads};
        if (made.status().code() == ErrorCode::Usage && mOptions.simd != plain.simd &&
            (*entry)->make(plain)) {
            return usageError(
                fmt::format("--simd '{}' is not a SIMD path (expected auto, scalar, "
                            "avx2 or avx512)",
                            mOptions.simd));
        }
        return made.status();
    }
    mMade.push_back({name, (*entry)->gpu, std::move(made).value()});
    return mMade.back().backend.get();
}

namespace {

Status entryError(const std::string& entry, const Status& why) {
    return Status(why.code(), fmt::format("--methods entry '{}': {}", entry, why.message()));
}

/// Checks one entry through the registry (form, backend, method); creates nothing it keeps.
Result<MethodSpec> parseEntry(const std::string& entry, const JobRules& rules) {
    const auto colon = entry.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == entry.size()) {
        return usageError(
            fmt::format("--methods entry '{}' is not of the form BACKEND:METHOD "
                        "(e.g. soft:unified)",
                        entry));
    }
    if (auto backend = findBackend(entry.substr(0, colon)); !backend) {
        return entryError(entry, backend.status());
    }
    if (!rules.allowAuto && entry.substr(colon + 1) == "auto") {
        return usageError(
            fmt::format("--methods entry '{}': 'auto' is not a method to measure (it "
                        "picks one of the others)",
                        entry));
    }
    auto spec = parseMethodSpec(entry);
    if (!spec && spec.status().code() != ErrorCode::Usage) {
        // The backend could not be created to ask it: resolveJobs() meets that again.
        return MethodSpec{entry.substr(0, colon), entry.substr(colon + 1)};
    }
    if (!spec) return Status(spec.status().code(), "--methods entry " + spec.status().message());
    return spec;
}

}  // namespace

Result<std::vector<Job>> resolveJobs(const std::vector<std::string>& entries, BackendSet& backends,
                                     const JobRules& rules, std::vector<Skipped>* skipped) {
    std::vector<MethodSpec> wanted;
    for (const std::string& entry : entries) {
        auto spec = parseEntry(entry, rules);
        if (!spec) return spec.status();
        wanted.push_back(*spec);
    }
    if (wanted.empty()) {
        return usageError("--methods is empty (expected e.g. soft:multipass,soft:unified)");
    }
    if (rules.addBaseline) {
        std::vector<MethodSpec> withBase;
        std::set<std::string> seenBackends, seenSpecs;
        for (const MethodSpec& s : wanted) {
            if (seenBackends.insert(s.backend).second) {
                withBase.push_back({s.backend, kBaselineMethod});
                seenSpecs.insert(withBase.back().text());
            }
            if (seenSpecs.insert(s.text()).second) withBase.push_back(s);
        }
        wanted = std::move(withBase);
    }
    std::vector<Job> jobs;
    for (const MethodSpec& s : wanted) {
        auto backend = backends.get(s.backend);
        if (!backend) {
            if (!rules.skipUnavailable || backend.status().code() == ErrorCode::Usage) {
                return backend.status();
            }
            if (skipped) skipped->push_back({s.text(), backend.status().message()});
            continue;
        }
        if (Status st = (*backend)->supports(s.method); !st) {
            if (!rules.skipUnavailable || st.code() == ErrorCode::Usage) return st;
            if (skipped) skipped->push_back({s.text(), st.message()});
            continue;
        }
        jobs.push_back({s, *backend});
    }
    return jobs;
}

Result<std::vector<Job>> resolvePaperJobs(const std::vector<std::string>& entries,
                                          BackendSet& backends, std::vector<Skipped>& skipped) {
    auto jobs =
        resolveJobs(entries, backends,
                    {.addBaseline = true, .skipUnavailable = true, .allowAuto = false}, &skipped);
    if (jobs && jobs->empty()) return unsupportedError("none of the --methods can run here");
    return jobs;
}

std::vector<std::string> defaultMethodList() {
    const std::span<const BackendEntry> all = backends();
    if (all.empty()) return {};
    const std::string name = all.front().name;
    std::vector<std::string> list{name + ":" + kBaselineMethod};
    if (auto backend = all.front().make({});
        backend && (*backend)->defaultMethod() != kBaselineMethod) {
        list.push_back(name + ":" + (*backend)->defaultMethod());
    }
    return list;
}

// ---- progress -------------------------------------------------------------------------------

Progress::Progress(int totalSteps, bool machineReadable, bool forceLines)
    : mTotal(std::max(totalSteps, 1)),
      mBar(!machineReadable && isatty(STDERR_FILENO)),
      mLines(forceLines && !mBar) {}

void Progress::step(const std::string& label) {
    ++mDone;
    if (mBar) {
        const int width = 30, filled = std::min(mDone, mTotal) * width / mTotal;
        fmt::print(stderr, "\r[{}{}] {}/{} {:<50.50}", std::string(filled, '#'),
                   std::string(width - filled, '.'), mDone, mTotal, label);
        std::fflush(stderr);
    } else if (mLines) {
        fmt::print(stderr, "[{}/{}] {}\n", mDone, mTotal, label);
        std::fflush(stderr);
    }
}

void Progress::status(const std::string& text) {
    if (mBar) fmt::print(stderr, "\r{}   ", text);
}

void Progress::done(bool keep) {
    if (!mBar) return;
    if (keep) {
        fmt::print(stderr, "\n");
    } else {
        fmt::print(stderr, "\r{:100}\r", "");
    }
}

// ---- measuring ------------------------------------------------------------------------------

std::vector<Measured> measure(std::span<const Job> jobs, const Prepared& p, const Rounds& rounds,
                              const MeasureProgress& progress) {
    using Clock = std::chrono::steady_clock;
    std::vector<Measured> out(jobs.size());
    // One output per job, rendered into frame after frame (Backend::renderInto): an application
    // keeps its images, so a frame's time does not include allocating them.
    std::vector<RenderOutput> images(jobs.size());
    const int total = rounds.warmup + rounds.frames;
    for (int round = 0; round < total; ++round) {
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            Measured& m = out[j];
            if (m.failed()) continue;
            if (progress.progress && progress.label.empty()) {
                progress.progress->status(fmt::format("{} frame {}/{}{}", jobs[j].text(), round + 1,
                                                      total,
                                                      round < rounds.warmup ? " (warm-up)" : ""));
            }
            const double cpu0 = processCpuMs();
            const auto t0 = Clock::now();
            // --synthesize K (views bench): the exact views' render and the warp, timed together.
            const Status r = renderSynthesizedInto(*jobs[j].backend, p.scene, p.rig, p.settings,
                                                   jobs[j].spec.method, p.synthesize, images[j]);
            const double wall =
                std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            const double cpu = processCpuMs() - cpu0;
            if (!r) {
                m.error = r;
                if (rounds.stopAtFirstError) return out;
                continue;
            }
            RenderStats stats;
            stats.method = images[j].method;
            if (auto last = jobs[j].backend->lastStats()) stats = *last;
            m.ran = stats.method;
            if (round < rounds.warmup) continue;
            m.wallMs.push_back(wall), m.cpuMs.push_back(cpu), m.stats.push_back(stats);
        }
    }
    if (progress.progress && !progress.label.empty()) {
        for (const Job& j : jobs) progress.progress->step(progress.label + " " + j.text());
    }
    return out;
}

bool validGpuSample(const RenderStats& s) { return s.gpuMs >= 0.0 && s.gpuMs <= s.drawWallMs; }

DeviceTimes deviceTimes(const std::vector<RenderStats>& frames, bool gpu) {
    DeviceTimes d;
    if (!gpu) return d;
    d.measured = true;
    std::vector<double> kept;
    for (const RenderStats& s : frames) {
        d.frameDrawMs.push_back(s.drawWallMs);
        d.frameReadbackMs.push_back(s.readbackWallMs);
        d.frameGpuMs.push_back(validGpuSample(s) ? std::optional<double>(s.gpuMs) : std::nullopt);
        if (d.frameGpuMs.back()) kept.push_back(s.gpuMs);
    }
    d.drawMs = statsOf(d.frameDrawMs).median;
    d.readbackMs = statsOf(d.frameReadbackMs).median;
    d.gpuFrames = int(kept.size());
    if (!kept.empty()) d.gpuMs = statsOf(kept).median;
    return d;
}

bool ranOnGpu(const Job& job, const std::string& ran) {
    const std::size_t colon = ran.find(':');
    const std::string name = colon != std::string::npos ? ran.substr(0, colon) : job.spec.backend;
    auto entry = findBackend(name);
    return entry && (*entry)->gpu;
}

RenderStats sumStats(const std::vector<RenderStats>& parts) {
    RenderStats sum;
    if (parts.empty()) return sum;
    sum.method = parts.front().method;
    sum.gpuMs = 0.0;
    sum.passes = 0;
    for (const RenderStats& p : parts) {
        sum.gpuMs = sum.gpuMs >= 0.0 && validGpuSample(p) ? sum.gpuMs + p.gpuMs : -1.0;
        sum.drawWallMs += p.drawWallMs, sum.readbackWallMs += p.readbackWallMs;
        sum.totalWallMs += p.totalWallMs, sum.passes += p.passes;
        sum.stages.vertexMs += p.stages.vertexMs, sum.stages.setupMs += p.stages.setupMs;
        sum.stages.rasterMs += p.stages.rasterMs, sum.stages.fillMs += p.stages.fillMs;
    }
    return sum;
}

std::vector<BatchSamples> measureBatches(std::span<const std::function<void()>> fns, int batches,
                                         int reps) {
    using Clock = std::chrono::steady_clock;
    std::vector<BatchSamples> out(fns.size());
    for (int b = 0; b < batches; ++b) {
        for (std::size_t k = 0; k < fns.size(); ++k) {
            const std::size_t which = (std::size_t(b) + k) % fns.size();
            // Thread CPU time: the functions are single-threaded, so time spent descheduled by
            // other processes does not count; wall time next to it.
            const double c0 = threadCpuMs();
            const auto s0 = Clock::now();
            for (int r = 0; r < reps; ++r) fns[which]();
            const double wall =
                std::chrono::duration<double, std::milli>(Clock::now() - s0).count();
            out[which].cpuMs.push_back((threadCpuMs() - c0) / reps);
            out[which].wallMs.push_back(wall / reps);
        }
    }
    return out;
}

int repetitionsFor(const std::function<void()>& fn, double minBatchMs) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    fn();
    const double once = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return once > 0 ? std::clamp(int(std::ceil(minBatchMs / once)), 1, 1000000) : 1;
}

// ---- the machine ----------------------------------------------------------------------------

Machine describeMachine(const BackendSet& backends) {
    Machine m;
    m.cpu = cpuModelName();
    m.cores = int(std::max(1u, std::thread::hardware_concurrency()));
    m.threads = backends.options().threads > 0 ? backends.options().threads : m.cores;
    m.simd = backends.options().simd != BackendOptions{}.simd
                 ? backends.options().simd
                 : raster::simdPathName(raster::bestSimdPath());
    bool sawGpu = false;
    for (const BackendSet::Made& b : backends.made()) {
        const std::vector<std::string> info = b.backend->info();
        for (const std::string& line : info) m.backendInfo.push_back(b.name + ": " + line);
        // The first GPU backend names the renderer (not auto, which may render on one).
        if (!b.gpu || sawGpu || b.name == kAutoBackend) continue;
        sawGpu = true;
        m.gpuRenderer = "none";
        if (Status s = b.backend->supports(kBaselineMethod); !s)
            m.gpuRenderer = "none (" + s.message() + ")";
        for (const std::string& line : info) {
            if (line.rfind("GL_RENDERER: ", 0) == 0) m.gpuRenderer = line.substr(13);
        }
    }
    const std::time_t now = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    m.date = buf;
    return m;
}

// ---- the paper benches' common options ------------------------------------------------------

void addMethodsOption(CLI::App* app, std::vector<std::string>& methods, const std::string& help,
                      const std::string& defaults) {
    app->add_option("--methods", methods, help)
        ->delimiter(',')
        ->allow_extra_args(false)
        ->default_str(defaults);
}

void addModelOptions(CLI::App* app, std::vector<std::string>& models, int& grid) {
    app->add_option("models", models, "Models (default: the procedural scene)");
    app->add_option("--grid", grid, "Lay out K copies of the model(s) in a grid")
        ->default_val(grid);
}

void addCommonOptions(CLI::App* app, CommonOptions& o, const char* framesHelp) {
    app->add_option("--frames", o.frames, framesHelp)->default_val(o.frames);
    app->add_option("--warmup", o.warmup, "Untimed runs of each method before timing")
        ->default_val(o.warmup);
    app->add_option("--threads", o.threads, "soft: worker threads (0 = one per core)")
        ->default_val(o.threads);
    auto* json = app->add_flag("--json", o.json, "Print JSON instead of tables");
    app->add_flag("--csv", o.csv, "Print CSV (one row per measurement) instead of tables")
        ->excludes(json);
    app->add_flag("--progress", o.progress,
                  "Progress lines on stderr even when it is not a terminal");
    app->add_option("--plot", o.plot, "Also draw FILE.png or FILE.svg with gnuplot");
    app->add_option("--save-json", o.saveJson, "Also write the JSON to FILE");
}

Status checkCommonOptions(const CommonOptions& o) {
    if (o.frames < 1 || o.frames > 100000) {
        return usageError(
            fmt::format("--frames {} is out of range (expected 1..100000)", o.frames));
    }
    if (o.warmup < 0 || o.warmup > 1000) {
        return usageError(fmt::format("--warmup {} is out of range (expected 0..1000)", o.warmup));
    }
    if (o.threads < 0 || o.threads > 1024) {
        return usageError(fmt::format(
            "--threads {} is out of range (expected 0..1024, 0 = all cores)", o.threads));
    }
    if (!o.plot.empty()) return checkPlotTarget(o.plot);
    return {};
}

Result<std::string> findModel(const std::string& given, const std::string& defaultName) {
    if (!given.empty()) return given;
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("MVR_SHARED_DIR"); env && *env) {
        candidates.push_back(fs::path(env) / "models" / defaultName);
    }
    if (*MVR_DEFAULT_SHARED_DIR)
        candidates.push_back(fs::path(MVR_DEFAULT_SHARED_DIR) / "models" / defaultName);
    candidates.push_back(fs::path("../shared/models") / defaultName);
    candidates.push_back(fs::path("shared/models") / defaultName);
    for (const fs::path& c : candidates) {
        std::error_code ec;
        if (fs::is_regular_file(c, ec)) return c.string();
    }
    return inputError(
        fmt::format("no model given and {} not found (expected a MODEL argument, or "
                    "$MVR_SHARED_DIR/models/{} or ../shared/models/{})",
                    defaultName, defaultName, defaultName));
}

}  // namespace mvr::cli::bench
