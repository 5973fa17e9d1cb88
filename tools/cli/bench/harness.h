// tools/cli/bench/harness.h — what every `mvr bench` measurement shares: jobs (BACKEND:METHOD
// resolved through the backend registry), interleaved rounds over the jobs, statistics, the
// machine the numbers come from, progress on stderr and the options of the paper benches.
// Formatting (tables, CSV, JSON, plots) is report.h's.
//
// Why interleaved: one frame of each job per round, so that a change in machine load (other
// processes, thermal throttling) hits every job alike and ratios come from the same rounds.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mvr/backends.h"
#include "mvr/core/render.h"
#include "mvr/core/status.h"
#include "options.h"

namespace mvr::cli::bench {

/// The reference method every backend has and the paper benches compare against.
inline constexpr const char* kBaselineMethod = "multipass";

// ---- statistics -----------------------------------------------------------------------------

/// Median, extremes and quartiles of a sample (linear interpolation between ranks).
struct Stats {
    double median = 0, min = 0, max = 0, q1 = 0, q3 = 0;
    int n = 0;
};
/// The q-quantile (0..1) of an ascending sample; 0 for an empty one.
double quantile(const std::vector<double>& sorted, double q);
Stats statsOf(std::vector<double> samples);

/// CPU time of the calling thread / of the whole process (every thread), ms.
double threadCpuMs();
double processCpuMs();

// ---- jobs -----------------------------------------------------------------------------------

/// The backends a bench uses, each created once (on first use) with the bench's options.
class BackendSet {
public:
    explicit BackendSet(BackendOptions options) : mOptions(std::move(options)) {}
    /// The backend `name`. Errors: makeBackend's; a SIMD path the backend refuses names --simd.
    Result<Backend*> get(const std::string& name);

    struct Made {
        std::string name;
        bool gpu = false;  ///< the registry's BackendEntry::gpu
        std::unique_ptr<Backend> backend;
    };
    /// The backends created so far, in the order they were first asked for.
    const std::vector<Made>& made() const { return mMade; }
    const BackendOptions& options() const { return mOptions; }

private:
    BackendOptions mOptions;
    std::vector<Made> mMade;
};

/// One BACKEND:METHOD to measure.
struct Job {
    MethodSpec spec;
    Backend* backend = nullptr;
    std::string text() const { return spec.text(); }
};

/// A job that cannot run here, and why (the paper benches list these and go on).
struct Skipped {
    std::string spec, reason;
};

/// How the --methods list becomes jobs.
struct JobRules {
    /// Put BACKEND:multipass first for every backend of the list (the speed-up baseline) and
    /// measure each entry once.
    bool addBaseline = false;
    /// A backend or method that cannot run here goes into `skipped` instead of failing.
    bool skipUnavailable = false;
    /// Accept "auto" (it picks one of the others: the plain bench reports which).
    bool allowAuto = true;
};

/// Parses the --methods entries (every one BACKEND:METHOD, checked through the registry before
/// anything is created) and creates their backends in `backends`. Errors: Usage naming the
/// entry ("--methods entry 'x:y': …"); without skipUnavailable, whatever keeps a job from
/// running here (its status code: Unsupported, …).
Result<std::vector<Job>> resolveJobs(const std::vector<std::string>& entries, BackendSet& backends,
                                     const JobRules& rules,
                                     std::vector<Skipped>* skipped = nullptr);

/// The jobs of a paper bench: resolveJobs with each backend's multipass baseline first,
/// unavailable methods in `skipped`, no "auto"; Unsupported when none of them can run here.
Result<std::vector<Job>> resolvePaperJobs(const std::vector<std::string>& entries,
                                          BackendSet& backends, std::vector<Skipped>& skipped);

/// The default --methods of `mvr bench`: the first registered backend's baseline and its
/// default method ("soft:multipass,soft:unified").
std::vector<std::string> defaultMethodList();

// ---- progress -------------------------------------------------------------------------------

/// Progress on stderr: a bar when stderr is a terminal and stdout is for people, else nothing,
/// or one line per step when forced (--progress).
class Progress {
public:
    Progress(int totalSteps, bool machineReadable, bool forceLines);
    /// One step done: advances the bar or prints "[i/n] label".
    void step(const std::string& label);
    /// The bar's line shows `text` (the plain bench's per-frame status); nothing otherwise.
    void status(const std::string& text);
    /// Clears the bar; `keep`: leaves its last line (before an error message) instead.
    void done(bool keep = false);

private:
    int mTotal, mDone = 0;
    bool mBar, mLines;
};

// ---- measuring ------------------------------------------------------------------------------

/// The samples of one job over the timed rounds.
struct Measured {
    std::vector<double> wallMs;      ///< wall time of each render() call
    std::vector<double> cpuMs;       ///< process CPU time (all threads) of each call
    std::vector<RenderStats> stats;  ///< Backend::lastStats() after each call
    std::string ran;                 ///< the method that ran (differs for "auto")
    Status error;                    ///< the failed render (this job was not rendered again)
    bool failed() const { return !error; }
};

/// A GPU backend's own timings of one job (RenderStats of each timed frame): draw (first draw
/// to the finished frame), readback (handing the views back) and the GPU timer of the draws.
/// A frame's GPU timer is kept only when it is non-negative and at most that frame's draw wall
/// time (the first GL_TIME_ELAPSED on llvmpipe reads 5.9e6 ms); gpu is the median of the kept
/// samples, nullopt when none was kept. CPU backends have none of this (`measured` false).
struct DeviceTimes {
    bool measured = false;              ///< the frames ran on a GPU backend (BackendEntry::gpu)
    double drawMs = 0, readbackMs = 0;  ///< medians over the frames
    std::optional<double> gpuMs;        ///< median of the kept GPU timer samples
    int gpuFrames = 0;                  ///< frames whose GPU timer was kept
    /// Per frame, in order: draw, readback and the GPU timer (nullopt: dropped or none).
    std::vector<double> frameDrawMs, frameReadbackMs;
    std::vector<std::optional<double>> frameGpuMs;
};
/// Whether a frame's GPU timer can be right: 0 <= gpuMs <= drawWallMs.
bool validGpuSample(const RenderStats& stats);
/// The DeviceTimes of frames' stats; `gpu` false: an unmeasured one (a CPU backend's).
DeviceTimes deviceTimes(const std::vector<RenderStats>& frames, bool gpu);
/// Whether `job`'s frames ran on a GPU backend: its registry row's `gpu`, or for a backend that
/// picks another one (auto, whose RenderStats::method is "BACKEND:METHOD"), the picked one's.
bool ranOnGpu(const Job& job, const std::string& ran);
/// Frames' stats summed (one frame drawn as several renders: the shadows bench's K passes).
/// The sum's GPU timer is negative where any part's sample is not valid.
RenderStats sumStats(const std::vector<RenderStats>& parts);

struct Rounds {
    int warmup = 0;  ///< untimed rounds first
    int frames = 1;  ///< timed rounds
    /// Stop at the first failed render (the plain bench); else that job drops out and the
    /// others go on.
    bool stopAtFirstError = false;
};

/// How measure() reports progress.
struct MeasureProgress {
    Progress* progress = nullptr;
    /// Non-empty: one step "label BACKEND:METHOD" per job after the rounds (the paper benches);
    /// empty: a status line per render ("BACKEND:METHOD frame i/n").
    std::string label;
};

/// Renders the prepared request with every job, round after round (round-robin over the jobs:
/// interleaved), timing each call by wall clock and process CPU time.
std::vector<Measured> measure(std::span<const Job> jobs, const Prepared& request,
                              const Rounds& rounds, const MeasureProgress& progress = {});

/// Per-call CPU (calling thread) and wall times of a batch of calls.
struct BatchSamples {
    std::vector<double> cpuMs, wallMs;
};
/// Times `batches` rounds over `fns`, each fn called `reps` times per batch (times per call);
/// round b starts with fn b mod n, so that no fn is always first after another.
std::vector<BatchSamples> measureBatches(std::span<const std::function<void()>> fns, int batches,
                                         int reps);
/// Repetitions of `fn` that take at least `minBatchMs` (from the wall time of one call).
int repetitionsFor(const std::function<void()>& fn, double minBatchMs);

// ---- the machine ----------------------------------------------------------------------------

struct Machine {
    std::string cpu = "unknown CPU";
    int cores = 1;                         ///< hardware threads
    std::string simd = "-";                ///< the CPU backend's SIMD path
    int threads = 1;                       ///< the CPU backend's worker threads
    std::string gpuRenderer = "not used";  ///< GL_RENDERER of the GPU backend used, if any
    std::string date;                      ///< "YYYY-MM-DD HH:MM UTC"
    std::vector<std::string> backendInfo;  ///< "name: line" for each info() line of each backend
};
/// The machine, and what `backends` (those a bench created) say about themselves.
Machine describeMachine(const BackendSet& backends);

// ---- the paper benches' common options ------------------------------------------------------

struct CommonOptions {
    int frames = 5;
    int warmup = 1;
    int threads = 0;
    bool json = false;
    bool csv = false;
    bool progress = false;
    std::string plot;
    std::string saveJson;  ///< also write the JSON here (tables still on stdout)
    bool machineReadable() const { return json || csv; }
};
/// Adds --frames, --warmup, --threads, --json, --csv, --progress, --plot, --save-json.
void addCommonOptions(CLI::App* app, CommonOptions& options, const char* framesHelp);
/// Adds --methods: one comma-separated list (`--methods a,b`, or repeated `--methods a --methods
/// b`), never the words after it, so a model named next is a model, not a method.
void addMethodsOption(CLI::App* app, std::vector<std::string>& methods, const std::string& help,
                      const std::string& defaults);
/// Adds the positional models (default: the procedural scene) and --grid K.
void addModelOptions(CLI::App* app, std::vector<std::string>& models, int& grid);
/// Range checks, and that --plot can be drawn (before minutes of measuring).
Status checkCommonOptions(const CommonOptions& options);

/// `given`, or `defaultName` from the shared models folder ($MVR_SHARED_DIR/models, the build's
/// shared folder, ../shared/models, shared/models). Errors: Input naming the places.
Result<std::string> findModel(const std::string& given, const std::string& defaultName);

}  // namespace mvr::cli::bench
